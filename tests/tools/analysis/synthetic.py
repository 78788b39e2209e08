"""Synthetic data with a known answer for the fit tests."""
import numpy as np
import pandas as pd

TRUTH = {"phi_J": 0.8433, "q": 0.28, "znu": 3.5}
LN_F = [0.5, 2.0, -0.8]  # ln F(x) = 0.5 + 2 x - 0.8 x^2 (coefficients low to high)


def flow_replicas(rng, noise=0.03, seeds=8, truth=TRUTH, ln_f=LN_F, correction=None, model="RD0",
                  phis=np.linspace(0.825, 0.865, 9), rates=(1e-3, 3e-4, 1e-4, 3e-5, 1e-5)):
    """Replica means O = rate^q exp(P(x)) (1 + rate^w c) exp(noise * gaussian), one row per
    (phi, rate, seed); correction = (w, c) or None."""
    rows = []
    for phi in phis:
        for rate in rates:
            x = (phi - truth["phi_J"]) / rate ** (1 / truth["znu"])
            value = rate ** truth["q"] * np.exp(np.polyval(ln_f[::-1], x))
            if correction is not None:
                value *= 1 + rate ** correction[0] * correction[1]
            for seed in range(seeds):
                rows.append(dict(model=model, N=1024, phi=round(phi, 5), rate=rate, seed=seed,
                                 pressure=value * np.exp(noise * rng.normal()), pressure_error=np.nan,
                                 left_out=""))
    return pd.DataFrame(rows)


def pull_bounds(k, level=0.001):
    """Range of sum of k squared pulls (chi-squared, k dof) outside which a calibrated
    estimator with correct errors lands with probability `level` on each side."""
    from scipy.stats import chi2
    return chi2.ppf(level, k), chi2.ppf(1 - level, k)
