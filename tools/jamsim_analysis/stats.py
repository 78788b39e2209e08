"""Statistics of time series: autocorrelation, error bars of correlated means (integrated
autocorrelation time, blocking, jackknife), steady-state windows, and the averages per
replica and per (model, N, phi, rate).

Convention: for n samples of a stationary series with variance s^2 and normalised
autocorrelation rho(t), the integrated autocorrelation time (in samples) is
    tau_int = 1/2 + sum_{t>=1} rho(t),
so that var(mean) = 2 tau_int s^2 / n. An AR(1) series x_t = a x_{t-1} + noise has
rho(t) = a^t and tau_int = (1 + a) / (2 (1 - a)).
"""
import dataclasses

import numpy as np
import pandas as pd
from scipy import stats as sps

from .errors import AnalysisError

# Sokal's window: sum rho(t) up to the first W with W >= WINDOW_FACTOR * tau_int(W).
WINDOW_FACTOR = 5.0
# Fewest samples in a steady window for an error estimate.
MIN_SAMPLES = 16
# A replica drifts when the means of the first and last thirds of its window differ by more
# than this many combined standard errors.
DRIFT_Z = 3.5
# Independent samples (n / 2 tau_int) a third of the window needs for the drift test.
MIN_INDEPENDENT = 3


def autocorrelation(x):
    """Normalised autocorrelation rho(t), t = 0..n-1, of a 1-D series (FFT, the biased
    estimator sum_{i} dx_i dx_{i+t} / sum_i dx_i^2)."""
    x = np.asarray(x, float)
    n = len(x)
    dx = x - x.mean()
    size = 1 << (2 * n - 1).bit_length()
    spectrum = np.fft.rfft(dx, size)
    acov = np.fft.irfft(spectrum * np.conj(spectrum), size)[:n]
    if acov[0] <= 0:
        return np.r_[1.0, np.zeros(n - 1)]
    return acov / acov[0]


def integrated_autocorrelation_time(x, window_factor=WINDOW_FACTOR):
    """(tau_int in samples, window W) by Sokal's automatic window."""
    rho = autocorrelation(x)
    tau = 0.5 + np.cumsum(rho[1:])  # tau[W-1] = 1/2 + sum_{t=1..W} rho(t)
    windows = np.arange(1, len(rho))
    ok = windows >= window_factor * tau
    if not ok.any():
        return float(max(tau[-1], 0.5)) if len(tau) else 0.5, len(rho) - 1
    w = int(np.argmax(ok))
    return float(max(tau[w], 0.5)), int(windows[w])


def blocking_levels(x):
    """Flyvbjerg-Petersen blocking: [(block size, blocks, standard error of the mean,
    its uncertainty)] as the series is halved until fewer than 4 blocks remain."""
    x = np.asarray(x, float)
    levels, size = [], 1
    while len(x) >= 4:
        n = len(x)
        se = np.std(x, ddof=1) / np.sqrt(n)
        levels.append((size, n, se, se / np.sqrt(2.0 * (n - 1))))
        x = 0.5 * (x[: n // 2 * 2 : 2] + x[1 : n // 2 * 2 : 2])
        size *= 2
    return levels


def blocking_error(x):
    """(standard error of the mean, block size) by blocking, with the optimal block of Lee,
    Needs and Drummond (2011): the smallest B with B^3 > 2 n (se_B / se_1)^4. When no level
    qualifies, the largest block with at least 4 blocks is used."""
    levels = blocking_levels(x)
    if not levels:
        return float("nan"), 0
    n, se1 = levels[0][1], levels[0][2]
    for size, _, se, _ in levels:
        if se1 == 0 or size ** 3 > 2 * n * (se / se1) ** 4:
            return float(se), size
    return float(levels[-1][2]), levels[-1][0]


def jackknife(x, func, n_blocks=20):
    """Jackknife over contiguous blocks: (estimate, error) of func(mean over rows) for a
    series x [n] or [n, k]; func takes the mean vector (or scalar). The estimate is
    bias-corrected: n_b f(all) - (n_b - 1) mean(f(leave one out))."""
    x = np.asarray(x, float)
    n = len(x) // n_blocks * n_blocks
    if n_blocks < 2 or n == 0:
        raise AnalysisError(f"jackknife needs at least {n_blocks} samples (has {len(x)})")
    blocks = x[:n].reshape((n_blocks, n // n_blocks) + x.shape[1:]).mean(axis=1)
    total = blocks.sum(axis=0)
    full = func(total / n_blocks)
    leave_out = np.array([func((total - b) / (n_blocks - 1)) for b in blocks])
    estimate = n_blocks * full - (n_blocks - 1) * leave_out.mean(axis=0)
    error = np.sqrt((n_blocks - 1) / n_blocks * np.sum((leave_out - leave_out.mean(axis=0)) ** 2, axis=0))
    return estimate, error


@dataclasses.dataclass
class MeanEstimate:
    """Mean of a correlated series. error = sqrt(2 tau_int var / n); blocking_error and
    block_size from blocking; tau_int in samples; n_effective = n / (2 tau_int)."""
    mean: float
    error: float
    tau_int: float
    n: int
    blocking_error: float
    block_size: int

    @property
    def n_effective(self):
        return self.n / (2 * self.tau_int)


def mean_with_error(x):
    """MeanEstimate of a 1-D series (error NaN below 2 samples)."""
    x = np.asarray(x, float)
    n = len(x)
    if n == 0:
        raise AnalysisError("mean of an empty series")
    if n < 2:
        return MeanEstimate(float(x[0]), float("nan"), 0.5, 1, float("nan"), 0)
    tau, _ = integrated_autocorrelation_time(x)
    error = float(np.sqrt(np.var(x, ddof=1) * 2 * tau / n))
    block_err, block = blocking_error(x)
    return MeanEstimate(float(x.mean()), error, tau, n, block_err, block)


@dataclasses.dataclass
class SteadyWindow:
    """The steady part of a series: samples [start, n). start_time: its strain (or time);
    drift_z: |mean(first third) - mean(last third)| / combined error (see _drift_z; NaN when
    the window is too short for the test); drifting: drift_z above the threshold."""
    start: int
    start_time: float
    drift_z: float
    drifting: bool


def _drift_z(values):
    """|mean(first third) - mean(last third)| in standard errors, NaN when a third holds
    fewer than MIN_INDEPENDENT independent samples (too short to tell drift from slow
    fluctuations). Under the hypothesis of a stationary window both thirds share the
    variance and tau_int of the second half (a transient left in the first third would
    inflate its own estimate and hide itself)."""
    third = len(values) // 3
    if third < 4:
        return float("nan")
    half = values[len(values) // 2:]
    tau, _ = integrated_autocorrelation_time(half)
    if third < 2 * tau * MIN_INDEPENDENT:
        return float("nan")
    err = np.sqrt(2.0 * np.var(half, ddof=1) * 2 * tau / third)
    diff = abs(np.mean(values[:third]) - np.mean(values[-third:]))
    return float(diff / err) if err > 0 else (0.0 if diff == 0 else np.inf)


def mser_truncation(values, batch=5):
    """MSER-5 (White 1997): the number of leading samples to drop, d = 5 k with k
    minimising the squared standard error sum_{i>k} (b_i - mean)^2 / (m - k)^2 of the batch
    means b (batches of 5), searched over the first half."""
    m = len(values) // batch
    if m < 4:
        return 0
    b = np.asarray(values[: m * batch], float).reshape(m, batch).mean(axis=1)
    scores = [np.var(b[k:]) / (m - k) for k in range(m // 2 + 1)]  # var/(m-k) = sum/(m-k)^2
    return int(np.argmin(scores)) * batch


def steady_window(times, values, transient=0.0, z_max=DRIFT_Z):
    """Steady window of a series: from the first sample with times >= transient (the declared
    transient), a further MSER-5 truncation (the start that minimises the standard error of
    the remaining mean: the transient's bias against the noise); then the first and last
    thirds of the window are compared, and more than z_max standard errors apart flags the
    replica as drifting (the observable has not settled)."""
    times, values = np.asarray(times, float), np.asarray(values, float)
    first = int(np.searchsorted(times, transient, side="left")) if len(times) else 0
    first = min(first, len(values))
    start = first + mser_truncation(values[first:])
    z = _drift_z(values[start:])
    t0 = float(times[start]) if start < len(times) else float("nan")
    return SteadyWindow(start, t0, z, bool(z > z_max))


KEYS = ("model", "N", "phi", "rate")
# Columns >= 0 by construction (repulsive contacts, counts, squares, fractions): a negative
# sample is no physics but a damaged archive.
NONNEGATIVE = frozenset(("energy_per_particle", "pressure", "contact_number", "nonaffine_velocity_sq",
                         "dissipated_power", "kinetic_energy_per_particle", "pressure_kinetic", "packing_fraction",
                         "contact_number_nonrattler", "rattler_fraction", "solver_iterations"))


def replica_averages(archive, observables, time_column="strain", drift_observable=None, detect=True):
    """Per finished replica: the steady window and the mean, error and tau_int of each
    observable over it. Returns a DataFrame with the replica's parameters, `<obs>`,
    `<obs>_error`, `<obs>_tau` (samples), `window_start` (strain, or time for a dynamics
    replica at rate 0, whose `time` column is set), `samples`,
    `drift_z`, `drifting` and `left_out` (a reason, or "" for replicas kept). Replicas not
    done appear with left_out = their status."""
    table = archive.replicas
    drift_observable = drift_observable or observables[0]
    columns = set(archive.observables())
    rows = []
    for _, rep in table.iterrows():
        row = {k: rep[k] for k in table.columns if k not in ("file",)}
        row["left_out"] = ""
        if rep["status"] != 2:
            row["left_out"] = f"status {rep['status_name']}" + (
                f" ({rep['failure_reason']})" if rep.get("failure_reason") else "")
            rows.append(row)
            continue
        r = int(rep["replica"])
        # A dynamics replica at rate 0 runs in time (its `time` parameter set): its transient
        # is a time, its strain 0.
        in_time = float(rep.get("rate", np.nan)) == 0.0 and float(rep.get("time", np.nan)) > 0
        column = "time" if time_column == "strain" and in_time else time_column
        times = archive.series(r, column) if column in columns else None
        series = {o: archive.series(r, o) for o in observables}
        n = len(series[drift_observable])
        if times is None or not np.all(np.isfinite(times[:n])):
            times = np.arange(n, dtype=float)
            transient = 0.0
        else:
            if np.any(np.diff(times[:n]) < 0):
                k = int(np.flatnonzero(np.diff(times[:n]) < 0)[0])
                raise AnalysisError(f"'{rep['file']}' is damaged: replica {r}'s {column} decreases at "
                                    f"sample {k + 1} ({times[k]:.6g} -> {times[k + 1]:.6g}); it never "
                                    "decreases in a run")
            transient = rep.get("transient", 0.0)
            transient = 0.0 if not np.isfinite(transient) else float(transient)
        first = int(np.searchsorted(times[:n], transient, side="left"))
        negative = [o for o in observables if o in NONNEGATIVE and np.any(series[o][:n] < 0)]
        if negative:  # no run writes these below 0: a damaged or hand-edited archive
            k = int(np.flatnonzero(series[negative[0]][:n] < 0)[0])
            row.update(window_start=np.nan, samples=0, drift_z=np.nan, drifting=False,
                       left_out=f"{negative[0]} < 0 at sample {k} ({series[negative[0]][k]:.6g}), which jamsim "
                                "never writes (damaged or edited?)")
            rows.append(row)
            continue
        bad = [o for o in observables if not np.all(np.isfinite(series[o][first:n]))]
        if bad:  # a blown-up replica: no window, no mean (and no numpy warnings on inf)
            k = int(np.flatnonzero(~np.isfinite(series[bad[0]][first:n]))[0]) + first
            row.update(window_start=np.nan, samples=0, drift_z=np.nan, drifting=False,
                       left_out=f"{bad[0]} not finite after the transient (sample {k}: {series[bad[0]][k]})")
            rows.append(row)
            continue
        if detect and n >= MIN_SAMPLES:
            window = steady_window(times, series[drift_observable], transient)
        else:
            start = int(np.searchsorted(times, transient)) if n > 1 else 0
            window = SteadyWindow(start, float(times[start]) if start < n else np.nan, 0.0, False)
        row.update(window_start=window.start_time, samples=n - window.start, drift_z=window.drift_z,
                   drifting=window.drifting)
        if n - window.start <= 0:
            row["left_out"] = "empty steady window"
        for o in observables:
            v = series[o][window.start:]
            if len(v) == 0 or not np.all(np.isfinite(v)):
                row["left_out"] = row["left_out"] or f"{o} not finite in the window"
                continue
            est = mean_with_error(v)
            row.update({o: est.mean, f"{o}_error": est.error, f"{o}_tau": est.tau_int})
        if window.drifting and not row["left_out"]:
            row["left_out"] = f"{drift_observable} drifts (first/last third differ by {window.drift_z:.1f} sigma)"
        rows.append(row)
    return pd.DataFrame(rows)


# Two-sided coverage of a 1-sigma interval of a normal variable: erf(1/sqrt 2).
ONE_SIGMA = 0.6826894921370859


def seed_average(means, time_errors):
    """Mean over seeds of replica means and its 1-sigma error (random-effects combination).

    Replica i has mean m_i with time error e_i (autocorrelation-aware, stats.mean_with_error);
    m_i = mu + b_i + noise, b_i a seed-to-seed offset of variance tau^2. The seed-to-seed
    variance is estimated by moments, tau^2 = max(0, s^2 - mean(e_i^2)) (s^2: variance of the
    m_i; DerSimonian-Laird with equal weights), and
        error^2 = sum(e_i^2) / k^2 + t^2 tau^2 / k,
    t = the (1 + ONE_SIGMA)/2 quantile of Student's t with k - 1 degrees of freedom (1.84 for
    2 seeds, 1.20 for 4, 1.03 for 16), so the interval keeps its 68% coverage when the offsets
    dominate and tau^2 rests on few seeds. The error is never smaller than the time errors
    alone support (tau^2 >= 0). Seeds without a time error count as all spread (tau^2 = s^2).
    Returns (mean, error, error_time, error_seeds): error_time = sqrt(sum e_i^2)/k (NaN
    without time errors), error_seeds = s/sqrt(k) (NaN for one seed)."""
    m = np.asarray(means, float)
    e = np.asarray(time_errors, float)
    k = len(m)
    finite = np.isfinite(e)
    error_time = float(np.sqrt(np.sum(e[finite] ** 2)) / k) if finite.all() else float("nan")
    if k < 2:
        return float(m.mean()), error_time, error_time, float("nan")
    s2 = float(np.var(m, ddof=1))
    within = float(np.mean(e[finite] ** 2)) if finite.all() else 0.0
    tau2 = max(0.0, s2 - within)
    t = float(sps.t.ppf(0.5 + ONE_SIGMA / 2, k - 1))
    base = error_time ** 2 if np.isfinite(error_time) else 0.0
    return float(m.mean()), float(np.sqrt(base + t * t * tau2 / k)), error_time, float(np.sqrt(s2 / k))


def one_seed_note(groups):
    """A note on the state points of group_averages' table that hold one seed ("" when none):
    their error is that seed's time error, which misses the spread between seeds and comes out
    small on windows of few independent samples (samples / 2 tau_int)."""
    one = int((groups["seeds"] == 1).sum()) if "seeds" in groups else 0
    if not one:
        return ""
    return (f"note: {one} of {len(groups)} state points have one seed: their error is that seed's time error, "
            "which misses the spread between seeds and comes out small on windows of few independent samples "
            "(samples / 2 tau); run two or more seeds for error bars")


def group_averages(replica_table, observables, keys=KEYS):
    """Averages over seeds per `keys` of the kept replicas (left_out == ""). For each
    observable (see seed_average): `<obs>` (mean of replica means), `<obs>_error` (its
    1-sigma error: the time errors combined with the spread between seeds, never below the
    time errors), `<obs>_error_time` (the time errors alone: sqrt(sum e_i^2)/n),
    `<obs>_error_seeds` (the plain standard error over seeds, NaN for one seed),
    `<obs>_error_fit` (the fits' weights: the seed-to-seed variance pooled over each model
    and N, pooled_errors) and `seeds`."""
    kept = replica_table[replica_table["left_out"] == ""] if "left_out" in replica_table else replica_table
    if kept.empty:
        raise AnalysisError("no finished replica left to average")
    keys = [k for k in keys if k in kept.columns]
    rows = []
    for key, part in kept.groupby(keys, dropna=False, sort=True):
        row = dict(zip(keys, key if isinstance(key, tuple) else (key,)))
        row["seeds"] = len(part)
        for o in observables:
            v = part[o].to_numpy(float)
            e = part[f"{o}_error"].to_numpy(float) if f"{o}_error" in part else np.full(len(v), np.nan)
            row[o], row[f"{o}_error"], row[f"{o}_error_time"], row[f"{o}_error_seeds"] = seed_average(v, e)
        rows.append(row)
    out = pd.DataFrame(rows)
    for o in observables:
        out[f"{o}_error_fit"] = pooled_errors(out, o, [k for k in POOL_KEYS if k in keys])
    return out


# The groups that share one seed-to-seed variance ratio (pooled_errors).
POOL_KEYS = ("model", "N")


def pooled_errors(groups, observable, pool_keys=POOL_KEYS):
    """Fit weights of the seed averages: the seed-to-seed variance pooled over the groups
    that share `pool_keys` (each model and N of an archive), as one ratio to the time error.

    With k_j seeds in group j, s_j^2 the variance of its replica means and w_j = k_j
    error_time_j^2 their mean squared time error, the replicas' variance is taken as
    w_j (1 + r): r = tau_j^2 / w_j, one ratio for every group of the pool. Its REML (and
    moments) estimate is 1 + r = sum_j (k_j - 1) s_j^2 / w_j / nu, nu = sum_j (k_j - 1);
    then error_fit_j^2 = error_time_j^2 (1 + t^2 max(0, r)), t the (1 + ONE_SIGMA)/2
    Student-t quantile with nu dof. The ratio rests on nu degrees of freedom (20 for 20
    points of 2 seeds) instead of k_j - 1 per point, so a fit does not favour points whose
    spread came out small by chance. Never below error_time. Groups with one seed or
    without a time error keep `<obs>_error`; so does a pool with no spread to estimate."""
    err = groups[f"{observable}_error"].to_numpy(float).copy()
    e_time = groups[f"{observable}_error_time"].to_numpy(float)
    e_seeds = groups[f"{observable}_error_seeds"].to_numpy(float)
    k = groups["seeds"].to_numpy(float)
    usable = (k >= 2) & np.isfinite(e_time) & (e_time > 0) & np.isfinite(e_seeds)
    labels = (groups[list(pool_keys)].astype(str).agg("|".join, axis=1).to_numpy()
              if pool_keys else np.zeros(len(groups), dtype=str))
    for label in np.unique(labels[usable]):
        sel = usable & (labels == label)
        nu = float(np.sum(k[sel] - 1))
        ratio = float(np.sum((k[sel] - 1) * (e_seeds[sel] / e_time[sel]) ** 2) / nu)  # s^2/w = (1 + r)
        t = float(sps.t.ppf(0.5 + ONE_SIGMA / 2, nu))
        err[sel] = e_time[sel] * np.sqrt(1 + t * t * max(0.0, ratio - 1))
    return err


def residual_scale(chi2, dof):
    """The factor of a weighted least-squares covariance (J^T W J)^-1 of a fit to seed
    averages: t^2 chi2/dof, t the (1 + ONE_SIGMA)/2 Student-t quantile with the fit's dof
    (1.20 for 3 dof, 1.04 for 14). The weights' common scale is taken from the residuals, as
    in a regression with unknown variance, so a 1-sigma interval covers 68% when the weights
    are right up to one factor; and a fit with chi2/dof > 1 (a model or weights at odds with
    the data) gets its errors inflated by sqrt(chi2/dof). (The rule sqrt(max(1, chi2/dof))
    covers 73% with right weights and 3 dof.) 1 without dof."""
    if dof <= 0 or not np.isfinite(chi2):
        return 1.0
    t = float(sps.t.ppf(0.5 + ONE_SIGMA / 2, dof))
    return t * t * chi2 / dof


def fit_errors(groups, observable):
    """The errors that weight a fit: `<obs>_error_fit` (pooled_errors) where the table has
    it, else `<obs>_error`."""
    col = f"{observable}_error_fit"
    return groups[col] if col in groups else groups[f"{observable}_error"]
