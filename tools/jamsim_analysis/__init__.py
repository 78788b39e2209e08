"""Analysis of jamsim archives: load campaigns into pandas, honest error bars, the analyses
of the thesis (scaling collapse, Newtonian and Bagnold divergences, finite-size scaling of
jamming, velocity correlations, steady averages compared between models or archives,
configuration pictures, psi6 and animations of configuration frames) and one report per
archive.

    import jamsim_analysis as ja     # installed (tools/README.md), or run from tools/
    run = ja.open_archives("out/quickstart.h5")
    run.replicas                     # one row per replica (pandas)
    table = ja.replica_averages(run, ["pressure"])
    groups = ja.group_averages(table, ["pressure"])
    fit = ja.fit_collapse(ja.collapse_points(groups, "pressure"))
    cmp = ja.compare_averages(groups, ["pressure"])   # models at the state points they share
    ds = ja.replica_dataset(run, ["pressure"])    # xarray over (N, phi, rate, seed)

Every raw read of an HDF5 file happens in archive.py; everything else takes DataFrames and
numpy arrays.
"""
import importlib

# Where each public name lives. They are imported on first use (PEP 562 __getattr__), not by
# `import jamsim_analysis`: the modules import pandas, scipy, h5py and matplotlib (over a
# second), which the commands' --help and argument errors do not need.
_NAMES = {
    "errors": ("AnalysisError",),
    "archive": ("open_archives", "Archive", "FinalConfiguration"),
    "stats": ("autocorrelation", "integrated_autocorrelation_time", "blocking_error", "mean_with_error", "jackknife",
              "steady_window", "replica_averages", "group_averages"),
    "scaling": ("fit_collapse", "collapse_points", "bootstrap_collapse", "compare_collapses"),
    "rheology": ("fit_divergence", "newtonian_divergence", "bagnold_analysis", "local_slopes"),
    "jamming": ("jamming_probability", "phi_j_samples", "finite_size_scaling"),
    "correlations": ("correlation_minima", "fit_minimum_growth"),
    "comparison": ("compare_averages",),
    "pictures": ("contact_network", "rattlers", "animate_frames"),
    "order": ("psi6", "psi6_over_strain"),
    "tables": ("to_dataset", "replica_dataset", "group_dataset", "means_table", "write_means_csv"),
}
_WHERE = {name: module for module, names in _NAMES.items() for name in names}

# The names above and their modules (as when they were imported eagerly).
__all__ = sorted(set(_WHERE) | set(_NAMES))


def __getattr__(name):
    """A public name or module, imported on first use."""
    if name in _NAMES:
        return importlib.import_module(f".{name}", __name__)  # the import binds it here too
    if name in _WHERE:
        value = getattr(importlib.import_module(f".{_WHERE[name]}", __name__), name)
        globals()[name] = value  # later uses find it without this function
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
