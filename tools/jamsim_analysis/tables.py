"""Data out: the package's tables as an xarray Dataset over the sweep's grid, and a flat CSV of
the per-replica means for spreadsheets and other languages.

    run = ja.open_archives("out/quickstart.h5")
    ds = ja.replica_dataset(run, ["pressure", "shear_stress"])   # dims (N, phi, rate, seed)
    ds["pressure"].sel(N=1024, rate=1e-4).mean("seed")
    gs = ja.group_dataset(ja.group_averages(ja.replica_averages(run, ["pressure"]), ["pressure"]),
                          ["pressure"])                          # dims (N, phi, rate)
    ja.write_means_csv(ja.replica_averages(run, ["pressure"]), "means.csv", ["pressure"])

A Dataset needs a grid: every combination of the sweep's N, phi, rate and seed is one replica
(finished or not; cells of replicas that are not done or were left out hold NaN and say why
in `left_out`). A sweep with `points` off the grid is refused (use the DataFrame or the CSV).
A dimension the campaign's model does not read (rate for the minimisation protocols, NaN in
the table) is left out. Coordinates are float64 (phi, rate) and int64 (N, seed).
"""
import os

import numpy as np
import pandas as pd

from . import stats
from .command_support import write_beside
from .errors import AnalysisError

GRID = ("N", "phi", "rate", "seed")
INTEGER = ("N", "seed")
# Columns of the per-replica CSV, in this order, before the observables (those present).
CSV_KEYS = ("replica", "campaign", "model", "N", "phi", "rate", "seed", "status_name", "left_out",
            "window_start", "samples", "drift_z", "drift_limit")


def _one_model(table, model):
    if model is not None:
        table = table[table["model"] == model]
        if table.empty:
            raise AnalysisError(f"no replica of model {model}")
    models = sorted(set(table["model"])) if "model" in table else []
    if len(models) > 1:
        raise AnalysisError(f"replicas of models {', '.join(models)}: a Dataset holds one model (model=...)")
    return table, (models[0] if models else "")


def to_dataset(table, dims=GRID, model=None):
    """A table with one row per grid cell (replica_averages, Archive.replicas, group_averages)
    as an xarray Dataset over `dims`; every other column is a data variable. Dimensions whose
    column is NaN throughout are dropped. Raises AnalysisError when the rows are not a full
    grid over `dims` or two rows share a cell."""
    import xarray as xr  # Debian: python3-xarray

    table, the_model = _one_model(table, model)
    if table.empty:
        raise AnalysisError("no replica to put in a Dataset")
    missing = [d for d in dims if d not in table and d != "rate"]
    if missing:
        raise AnalysisError(f"the table has no column {', '.join(missing)}")
    dims = [d for d in dims if d in table and not table[d].isna().all()]
    partial = [d for d in dims if table[d].isna().any()]
    if partial:
        raise AnalysisError(f"column {', '.join(partial)} is NaN for some replicas only: not a grid")
    table = table.copy()
    for d in dims:
        table[d] = table[d].astype("int64" if d in INTEGER else "float64")
    cells = table[dims].drop_duplicates()
    if len(cells) != len(table):
        first = table[table.duplicated(dims, keep=False)].iloc[0]
        same = table[(table[dims] == first[dims]).all(axis=1)]
        raise AnalysisError("two replicas share " + ", ".join(f"{d} = {first[d]}" for d in dims) +
                            " (rows " + ", ".join(str(r) for r in same.index[:4]) + ")")
    shape = [table[d].nunique() for d in dims]
    if int(np.prod(shape)) != len(table):
        raise AnalysisError(f"the sweep is not a grid: {len(table)} replicas over " +
                            " x ".join(f"{n} {d}" for n, d in zip(shape, dims)) +
                            f" = {int(np.prod(shape))} cells (a sweep with points off the grid): "
                            "use the DataFrame or the CSV")
    drop = [c for c in ("file", "source", "row", "model", "campaign") if c in table]
    campaign = table["campaign"].iloc[0] if "campaign" in table else ""
    ds = table.drop(columns=drop).set_index(dims).sort_index().to_xarray()
    ds.attrs.update(model=the_model, campaign=str(campaign),
                    description="jamsim: one cell per " + ", ".join(dims))
    return ds


def replica_dataset(archive, observables=("pressure", "shear_stress"), model=None, **averages):
    """Per-replica steady means (stats.replica_averages: `<obs>`, `<obs>_error`, `<obs>_tau`,
    `<obs>_dof`, window, drift, `left_out`, and every parameter) of an Archive as a Dataset over
    (N, phi, rate, seed)."""
    return to_dataset(stats.replica_averages(archive, list(observables), **averages), GRID, model)


def group_dataset(groups, observables=None, model=None):
    """Averages over seeds (stats.group_averages) as a Dataset over (N, phi, rate)."""
    del observables  # every column of the table becomes a variable
    return to_dataset(groups, GRID[:3], model)


def means_table(table, observables):
    """The per-replica table in the CSV's column order: keys, then `<obs>`, `<obs>_error`,
    `<obs>_tau`, `<obs>_dof` for each observable."""
    cols = [c for c in CSV_KEYS if c in table]
    for o in observables:
        cols += [c for c in (o, f"{o}_error", f"{o}_tau", f"{o}_dof") if c in table]
    out = table[cols].copy()
    for c in INTEGER + ("replica", "samples"):
        if c in out and out[c].notna().all():
            out[c] = out[c].astype("int64")
    return out


def write_means_csv(table, path, observables):
    """Write means_table(table) as comma-separated values with a header line, numbers in their
    shortest text that reads back as the same double, NaN as an empty field. The file is
    written under a temporary name and renamed; an existing `path` is refused."""
    if os.path.exists(path):
        raise AnalysisError(f"'{path}' exists: choose another output (nothing is overwritten)")
    directory = os.path.dirname(path) or "."
    if not os.path.isdir(directory):
        raise AnalysisError(f"'{path}': the directory '{directory}' does not exist")
    out = means_table(table, observables)
    write_beside(path, lambda tmp: out.to_csv(tmp, index=False, na_rep=""))
    return out
