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
from .errors import AnalysisError
from .archive import open_archives, Archive, FinalConfiguration
from .stats import (autocorrelation, integrated_autocorrelation_time, blocking_error,
                    mean_with_error, jackknife, steady_window, replica_averages, group_averages)
from .scaling import fit_collapse, collapse_points, bootstrap_collapse, compare_collapses
from .rheology import fit_divergence, newtonian_divergence, bagnold_analysis, local_slopes
from .jamming import jamming_probability, phi_j_samples, finite_size_scaling
from .correlations import correlation_minima, fit_minimum_growth
from .comparison import compare_averages
from .pictures import contact_network, rattlers, animate_frames
from . import order
from .order import psi6, psi6_over_strain
from .tables import to_dataset, replica_dataset, group_dataset, means_table, write_means_csv

__all__ = [name for name in dir() if not name.startswith("_")]
