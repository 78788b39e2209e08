"""Finite-size scaling of the jamming threshold on synthetic ensembles with a known answer:
phi_J of each configuration normal with mean phi_inf + b N^(-1/(2 nu)) and width
a N^(-1/(2 nu)) (compression protocols), or quenches at fixed phi that jam with probability
Phi((phi - mu_N)/s_N) (RAND). Pull sums over 5 noise seeds inside chi-squared's central 99.8%."""
import numpy as np
import pandas as pd
import pytest

import jamsim_analysis as ja
from jamsim_analysis import jamming
from synthetic import pull_bounds

TRUE = {"phi_J_inf": 0.8423, "b": -0.25, "a": 0.12, "nu": 1.0}
SIZES = (32, 64, 128, 256, 512, 1024)


def centre_and_width(n):
    scale = n ** (-1 / (2 * TRUE["nu"]))
    return TRUE["phi_J_inf"] + TRUE["b"] * scale, TRUE["a"] * scale


def compressed_states(rng, per_size=200):
    rows = []
    for n in SIZES:
        mu, s = centre_and_width(n)
        for v in rng.normal(mu, s, per_size):
            rows.append(dict(model="COMPRESS", N=n, phi=0.86, jammed=1, packing_fraction=v))
    return pd.DataFrame(rows)


def quenched_states(rng, per_point=150):
    rows = []
    for n in SIZES[:4]:
        mu, s = centre_and_width(n)
        for phi in mu + s * np.linspace(-2, 2, 9):
            p = ja.jamming.special.ndtr((phi - mu) / s)
            for j in rng.random(per_point) < p:
                rows.append(dict(model="RAND", N=n, phi=phi, jammed=int(j), packing_fraction=phi))
    return pd.DataFrame(rows)


def check(fits, names):
    lo, hi = pull_bounds(len(fits))
    for name in names:
        pulls = np.array([(f.values[name] - TRUE[name]) / f.errors[name] for f in fits])
        assert lo <= np.sum(pulls ** 2) <= hi, (name, pulls)


def test_finite_size_scaling_of_compressed_thresholds():
    fits = [jamming.finite_size_scaling(jamming.thresholds(compressed_states(np.random.default_rng(s))))
            for s in range(5)]
    check(fits, ("phi_J_inf", "nu", "a", "b"))


def test_thresholds_from_jamming_probability_and_their_scaling():
    fits, mus = [], []
    for s in range(5):
        thr = jamming.thresholds(quenched_states(np.random.default_rng(10 + s)))
        mus.append(thr)
        fits.append(jamming.finite_size_scaling(thr))
    check(fits, ("phi_J_inf", "nu"))
    # the per-N maximum-likelihood centres and widths, pooled over seeds and sizes
    pulls = []
    for thr in mus:
        for _, t in thr.iterrows():
            mu, s = centre_and_width(t["N"])
            pulls += [(t["mu"] - mu) / t["mu_error"], (t["s"] - s) / t["s_error"]]
    lo, hi = pull_bounds(len(pulls))
    assert lo <= np.sum(np.square(pulls)) <= hi


def test_jamming_probability_counts_and_binomial_errors():
    states = pd.DataFrame(dict(model="RAND", N=64, phi=[0.84] * 4 + [0.86] * 2, jammed=[0, 1, 1, 1, 1, 1]))
    pj = jamming.jamming_probability(states).set_index("phi")
    assert pj.loc[0.84, "P_J"] == 0.75 and np.isclose(pj.loc[0.84, "error"], np.sqrt(0.75 * 0.25 / 4))
    assert pj.loc[0.86, "P_J"] == 1.0 and np.isclose(pj.loc[0.86, "error"], np.sqrt(0.5 * 0.5 / 2))


def test_too_few_sizes_and_unresolved_widths_are_refused():
    thr = jamming.thresholds(compressed_states(np.random.default_rng(0)))
    with pytest.raises(ja.AnalysisError, match="at least 3 system sizes"):
        jamming.finite_size_scaling(thr[thr["N"] <= 64])
    with pytest.raises(ja.AnalysisError, match="not resolved"):
        jamming.threshold_from_counts([0.80, 0.82, 0.84], [0, 10, 10], [10, 10, 10])
