"""Divergence fits and the Newtonian/Bagnold plateaus on synthetic flow curves with a known
answer: C(phi) = A (phi_J - phi)^-beta (1 + c (phi_J - phi)), relative noise 3% with that
error given. Over 5 noise seeds the squared pulls of beta and phi_J sum inside the central
99.8% of chi-squared with 5 dof."""
import numpy as np
import pandas as pd
import pytest

import jamsim_analysis as ja
from jamsim_analysis import rheology
from synthetic import pull_bounds

PHI_J, NOISE = 0.8433, 0.03
PHIS = np.array([0.78, 0.79, 0.80, 0.81, 0.82, 0.825, 0.83, 0.835])


def coefficient(phi, beta, c=0.0, A=1.0):
    d = PHI_J - phi
    return A * d ** -beta * (1 + c * d)


def flow_groups(rng, power, beta, c=0.0, rates=(1e-6, 3e-6, 1e-5), thinning_rate=None):
    """Group averages O = rate^power C(phi) (noise NOISE, error given); at thinning_rate, if
    given, O is 100 times lower than the plateau (shear thinning: slope far below power)."""
    rows = []
    for phi in PHIS:
        for rate in rates + ((thinning_rate,) if thinning_rate else ()):
            value = rate ** power * coefficient(phi, beta, c) * (0.01 if rate == thinning_rate else 1)
            rows.append(dict(model="RD0", N=1024, phi=phi, rate=rate, seeds=8,
                             pressure=value * (1 + NOISE * rng.normal()), pressure_error=NOISE * value))
    return pd.DataFrame(rows)


def check(values, errors, truth):
    lo, hi = pull_bounds(len(values))
    pulls = (np.array(values) - truth) / np.array(errors)
    assert lo <= np.sum(pulls ** 2) <= hi, pulls


@pytest.mark.parametrize("phi_j_known", [True, False])
def test_divergence_fit_recovers_beta(phi_j_known):
    fits = []
    for s in range(5):
        rng = np.random.default_rng(s)
        v = coefficient(PHIS, 2.6)
        fits.append(ja.fit_divergence(PHIS, v * (1 + NOISE * rng.normal(size=len(v))), NOISE * v,
                                      phi_j=PHI_J if phi_j_known else None))
    check([f.values["beta"] for f in fits], [f.errors["beta"] for f in fits], 2.6)
    if not phi_j_known:
        check([f.values["phi_J"] for f in fits], [f.errors["phi_J"] for f in fits], PHI_J)


def test_local_slopes_classify_regimes():
    rows = [dict(model="RD", N=64, phi=0.8, rate=r, pressure=r ** k * 5, pressure_error=1e-3 * r ** k * 5)
            for k, r0 in ((1, 0), (2, 0)) for r in (1e-4, 1e-3)]
    g = pd.DataFrame(rows)
    g.loc[:1, "phi"] = 0.7
    slopes = rheology.local_slopes(g, "pressure").set_index("phi")
    assert slopes.loc[0.7, "regime"] == "Newtonian" and np.isclose(slopes.loc[0.7, "slope"], 1)
    assert slopes.loc[0.8, "regime"] == "Bagnold" and np.isclose(slopes.loc[0.8, "slope"], 2)
    g.loc[:1, "pressure"] = [1.0, 10 ** 0.5]
    assert rheology.local_slopes(g, "pressure").set_index("phi").loc[0.7, "regime"] == "shear thinning"


def test_newtonian_plateau_leaves_out_shear_thinning_and_recovers_beta():
    fits = []
    for s in range(5):
        groups = flow_groups(np.random.default_rng(10 + s), 1, 2.6, thinning_rate=1e-3)
        plateau, fit = ja.newtonian_divergence(groups, "pressure", phi_j=PHI_J)
        assert (plateau["rates_used"] == 3).all(), plateau  # the shear-thinning rate is not used
        fits.append(fit)
    check([f.values["beta"] for f in fits], [f.errors["beta"] for f in fits], 2.6)


def test_bagnold_divergence_with_correction_recovers_beta():
    fits = []
    for s in range(5):
        groups = flow_groups(np.random.default_rng(20 + s), 2, 5.0, c=-4.0)
        plateau, fit = ja.bagnold_analysis(groups, "pressure", phi_j=PHI_J, correction=True)
        assert plateau["left_out"].eq("").all()
        fits.append(fit)
    check([f.values["beta"] for f in fits], [f.errors["beta"] for f in fits], 5.0)
    check([f.values["c"] for f in fits], [f.errors["c"] for f in fits], -4.0)


def test_divergence_refuses_too_few_points():
    with pytest.raises(ja.AnalysisError, match="points below phi_J"):
        ja.fit_divergence([0.80, 0.81], [1.0, 2.0], [0.1, 0.1])
