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
# Two-sided coverage of a 1-sigma interval of a normal variable: erf(1/sqrt 2).
ONE_SIGMA = 0.6826894921370859
# Fewest samples in a steady window for an error estimate.
MIN_SAMPLES = 16
# A replica drifts when the means of the first and last thirds of its window differ by more
# than this many combined standard errors (the limit for errors known exactly; for errors
# estimated with few dof, Student's t quantile of the same tail probability, drift_limit).
DRIFT_Z = 3.5
# MSER searches the first quarter of the window for the start (the rest is never cut).
MSER_SEARCH = 0.25
# Independent samples (n / 2 tau_int) a third of the window needs for the drift test.
MIN_INDEPENDENT = 3


def _lag_sums(dx):
    """sum_i dx_i dx_{i+t}, t = 0..n-1, of a 1-D series (FFT, zero-padded: no wrap-around)."""
    n = len(dx)
    size = 1 << (2 * n - 1).bit_length()
    spectrum = np.fft.rfft(dx, size)
    return np.fft.irfft(spectrum * np.conj(spectrum), size)[:n]


def autocorrelation(x):
    """Normalised autocorrelation rho(t), t = 0..n-1, of a 1-D series (FFT, the biased
    estimator sum_{i} dx_i dx_{i+t} / sum_i dx_i^2)."""
    x = np.asarray(x, float)
    n = len(x)
    acov = _lag_sums(x - x.mean())
    if acov[0] <= 0:
        return np.r_[1.0, np.zeros(n - 1)]
    return acov / acov[0]


def _mean_variance_by_window(x, window_factor, trend=False):
    """(tau_int, window W, variance s^2) of a series, corrected for the sample mean (with
    trend, for the least-squares straight line instead: the drift test's errors).

    With the sample mean subtracted, each lag's autocovariance estimate is low by about
    var(mean) = S/n, where S = s^2 + 2 sum_{t>=1} C(t) = 2 tau_int s^2: the windowed sum
    S_W = C(0) + 2 sum_{t=1..W} C(t) is low by (2W + 1) S / n, and C(0) by S / n. On the
    short windows of a campaign (n / 2 tau_int of 10 to 30) that bias made tau_int, and with
    it the error of the mean, 30-40% too small: the mean lay outside its 1-sigma interval in
    43% of stationary AR(1) series of 121 samples at tau_int = 4.5, where 31.7% is right. So
    S = S_W / (1 - p (2W + 1)/n) and s^2 = C(0) + p S / n, p the parameters fitted (1, or 2
    with trend: the slope's error takes about as much again), and Sokal's window is the first
    W with W >= window_factor * tau_int(W), searched below n/(2p + 2) (a correction of at
    most 2 for the mean, 3 for a line); without one, the largest W there is used. S is at least n C(0)/(n - p), so
    tau_int >= 1/2 (no anticorrelation)."""
    n = len(x)
    fitted = 2 if trend else 1
    if trend:
        t = np.arange(n, dtype=float)
        dx = x - np.polyval(np.polyfit(t, x, 1), t)
    else:
        dx = x - x.mean()
    acov = _lag_sums(dx) / n
    if acov[0] <= 0:
        return 0.5, 0, 0.0
    last = (n - 1) // (2 * fitted + 2)
    if last < 1:  # too few samples for a lag: taken as uncorrelated
        return 0.5, 0, float(np.sum(dx * dx) / max(n - fitted, 1))
    windows = np.arange(1, last + 1)
    partial = acov[0] + 2 * np.cumsum(acov[1 : last + 1])
    total = np.maximum(partial / (1.0 - fitted * (2 * windows + 1) / n), acov[0] * n / (n - fitted))
    variance = acov[0] + fitted * total / n
    tau = total / (2 * variance)
    ok = windows >= window_factor * tau
    w = int(np.argmax(ok)) if ok.any() else len(windows) - 1
    return float(tau[w]), int(windows[w]), float(variance[w])


def integrated_autocorrelation_time(x, window_factor=WINDOW_FACTOR):
    """(tau_int in samples, window W) by Sokal's automatic window, corrected for the sample
    mean (_mean_variance_by_window)."""
    x = np.asarray(x, float)
    if len(x) < 2:
        return 0.5, 0
    tau, w, _ = _mean_variance_by_window(x, window_factor)
    return tau, w


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
    block_size from blocking; tau_int in samples; n_effective = n / (2 tau_int); dof: the
    degrees of freedom of error^2 as an estimate (error_dof)."""
    mean: float
    error: float
    tau_int: float
    n: int
    blocking_error: float
    block_size: int
    dof: float = float("inf")

    @property
    def n_effective(self):
        return self.n / (2 * self.tau_int)


def error_dof(n, window):
    """Degrees of freedom of a windowed estimate of var(mean): n / (2W + 1) (Bartlett: the
    relative variance of a sum of 2W + 1 autocovariances over n samples is 2 (2W + 1) / n).
    A mean over n_effective = 13 independent samples has W about 20 and so 3 dof: its error
    is uncertain by about 80% in variance, and a 1-sigma interval needs Student's t factor
    (one_sigma_factor) to cover the truth 68% of the time."""
    return float(n) / (2 * window + 1) if window > 0 else float(max(n - 1, 1))


def one_sigma_factor(dof):
    """Student's t quantile at (1 + ONE_SIGMA)/2 for dof degrees of freedom (1 for infinite
    dof; 1.84 for 1, 1.20 for 3, 1.03 for 16): error * factor covers the truth 68.27% of the
    time when error^2 is an estimate with that many dof."""
    dof = np.asarray(dof, float)
    factor = np.where(np.isfinite(dof), sps.t.ppf(0.5 + ONE_SIGMA / 2, np.where(np.isfinite(dof), dof, 1.0)), 1.0)
    return float(factor) if factor.ndim == 0 else factor


def mean_with_error(x):
    """MeanEstimate of a 1-D series (error NaN below 2 samples)."""
    x = np.asarray(x, float)
    n = len(x)
    if n == 0:
        raise AnalysisError("mean of an empty series")
    if n < 2:
        return MeanEstimate(float(x[0]), float("nan"), 0.5, 1, float("nan"), 0, float("nan"))
    tau, window, variance = _mean_variance_by_window(x, WINDOW_FACTOR)
    error = float(np.sqrt(variance * 2 * tau / n))
    block_err, block = blocking_error(x)
    return MeanEstimate(float(x.mean()), error, tau, n, block_err, block, error_dof(n, window))


@dataclasses.dataclass
class SteadyWindow:
    """The steady part of a series: samples [start, n). start_time: its strain (or time);
    drift_z: |mean(first third) - mean(last third)| / combined error (see _drift_z; NaN when
    the window is too short for the test); drift_limit: the z above which it drifts (DRIFT_Z
    for the dof of that error, drift_limit); drifting: drift_z above drift_limit."""
    start: int
    start_time: float
    drift_z: float
    drifting: bool
    drift_limit: float = DRIFT_Z


def drift_limit(dof, z_max=DRIFT_Z):
    """The |z| above which a window drifts: Student's t quantile with `dof` degrees of freedom
    at the normal tail probability of z_max (3.5: 4.7e-4 two-sided). The combined error rests
    on the second half's variance and tau_int, estimated with few dof on short windows; with
    the normal limit (and the error from the half's own mean, MSER over the first half), 1%
    of stationary AR(1) windows of 121 samples at tau_int = 4.5 were flagged, 20 times the
    nominal rate. Now 0.15% (and 0.55% at tau_int = 19.5), while a ramp across a window of
    1000 samples that moves the mean by 3 of the series' standard deviations is flagged in
    72% of them (48% for 2)."""
    if not np.isfinite(dof):
        return float(z_max)
    return float(sps.t.ppf(sps.norm.cdf(z_max), dof))


def _drift_z(values):
    """(|mean(first third) - mean(last third)| in standard errors, the dof of that error):
    z NaN when a third holds fewer than MIN_INDEPENDENT independent samples (too short to
    tell drift from slow fluctuations). Under the hypothesis of a stationary window both
    thirds share the variance and tau_int of the second half about its least-squares line
    (a transient left in the first third, or a drift through the whole window, would
    inflate them and hide itself: about the half's own mean, a ramp across 1000 samples of 2
    standard deviations was flagged in a fifth of the windows, about its line in half)."""
    third = len(values) // 3
    if third < 4:
        return float("nan"), float("inf")
    half = np.asarray(values[len(values) // 2:], float)
    tau, window, variance = _mean_variance_by_window(half, WINDOW_FACTOR, trend=True)
    if third < 2 * tau * MIN_INDEPENDENT:
        return float("nan"), float("inf")
    err = np.sqrt(2.0 * variance * 2 * tau / third)
    diff = abs(np.mean(values[:third]) - np.mean(values[-third:]))
    z = float(diff / err) if err > 0 else (0.0 if diff == 0 else np.inf)
    return z, error_dof(len(half), window)


def mser_truncation(values, batch=5, search=MSER_SEARCH):
    """MSER-5 (White 1997): the number of leading samples to drop, d = 5 k with k
    minimising the squared standard error sum_{i>k} (b_i - mean)^2 / (m - k)^2 of the batch
    means b (batches of 5), searched over the first `search` fraction of the batches. Any
    cut chosen from the data favours a window that looks steady: searched over the first
    half, it cut stationary AR(1) windows of 121 samples at tau_int = 4.5 in 40% of them,
    and their 1-sigma intervals (with the t factor) then covered the truth 63% of the time;
    over the first quarter, 68%, while transients shorter than that are still cut."""
    m = len(values) // batch
    if m < 4:
        return 0
    b = np.asarray(values[: m * batch], float).reshape(m, batch).mean(axis=1)
    scores = [np.var(b[k:]) / (m - k) for k in range(int(m * search) + 1)]  # var/(m-k) = sum/(m-k)^2
    return int(np.argmin(scores)) * batch


def steady_window(times, values, transient=0.0, z_max=DRIFT_Z):
    """Steady window of a series: from the first sample with times >= transient (the declared
    transient), a further MSER-5 truncation (the start that minimises the standard error of
    the remaining mean: the transient's bias against the noise); then the first and last
    thirds of the window are compared, and more than drift_limit standard errors apart flags
    the replica as drifting (the observable has not settled)."""
    times, values = np.asarray(times, float), np.asarray(values, float)
    first = int(np.searchsorted(times, transient, side="left")) if len(times) else 0
    first = min(first, len(values))
    start = first + mser_truncation(values[first:])
    z, dof = _drift_z(values[start:])
    limit = drift_limit(dof, z_max) if np.isfinite(z) else float("nan")  # no test, no limit
    t0 = float(times[start]) if start < len(times) else float("nan")
    return SteadyWindow(start, t0, z, bool(z > limit), limit)


KEYS = ("model", "N", "phi", "rate")
# Columns >= 0 by construction (repulsive contacts, counts, squares, fractions): a negative
# sample is no physics but a damaged archive.
NONNEGATIVE = frozenset(("energy_per_particle", "pressure", "contact_number", "nonaffine_velocity_sq",
                         "dissipated_power", "kinetic_energy_per_particle", "pressure_kinetic", "packing_fraction",
                         "contact_number_nonrattler", "rattler_fraction", "solver_iterations"))


def replica_averages(archive, observables, time_column="strain", drift_observable=None, detect=True):
    """Per finished replica: the steady window and the mean, error and tau_int of each
    observable over it. Returns a DataFrame with the replica's parameters, `<obs>`,
    `<obs>_error`, `<obs>_tau` (samples), `<obs>_dof` (the error's dof, error_dof), `window_start` (strain, or time for a dynamics
    replica at rate 0, whose `time` column is set), `samples`,
    `drift_z`, `drift_limit`, `drifting` and `left_out` (a reason, or "" for replicas kept). Replicas not
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
        else:  # no drift test: NaN, not a z of 0 that would read as steady
            start = int(np.searchsorted(times, transient)) if n > 1 else 0
            window = SteadyWindow(start, float(times[start]) if start < n else np.nan, np.nan, False, np.nan)
        row.update(window_start=window.start_time, samples=n - window.start, drift_z=window.drift_z,
                   drift_limit=window.drift_limit, drifting=window.drifting)
        if n - window.start <= 0:
            row["left_out"] = "empty steady window"
        for o in observables:
            v = series[o][window.start:]
            if len(v) == 0 or not np.all(np.isfinite(v)):
                row["left_out"] = row["left_out"] or f"{o} not finite in the window"
                continue
            est = mean_with_error(v)
            row.update({o: est.mean, f"{o}_error": est.error, f"{o}_tau": est.tau_int, f"{o}_dof": est.dof})
        if window.drifting and not row["left_out"]:
            row["left_out"] = (f"{drift_observable} drifts (first/last third differ by {window.drift_z:.1f} sigma; "
                               f"the limit for its error's dof is {window.drift_limit:.1f})")
        rows.append(row)
    return pd.DataFrame(rows)


def time_error_dof(time_errors, time_dofs):
    """Satterthwaite's dof of sum(e_i^2), each e_i^2 estimated with nu_i dof:
    (sum e_i^2)^2 / sum(e_i^4 / nu_i); infinite without dofs or errors."""
    if time_dofs is None:
        return float("inf")
    e = np.asarray(time_errors, float)
    nu = np.asarray(time_dofs, float)
    if not (np.all(np.isfinite(e)) and np.any(e > 0)):
        return float("inf")
    pooled = float(np.sum(e ** 4 / np.where(np.isfinite(nu) & (nu > 0), nu, np.inf)))
    return float(np.sum(e ** 2) ** 2 / pooled) if pooled > 0 else float("inf")


def seed_average(means, time_errors, time_dofs=None):
    """Mean over seeds of replica means and its 1-sigma error (random-effects combination).

    Replica i has mean m_i with time error e_i (autocorrelation-aware, stats.mean_with_error)
    estimated with nu_i dof (time_dofs; infinite when not given); m_i = mu + b_i + noise, b_i
    a seed-to-seed offset of variance tau^2. The seed-to-seed variance is estimated by
    moments, tau^2 = max(0, s^2 - mean(e_i^2)) (s^2: variance of the m_i; DerSimonian-Laird
    with equal weights), and
        error^2 = sum(e_i^2) / k^2 + t^2 tau^2 / k  (k >= 2),   error = t_w e_1  (k = 1),
    t = the (1 + ONE_SIGMA)/2 quantile of Student's t with k - 1 degrees of freedom (1.84 for
    2 seeds, 1.20 for 4, 1.03 for 16), so the interval keeps its 68% coverage when the offsets
    dominate and tau^2 rests on few seeds; t_w the same quantile for the dof of the time
    error (time_error_dof), so one seed's interval keeps it on a short window (13
    independent samples: about 3 dof, t_w = 1.2). From two seeds on the spread between them
    is measured and t_w is not applied: with it, two seeds of such windows covered 82%. The error is never smaller than the time errors alone support (tau^2 >= 0).
    Seeds without a time error count as all spread (tau^2 = s^2). Returns (mean, error,
    error_time, error_seeds): error_time = sqrt(sum e_i^2)/k (NaN without time errors),
    error_seeds = s/sqrt(k) (NaN for one seed)."""
    m = np.asarray(means, float)
    e = np.asarray(time_errors, float)
    k = len(m)
    finite = np.isfinite(e)
    error_time = float(np.sqrt(np.sum(e[finite] ** 2)) / k) if finite.all() else float("nan")
    if k < 2:
        t_within = one_sigma_factor(time_error_dof(e, time_dofs))
        return float(m.mean()), error_time * t_within, error_time, float("nan")
    base = error_time ** 2 if np.isfinite(error_time) else 0.0
    s2 = float(np.var(m, ddof=1))
    within = float(np.mean(e[finite] ** 2)) if finite.all() else 0.0
    tau2 = max(0.0, s2 - within)
    t = one_sigma_factor(k - 1)
    return float(m.mean()), float(np.sqrt(base + t * t * tau2 / k)), error_time, float(np.sqrt(s2 / k))


def one_seed_note(groups):
    """A note on the state points of group_averages' table that hold one seed ("" when none):
    their error is that seed's time error (widened for its dof), which misses the spread
    between seeds."""
    one = int((groups["seeds"] == 1).sum()) if "seeds" in groups else 0
    if not one:
        return ""
    return (f"note: {one} of {len(groups)} state points have one seed: their error is that seed's time error "
            "(times Student's t for its dof), which misses the spread between seeds (the offsets of their starts); "
            "run two or more seeds for error bars that hold it")


# A drift test whose limit lies above this (its error rests on fewer than about 7 dof) can
# tell only large drifts.
WEAK_DRIFT_LIMIT = 6.0


def weak_drift_note(replica_table):
    """A note on the kept replicas whose window is too short for the drift test to tell a
    leftover transient from slow fluctuations ("" when none): drift_z NaN (a window below
    MIN_SAMPLES, or a third of it holding fewer than MIN_INDEPENDENT independent samples) or
    a limit above WEAK_DRIFT_LIMIT."""
    if "drift_limit" not in replica_table:
        return ""
    kept = replica_table[replica_table["left_out"] == ""] if "left_out" in replica_table else replica_table
    weak = kept["drift_z"].isna() | (kept["drift_limit"] > WEAK_DRIFT_LIMIT)
    if not weak.any():
        return ""
    return (f"note: {int(weak.sum())} of {len(kept)} replicas kept have windows too short for the drift test to tell "
            f"a transient left in them from slow fluctuations (drift_z empty, or drift_limit above {WEAK_DRIFT_LIMIT:g}: "
            "their thirds hold few independent samples); a longer run, or a look at their series, settles it")


def group_averages(replica_table, observables, keys=KEYS):
    """Averages over seeds per `keys` of the kept replicas (left_out == ""). For each
    observable (see seed_average): `<obs>` (mean of replica means), `<obs>_error` (its
    1-sigma error: the time errors combined with the spread between seeds, never below the
    time errors), `<obs>_error_time` (the time errors alone: sqrt(sum e_i^2)/n),
    `<obs>_error_seeds` (the plain standard error over seeds, NaN for one seed),
    `<obs>_error_dof` (the dof of `_error_time`, time_error_dof),
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
            nu = part[f"{o}_dof"].to_numpy(float) if f"{o}_dof" in part else None
            row[o], row[f"{o}_error"], row[f"{o}_error_time"], row[f"{o}_error_seeds"] = seed_average(v, e, nu)
            row[f"{o}_error_dof"] = time_error_dof(e, nu)
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
        t = one_sigma_factor(nu)
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
    t = one_sigma_factor(dof)
    return t * t * chi2 / dof


def fit_errors(groups, observable):
    """The errors that weight a fit: `<obs>_error_fit` (pooled_errors) where the table has
    it, else `<obs>_error`."""
    col = f"{observable}_error_fit"
    return groups[col] if col in groups else groups[f"{observable}_error"]
