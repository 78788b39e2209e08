"""Statistics against series with a known autocorrelation: AR(1), x_t = a x_{t-1} + e_t,
has rho(t) = a^t, tau_int = (1 + a)/(2(1 - a)) and, for n samples of variance s^2,
var(mean) = (s^2/n) [1 + 2 sum_{t=1}^{n-1} (1 - t/n) a^t] exactly."""
import numpy as np
import pytest

import jamsim_analysis as ja
from jamsim_analysis import stats


def ar1(a, n, rng, mean=0.0, burn=200):
    e = rng.normal(size=n + burn)
    x = np.empty(n + burn)
    x[0] = e[0] / np.sqrt(1 - a * a)
    for t in range(1, n + burn):
        x[t] = a * x[t - 1] + e[t]
    return mean + x[burn:] * np.sqrt(1 - a * a)  # unit variance


def exact_var_of_mean(a, n):
    t = np.arange(1, n)
    return (1 + 2 * np.sum((1 - t / n) * a ** t)) / n


def test_autocorrelation_equals_direct_sum():
    x = np.array([0.3, -1.2, 2.0, 0.7, 0.1, -0.4, 1.5])
    dx = x - x.mean()
    direct = np.array([np.sum(dx[: len(x) - t] * dx[t:]) for t in range(len(x))]) / np.sum(dx * dx)
    assert np.allclose(ja.autocorrelation(x), direct, atol=1e-12)


@pytest.mark.parametrize("a", [0.0, 0.5, 0.8])
def test_tau_int_of_ar1(a):
    """Sokal's estimate agrees with (1+a)/(2(1-a)) within 3 of its own statistical error
    sqrt(2(2W+1)/n) tau, for 4 independent series."""
    truth = (1 + a) / (2 * (1 - a))
    n = 20000
    for seed in range(4):
        tau, w = ja.integrated_autocorrelation_time(ar1(a, n, np.random.default_rng(seed)))
        sigma = np.sqrt(2 * (2 * w + 1) / n) * truth
        assert abs(tau - truth) <= 3 * sigma, (a, seed, tau, truth, sigma)


@pytest.mark.parametrize("n,a", [(121, 0.8), (400, 0.95), (60, 0.5)])
def test_error_of_a_short_window_covers_the_mean_with_its_dof(n, a):
    """4000 stationary AR(1) windows of 13, 10 and 20 independent samples: the interval
    mean +- error * one_sigma_factor(dof) covers the true mean (0) 68.27% of the time, within
    4 binomial standard deviations (0.029) below and 0.06 above (the dof n / (2W + 1), from
    Bartlett's variance of the window's sum, are a little low for these windows: 71-72.5%).
    The error before its correction for the sample mean, with a normal interval, covered
    56-60%; corrected, 64-65%."""
    from jamsim_analysis import coverage
    series = coverage.ar1(np.random.default_rng(int(n + 100 * a)), 4000, n, a)
    covered = [abs(e.mean) <= e.error * stats.one_sigma_factor(e.dof) for e in map(ja.mean_with_error, series)]
    rate = float(np.mean(covered))
    assert stats.ONE_SIGMA - 4 * np.sqrt(stats.ONE_SIGMA * (1 - stats.ONE_SIGMA) / 4000) <= rate, rate
    assert rate <= stats.ONE_SIGMA + 0.06, rate


@pytest.mark.parametrize("a", [0.0, 0.7, 0.9])
def test_error_of_mean_matches_exact_variance(a):
    """Over 300 independent series of n = 2000: (1) the scatter of the means agrees with the
    exact var(mean) (chi-squared with 299 dof: ratio within 1 +- 4 sqrt(2/299)); (2) the mean
    squared reported error (tau_int and blocking) agrees with the exact variance within a
    tolerance of 15% (the estimators' own bias for tau_int << n is a few percent, their
    scatter over 300 series below 2%)."""
    rng = np.random.default_rng(42)
    n, m = 2000, 300
    exact = exact_var_of_mean(a, n)
    series = [ar1(a, n, rng) for _ in range(m)]
    estimates = [ja.mean_with_error(x) for x in series]
    means = np.array([e.mean for e in estimates])
    ratio = np.var(means, ddof=1) / exact
    assert abs(ratio - 1) <= 4 * np.sqrt(2 / (m - 1)), ratio
    for name in ("error", "blocking_error"):
        mean_sq = np.mean([getattr(e, name) ** 2 for e in estimates])
        assert abs(mean_sq / exact - 1) <= 0.15, (name, mean_sq / exact)


def test_jackknife_of_mean_is_block_standard_error_and_nonlinear_function_matches_delta_method():
    rng = np.random.default_rng(7)
    x = ar1(0.6, 4000, rng, mean=3.0)
    blocks = x.reshape(20, 200).mean(axis=1)
    value, error = ja.jackknife(x, lambda m: m, n_blocks=20)
    assert np.isclose(value, x.mean()) and np.isclose(error, blocks.std(ddof=1) / np.sqrt(20))
    # f = mean^2: error = 2 |mean| error(mean) (delta method), to first order in error/mean
    value, error = ja.jackknife(x, lambda m: m * m, n_blocks=20)
    delta = 2 * abs(x.mean()) * blocks.std(ddof=1) / np.sqrt(20)
    assert abs(error / delta - 1) < 0.05 and abs(value - x.mean() ** 2) < 3 * delta


def test_steady_window_keeps_stationary_series():
    """30 stationary AR(1) series: the drift test (|z| > 3.5 on errors estimated from the same
    series) flags at most 3 (expected: about 1 with the estimators' scatter)."""
    rng = np.random.default_rng(3)
    flagged = sum(stats.steady_window(np.arange(600.0), ar1(0.8, 600, rng)).drifting for _ in range(30))
    assert flagged <= 3, flagged


def test_drift_test_of_short_stationary_windows_alarms_at_its_level():
    """2000 stationary AR(1) windows of 121 samples at tau_int = 4.5 (13 independent samples):
    the drift test's tail probability is that of 3.5 sigma, 4.7e-4; its error, from 3 or so
    dof, makes it 0.15% measured over other series (3 expected here; 9 or more has a Poisson
    probability of 0.4%). With the normal limit on that error, and MSER searching the first
    half, 20 of them (1%) were flagged."""
    from jamsim_analysis import coverage
    series = coverage.ar1(np.random.default_rng(21), 2000, 121, 0.8)
    t = np.arange(121.0)
    flagged = sum(stats.steady_window(t, x).drifting for x in series)
    assert flagged <= 8, flagged


def test_drift_test_finds_a_ramp():
    """1000 AR(1) windows of 1000 samples at tau_int = 4.5 with a ramp that moves the mean by
    3 of the series' standard deviations from start to end (the thirds' means 2 apart, about
    9 standard errors): at least 60% are flagged (72% measured, binomial sd 1.4%). With the
    error from the second half about its own mean the ramp inflated it and hid itself
    (about a fifth flagged)."""
    from jamsim_analysis import coverage
    series = coverage.ar1(np.random.default_rng(24), 1000, 1000, 0.8) + 3 * np.arange(1000) / 1000
    t = np.arange(1000.0)
    flagged = np.mean([stats.steady_window(t, x).drifting for x in series])
    assert flagged >= 0.6, flagged


def test_steady_window_flags_drift_and_drops_a_late_transient():
    rng = np.random.default_rng(5)
    t = np.arange(1000.0)
    noise = ar1(0.5, 1000, rng)
    sigma_mean = np.sqrt(exact_var_of_mean(0.5, 333))
    drift = noise + 20 * sigma_mean * t / t[-1]  # the thirds differ by ~13 sigma_mean: flagged
    w = stats.steady_window(t, drift, transient=100.0)
    assert w.drifting and w.drift_z > stats.DRIFT_Z
    # an exponential transient that lasts past the declared transient (decay 60 samples,
    # amplitude 30): the window must start later than declared, and the series is steady then
    relax = noise + 30 * np.exp(-t / 60.0)
    w = stats.steady_window(t, relax, transient=50.0)
    assert not w.drifting and w.start > 50
    # what is left of the transient biases the window's mean by less than its error
    est = ja.mean_with_error(relax[w.start:])
    assert 30 * np.mean(np.exp(-t[w.start:] / 60.0)) <= est.error, (w.start, est.error)


def test_group_averages_equal_direct_computation():
    import pandas as pd
    table = pd.DataFrame({"model": ["RD0"] * 4, "N": [64] * 4, "phi": [0.8, 0.8, 0.8, 0.84],
                          "rate": [1e-3] * 4, "p": [1.0, 2.0, 4.0, 5.0], "p_error": [0.1, 0.2, 0.2, 0.3],
                          "left_out": ["", "", "", ""]})
    g = ja.group_averages(table, ["p"])
    first = g[g["phi"] == 0.8].iloc[0]
    assert first["seeds"] == 3 and np.isclose(first["p"], 7 / 3)
    # random effects: time errors plus t^2 tau^2 / k, tau^2 = s^2 - mean(e^2), t of 2 dof
    s2, within = np.var([1, 2, 4], ddof=1), (0.01 + 0.04 + 0.04) / 3
    t = 1.3212  # Student t, 2 dof, quantile 0.8413
    assert np.isclose(first["p_error"], np.sqrt(within / 3 + t ** 2 * (s2 - within) / 3), rtol=1e-4)
    assert np.isclose(first["p_error_seeds"], np.std([1, 2, 4], ddof=1) / np.sqrt(3))
    assert np.isclose(first["p_error_time"], np.sqrt(0.01 + 0.04 + 0.04) / 3)
    single = g[g["phi"] == 0.84].iloc[0]
    assert single["seeds"] == 1 and np.isclose(single["p_error"], 0.3)


def test_fit_errors_pool_the_seed_spread_over_model_and_n():
    import pandas as pd
    # two points of RD0 N=64 (2 seeds each, time errors 0.1), one of N=128; the pooled ratio
    # 1 + r = mean over the pool of s^2 / mean(e^2) (1 dof per point)
    table = pd.DataFrame({"model": ["RD0"] * 6, "N": [64, 64, 64, 64, 128, 128],
                          "phi": [0.80, 0.80, 0.82, 0.82, 0.80, 0.80], "rate": [1e-3] * 6,
                          "p": [1.0, 1.3, 2.0, 2.1, 1.0, 1.0], "p_error": [0.1] * 6, "left_out": [""] * 6})
    g = ja.group_averages(table, ["p"])
    pool = g[g["N"] == 64]
    ratio = np.mean([np.var([1.0, 1.3], ddof=1), np.var([2.0, 2.1], ddof=1)]) / 0.01  # 1 + r = 2.5
    t = stats.sps.t.ppf(0.5 + stats.ONE_SIGMA / 2, 2)
    expected = np.sqrt(0.01 / 2) * np.sqrt(1 + t * t * (ratio - 1))
    assert np.allclose(pool["p_error_fit"], expected)
    assert np.allclose(stats.fit_errors(pool, "p"), expected)
    # per point, the first point's spread is the larger: its own error is larger than the pooled one
    assert pool["p_error"].iloc[0] > expected > pool["p_error"].iloc[1]
    # no spread at N=128: the pooled ratio is clipped at 0 and the error is the time error
    assert np.isclose(g[g["N"] == 128]["p_error_fit"].iloc[0], np.sqrt(0.02) / 2)
    # a table without the column weights fits by <obs>_error
    assert stats.fit_errors(g.drop(columns="p_error_fit"), "p").equals(g["p_error"])
