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


def write_flow_archive(path, model, means, rng, seeds=4, samples=200, noise=0.05, campaign=None,
                       shear_ratio=0.3, rho=0.0, first_seed=0):
    """A campaign archive in jamsim's layout (/replicas, /timeseries) of `model` with
    `seeds` replicas per state point: means = {(N, phi, rate): mean pressure}. Each replica's
    pressure series is mean * (1 + noise * AR(1) of correlation rho and unit variance) over
    `samples` samples after strain 0 (transient 0); shear_stress = shear_ratio * pressure.
    Replicas are done, without final configurations or correlations; seeds from `first_seed`,
    identities a hash of (model, N, phi, rate) as jamsim's are of the parameters (two archives
    of one state point with the same seeds hold "the same replicas"). Returns the path."""
    import h5py
    import zlib

    points = sorted(means)
    rows = [(n, phi, rate, s) for (n, phi, rate) in points for s in range(first_seed, first_seed + seeds)]
    p = np.empty((len(rows), samples))
    for k, (n, phi, rate, _) in enumerate(rows):
        e = rng.normal(size=samples)
        x = np.empty(samples)
        x[0] = e[0]
        for t in range(1, samples):
            x[t] = rho * x[t - 1] + np.sqrt(1 - rho ** 2) * e[t]
        p[k] = means[(n, phi, rate)] * (1 + noise * x)
    campaign = campaign or f"synthetic-{model}"
    with h5py.File(path, "w") as f:
        f.attrs.update(campaign=campaign, model=model, layout_version=4, code_version="synthetic",
                       spec_fingerprint=f"{zlib.crc32(campaign.encode()):08x}")
        r = f.create_group("replicas")
        cols = dict(N=[a[0] for a in rows], phi=[a[1] for a in rows], rate=[a[2] for a in rows],
                    seed=[a[3] for a in rows])
        for name, v in cols.items():
            r[name] = np.asarray(v, float)
        r["status"] = np.full(len(rows), 2, np.int32)
        r["n_samples"] = np.full(len(rows), samples, np.int64)
        r["rows_written"] = np.full(len(rows), samples, np.int64)
        r["identity"] = np.asarray([zlib.crc32(f"{model} {a[0]} {a[1]!r} {a[2]!r}".encode()) for a in rows], np.uint64)
        r["transient"] = np.zeros(len(rows))
        r["strain"] = np.full(len(rows), 1.0)
        t = f.create_group("timeseries")
        t["strain"] = np.tile(np.linspace(0, 1, samples, endpoint=False), (len(rows), 1))
        t["pressure"] = p
        t["shear_stress"] = shear_ratio * p
    return str(path)
