"""The collapse fit recovers phi_J, q and znu from synthetic flow curves with a known scaling
function and 3% log-normal noise per replica (8 seeds per point): over 5 noise seeds the sum
of squared pulls (fit - truth)/error of each parameter lies inside the central 99.8% of
chi-squared with 5 dof (errors neither too small nor too large)."""
import numpy as np
import pytest

import jamsim_analysis as ja
from synthetic import TRUTH, flow_replicas, pull_bounds

NOISE_SEEDS = range(5)


def fit_of(replicas, **kw):
    groups = ja.group_averages(replicas, ["pressure"])
    return ja.fit_collapse(ja.collapse_points(groups, "pressure"), **kw)


def check_pulls(fits, names=("phi_J", "q", "znu")):
    lo, hi = pull_bounds(len(fits))
    for name in names:
        pulls = np.array([(f.values[name] - TRUTH[name]) / f.errors[name] for f in fits])
        assert lo <= np.sum(pulls ** 2) <= hi, (name, pulls)


def test_collapse_recovers_known_exponents():
    fits = [fit_of(flow_replicas(np.random.default_rng(s)), degree=2) for s in NOISE_SEEDS]
    check_pulls(fits)
    for f in fits:  # derived exponents consistent with their definitions
        assert np.isclose(f.values["y"], f.values["q"] * f.values["znu"])
        assert np.isclose(f.values["beta"], f.values["znu"] - f.values["y"])
    # the errors are small enough for the test to mean something
    assert max(f.errors["phi_J"] for f in fits) < 0.002 and max(f.errors["q"] for f in fits) < 0.02


def test_collapse_with_correction_to_scaling():
    """O = rate^q e^P(x) (1 + 3 rate^0.4) over rates 1e-2..1e-6: the corrected fit recovers
    the exponents (pull test), while the uncorrected fit of the same data is rejected by
    its chi2/dof (beyond 5 standard deviations of chi2/dof for a good fit)."""
    rates = (1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 1e-6)
    fits, plain = [], []
    for s in NOISE_SEEDS:
        reps = flow_replicas(np.random.default_rng(100 + s), noise=0.02, rates=rates, correction=(0.4, 3.0),
                             phis=np.linspace(0.835, 0.851, 9))
        fits.append(fit_of(reps, degree=2, correction_degree=0))
        plain.append(fit_of(reps, degree=2))
    check_pulls(fits)
    w = np.array([f.values["w"] for f in fits])
    dw = np.array([f.errors["w"] for f in fits])
    assert np.sum(((w - 0.4) / dw) ** 2) <= pull_bounds(len(fits))[1]
    for f in plain:
        assert f.chi2_per_dof > 1 + 5 * np.sqrt(2 / f.dof) * 1.4, f.chi2_per_dof


def test_bootstrap_over_seeds_recovers_known_exponents():
    fits = []
    for s in range(3):
        reps = flow_replicas(np.random.default_rng(200 + s))
        fit = fit_of(reps, degree=2)
        boot = ja.bootstrap_collapse(reps, "pressure", fit, n_boot=60, seed=s)
        assert boot.method.startswith("bootstrap")
        fits.append(boot)
    check_pulls(fits)


def test_bootstrap_of_three_seeds_is_widened_and_never_below_the_least_squares_errors():
    """Three seeds per point: resampled means vary by 2/3 of the mean's variance, so the
    bootstrap's standard deviations are widened by sqrt(3/2); and the errors are never below
    the least-squares ones scaled by the residuals, which also hold a misfit (a 10%
    off-model distortion at the lowest rate: chi2/dof 4.5, where the bootstrap alone gave
    errors 3-4 times smaller)."""
    reps = flow_replicas(np.random.default_rng(31), seeds=3)
    fit = fit_of(reps, degree=2)
    boot = ja.bootstrap_collapse(reps, "pressure", fit, n_boot=40, seed=3)
    again = ja.bootstrap_collapse(reps, "pressure", fit, n_boot=40, seed=3)
    assert "widened by 1.22" in boot.method, boot.method
    for k in ("phi_J", "q", "znu"):
        assert boot.errors[k] == max(boot.bootstrap_errors[k], fit.errors[k])
        assert boot.bootstrap_errors[k] == again.bootstrap_errors[k]
    reps.loc[reps["rate"] == 1e-5, "pressure"] *= 1.1
    fit = fit_of(reps, degree=2)
    boot = ja.bootstrap_collapse(reps, "pressure", fit, n_boot=40, seed=3)
    assert fit.chi2_per_dof > 3, fit.chi2_per_dof
    for k in ("phi_J", "q", "znu"):
        assert boot.bootstrap_errors[k] < fit.errors[k] == boot.errors[k], (k, boot.bootstrap_errors[k], fit.errors[k])


def test_bootstrap_widening_is_sqrt_k_over_k_minus_1():
    """The widening itself: with the least-squares errors set to 0, the errors are the
    resampled standard deviations times sqrt(3/2) for 3 seeds and sqrt(6/5) for 6 (the
    same resamples: the bootstrap's random numbers depend on the seed alone)."""
    import dataclasses
    for seeds, factor in ((3, np.sqrt(1.5)), (6, np.sqrt(1.2))):
        reps = flow_replicas(np.random.default_rng(32), seeds=seeds)
        fit = fit_of(reps, degree=2)
        zero = dataclasses.replace(fit, errors={k: 0.0 for k in fit.errors})
        boot = ja.bootstrap_collapse(reps, "pressure", zero, n_boot=30, seed=4)
        assert f"widened by {factor:.3g}" in boot.method, boot.method
        assert all(boot.errors[k] == boot.bootstrap_errors[k] > 0 for k in ("phi_J", "q", "znu"))


def _comparison(rng, other_truth=None):
    import pandas as pd
    reps = pd.concat([flow_replicas(rng, model="RD0", seeds=24),
                      flow_replicas(rng, model="CD0", ln_f=[1.5, 1.0, -0.3], seeds=24,
                                    truth=other_truth or TRUTH)])
    groups = ja.group_averages(reps, ["pressure"])
    pts = pd.concat([ja.collapse_points(groups, "pressure", model=m) for m in ("RD0", "CD0")])
    return ja.compare_collapses(pts, degree=2)


def test_joint_against_separate_collapse():
    """Two models with the same phi_J, q, znu but different scaling functions: over 10 noise
    seeds the F test's p value falls below 0.01 at most twice (expected 0.1 times for a
    calibrated test; P(>= 3) < 1e-3 even at twice the nominal rate); with q = 0.28 against
    0.36 every comparison rejects the joint collapse (p < 1e-6). 24 seeds per point: the
    F test takes the errors as known, and errors from 8 seeds are uncertain by 25%."""
    rng = np.random.default_rng(300)
    same = [_comparison(rng) for _ in range(10)]
    assert sum(c.p_value < 0.01 for c in same) <= 2, [c.p_value for c in same]
    assert "support the same criticality" in same[0].statement() or same[0].p_value < same[0].alpha
    for _ in range(3):
        diff = _comparison(rng, dict(TRUTH, q=0.36))
        assert not diff.same_criticality and diff.p_value < 1e-6, diff.p_value
        assert "do not support" in diff.statement()


def test_collapse_refuses_too_few_rates_and_points():
    reps = flow_replicas(np.random.default_rng(1), rates=(1e-3, 1e-4))
    with pytest.raises(ja.AnalysisError, match="at least 3 shear rates"):
        fit_of(reps)
    reps = flow_replicas(np.random.default_rng(1), phis=[0.84])
    with pytest.raises(ja.AnalysisError, match="points in the window"):
        fit_of(reps, degree=3)
    groups = ja.group_averages(flow_replicas(np.random.default_rng(1), seeds=1), ["pressure"])
    with pytest.raises(ja.AnalysisError, match="at least 2 seeds"):
        ja.collapse_points(groups, "pressure")
