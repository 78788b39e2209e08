"""Velocity correlations g_y(x) (thesis eq. 4.23, Fig. 4.8): the position x_min of the
minimum of g_y (the size of the vortex-like structures), its seed average per rate and its
growth as the rate falls, x_min = A rate^-a."""
import dataclasses

import numpy as np
import pandas as pd

from .errors import AnalysisError


def minimum_position(x, g):
    """x of the minimum of g (x in d_s, bins of constant width): the vertex of the parabola
    through the lowest bin and its neighbours (the lowest bin itself at an end)."""
    x, g = np.asarray(x, float), np.asarray(g, float)
    if len(x) < 3:
        return float("nan")
    i = int(np.argmin(g))
    if i == 0 or i == len(g) - 1:
        return float(x[i])
    h = x[i + 1] - x[i]
    curvature = g[i - 1] - 2 * g[i] + g[i + 1]
    if curvature <= 0:
        return float(x[i])
    return float(x[i] + 0.5 * h * (g[i - 1] - g[i + 1]) / curvature)


def correlation_minima(archive, replica_table=None):
    """Per finished replica with g_y: x_min; then per (model, N, phi, rate) the mean over
    seeds with its standard error (NaN with one seed). Returns (per-replica DataFrame,
    per-group DataFrame with columns model, N, phi, rate, x_min, x_min_error, seeds)."""
    table = archive.done() if replica_table is None else replica_table
    if "left_out" in table:
        table = table[table["left_out"] == ""]
    rows = []
    for _, rep in table.iterrows():
        x, g = archive.correlation(int(rep["replica"]))
        if len(x) < 3:
            continue
        rows.append(dict(replica=rep["replica"], model=rep["model"], N=rep["N"], phi=rep["phi"],
                         rate=rep["rate"], x_min=minimum_position(x, g)))
    per_replica = pd.DataFrame(rows)
    if per_replica.empty:
        raise AnalysisError("no finished replica has a velocity correlation g_y(x)")
    grouped = []
    for key, part in per_replica.groupby(["model", "N", "phi", "rate"], sort=True):
        v = part["x_min"].to_numpy(float)
        grouped.append(dict(zip(("model", "N", "phi", "rate"), key), x_min=v.mean(),
                            x_min_error=v.std(ddof=1) / np.sqrt(len(v)) if len(v) > 1 else np.nan,
                            seeds=len(v)))
    return per_replica, pd.DataFrame(grouped)


def mean_curves(archive, replicas):
    """Seed-averaged g_y over `replicas` (same N and bins): (x [B], mean [B], error [B])."""
    curves = [archive.correlation(int(r)) for r in replicas]
    curves = [c for c in curves if len(c[0])]
    if not curves:
        return np.empty(0), np.empty(0), np.empty(0)
    b = min(len(c[0]) for c in curves)
    g = np.array([c[1][:b] for c in curves])
    err = g.std(axis=0, ddof=1) / np.sqrt(len(g)) if len(g) > 1 else np.full(b, np.nan)
    return curves[0][0][:b], g.mean(axis=0), err


@dataclasses.dataclass
class GrowthFit:
    """x_min = A rate^-a: a and A with errors (scaled by sqrt(max(1, chi2/dof))), chi2, dof."""
    a: float
    a_error: float
    A: float
    A_error: float
    chi2: float
    dof: int


def fit_minimum_growth(rate, x_min, error):
    """Weighted least squares of ln x_min = ln A - a ln rate."""
    rate, x_min, error = (np.asarray(v, float) for v in (rate, x_min, error))
    keep = np.isfinite(x_min) & np.isfinite(error) & (error > 0) & (x_min > 0)
    rate, x_min, error = rate[keep], x_min[keep], error[keep]
    if len(np.unique(rate)) < 3:
        raise AnalysisError(f"the growth of x_min needs at least 3 rates with 2 or more seeds; "
                            f"the data have {len(np.unique(rate))}")
    y, sy = np.log(x_min), error / x_min
    design = np.column_stack([np.ones_like(rate), -np.log(rate)]) / sy[:, None]
    coef, *_ = np.linalg.lstsq(design, y / sy, rcond=None)
    chi2 = float(np.sum((design @ coef - y / sy) ** 2))
    dof = len(y) - 2
    cov = np.linalg.inv(design.T @ design) * (max(1.0, chi2 / dof) if dof > 0 else 1.0)
    A = float(np.exp(coef[0]))
    return GrowthFit(float(coef[1]), float(np.sqrt(cov[1, 1])), A, A * float(np.sqrt(cov[0, 0])), chi2, dof)
