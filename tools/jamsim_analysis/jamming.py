"""Jamming of static ensembles (Papers I-II): the states of RAND, COOL, COMPRESS,
COOL_COMPRESS and SHEARED campaigns, the jamming probability P_J(phi, N), and finite-size
scaling of the threshold.

In 2D, L ~ N^(1/2). Per N the threshold distribution has a mean mu_N and a width s_N:
    s_N  = a N^(-1/(2 nu))                               (width: the correlation length)
    mu_N = phi_J(inf) + b N^(-(1/nu + omega)/2)          (shift; omega = 0 without correction)
For RAND and COOL (one quench at a fixed phi per replica) mu_N and s_N come from a
maximum-likelihood fit of P_J(phi) = Phi((phi - mu_N)/s_N) (Phi the normal CDF) to the
binomial counts; for the compression protocols (one phi_J per replica) they are the sample
mean and standard deviation.
"""
import dataclasses

import numpy as np
import pandas as pd
from scipy import optimize, special

from .errors import AnalysisError

QUENCHED = ("RAND", "COOL")  # one state at the replica's phi
COMPRESSED = ("COMPRESS", "COOL_COMPRESS", "SHEARED")  # one state at its own phi_J
STATE_COLUMNS = ("jammed", "pressure", "packing_fraction", "contact_number_nonrattler",
                 "excess_contacts", "energy_per_particle", "rattler_fraction")


def static_states(archive):
    """One row per finished replica of static models: model, N, phi, seed and the state's
    columns (jammed, pressure, packing_fraction, ...; the first row of each series)."""
    done = archive.done()
    unknown = sorted(set(done["model"]) - set(QUENCHED) - set(COMPRESSED))
    if unknown:
        raise AnalysisError(f"model {', '.join(unknown)} is not a jamming protocol "
                            f"({', '.join(QUENCHED + COMPRESSED)})")
    if done.empty:
        raise AnalysisError("no finished replica")
    present = [c for c in STATE_COLUMNS if c in archive.observables()]
    rows = []
    for _, rep in done.iterrows():
        row = {k: rep[k] for k in ("replica", "model", "N", "phi", "seed") if k in rep}
        for c in present:
            v = archive.series(int(rep["replica"]), c)
            row[c] = v[0] if len(v) else np.nan
        rows.append(row)
    return pd.DataFrame(rows)


def jamming_probability(states):
    """P_J per (model, N, phi) of quenched states: DataFrame model, N, phi, configurations,
    jammed, P_J, error (binomial, at least that of one event in m)."""
    rows = []
    for (model, n, phi), part in states.groupby(["model", "N", "phi"], sort=True):
        m, k = len(part), int(np.sum(part["jammed"] == 1))
        q = k / m
        err = np.sqrt(max(q * (1 - q), (1 / m) * (1 - 1 / m)) / m)
        rows.append(dict(model=model, N=n, phi=phi, configurations=m, jammed=k, P_J=q, error=err))
    return pd.DataFrame(rows)


def phi_j_samples(states):
    """Thresholds of the compression protocols: {(model, N): array of phi_J of jammed states}."""
    ok = states[states["jammed"] == 1]
    return {key: part["packing_fraction"].to_numpy(float) for key, part in ok.groupby(["model", "N"])}


def _numerical_hessian(f, x, h):
    x = np.asarray(x, float)
    n = len(x)
    hess = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            ei, ej = np.eye(n)[i] * h[i], np.eye(n)[j] * h[j]
            hess[i, j] = (f(x + ei + ej) - f(x + ei - ej) - f(x - ei + ej) + f(x - ei - ej)) / (4 * h[i] * h[j])
    return hess


def threshold_from_counts(phi, jammed, total):
    """Maximum-likelihood (mu, s) of P_J(phi) = Phi((phi - mu)/s) from binomial counts, with
    standard errors from the inverse Hessian: (mu, mu_error, s, s_error)."""
    phi, k, m = (np.asarray(a, float) for a in (phi, jammed, total))
    if len(phi) < 3 or np.all(k == 0) or np.all(k == m):
        raise AnalysisError("P_J must rise through (0, 1) over at least 3 packing fractions "
                            "for a threshold fit")

    def nll(t):
        mu, log_s = t
        p = np.clip(special.ndtr((phi - mu) / np.exp(log_s)), 1e-12, 1 - 1e-12)
        return -np.sum(k * np.log(p) + (m - k) * np.log(1 - p))

    q = k / m
    if not np.any((q > 0) & (q < 1)):
        raise AnalysisError("P_J jumps from 0 to 1 between two packing fractions: the width of the "
                            "threshold is not resolved (more packing fractions or configurations needed)")
    mu0 = np.interp(0.5, q, phi) if np.all(np.diff(q) >= 0) else phi[np.argmin(abs(q - 0.5))]
    s0 = max(np.ptp(phi) / 4, 1e-4)
    res = optimize.minimize(nll, [mu0, np.log(s0)], method="Nelder-Mead",
                            options={"xatol": 1e-9, "fatol": 1e-10, "maxiter": 4000})
    mu, log_s = res.x
    s = np.exp(log_s)
    cov = np.linalg.pinv(_numerical_hessian(nll, res.x, [s * 1e-2, 1e-2]))
    errors = np.sqrt(np.diag(cov))
    if not (np.all(np.isfinite(errors)) and np.all(errors > 0)) or errors[1] > 1:  # s_error > s
        raise AnalysisError("P_J jumps from 0 to 1 between two packing fractions: the width of the "
                            "threshold is not resolved (more packing fractions or configurations needed)")
    return float(mu), float(np.sqrt(max(cov[0, 0], 0))), float(s), float(s * np.sqrt(max(cov[1, 1], 0)))


def thresholds(states):
    """mu_N and s_N (with errors) per (model, N): DataFrame model, N, mu, mu_error, s,
    s_error, configurations."""
    rows = []
    for (model, n), part in states.groupby(["model", "N"], sort=True):
        if model in COMPRESSED:
            v = part.loc[part["jammed"] == 1, "packing_fraction"].to_numpy(float)
            if len(v) < 3:
                continue
            s = v.std(ddof=1)
            rows.append(dict(model=model, N=n, mu=v.mean(), mu_error=s / np.sqrt(len(v)), s=s,
                             s_error=s / np.sqrt(2 * (len(v) - 1)), configurations=len(v)))
        else:
            pj = jamming_probability(part)
            try:
                mu, dmu, s, ds = threshold_from_counts(pj["phi"], pj["jammed"], pj["configurations"])
            except AnalysisError:
                continue
            rows.append(dict(model=model, N=n, mu=mu, mu_error=dmu, s=s, s_error=ds,
                             configurations=int(pj["configurations"].sum())))
    return pd.DataFrame(rows)


@dataclasses.dataclass
class FiniteSizeFit:
    """phi_J(inf), nu, a, b (and omega with the correction) with errors, chi2, dof and the
    per-N thresholds used."""
    values: dict
    errors: dict
    chi2: float
    dof: int
    thresholds: pd.DataFrame

    @property
    def chi2_per_dof(self):
        return self.chi2 / self.dof if self.dof > 0 else float("nan")


def finite_size_scaling(table, correction=False):
    """Joint weighted fit of s_N and mu_N (see the module) to the thresholds of one model
    (DataFrame N, mu, mu_error, s, s_error). Needs at least 3 sizes."""
    t = table.sort_values("N")
    t = t[(t["mu_error"] > 0) & (t["s_error"] > 0) & np.isfinite(t["mu_error"]) & np.isfinite(t["s_error"])]
    n = t["N"].to_numpy(float)
    if len(n) < 3:
        raise AnalysisError(f"finite-size scaling needs at least 3 system sizes with a threshold; "
                            f"the data have {len(n)}")
    mu, dmu, s, ds = (t[c].to_numpy(float) for c in ("mu", "mu_error", "s", "s_error"))
    names = ["phi_J_inf", "b", "a", "nu"] + (["omega"] if correction else [])
    if 2 * len(n) <= len(names):
        raise AnalysisError(f"{len(n)} sizes: the fit with {len(names)} parameters needs more")

    def unpack(t):
        d = dict(zip(names, t))
        return d["phi_J_inf"], d["b"], d["a"], d["nu"], d.get("omega", 0.0)

    def residuals(t):
        pinf, b, a, nu, om = unpack(t)
        return np.concatenate([(mu - (pinf + b * n ** (-(1 / nu + om) / 2))) / dmu,
                               (s - a * n ** (-1 / (2 * nu))) / ds])

    slope = np.polyfit(np.log(n), np.log(s), 1)[0]
    nu0 = float(np.clip(-1 / (2 * slope), 0.3, 5)) if slope < 0 else 1.0
    a0 = float(np.exp(np.mean(np.log(s) + np.log(n) / (2 * nu0))))
    best = None
    for b0 in (-0.3, 0.0, 0.3):
        t0 = [mu[-1], b0, a0, nu0] + ([0.5] if correction else [])
        res = optimize.least_squares(residuals, t0, x_scale="jac", max_nfev=5000)
        if best is None or res.cost < best.cost:
            best = res
    chi2 = float(np.sum(best.fun ** 2))
    dof = 2 * len(n) - len(names)
    cov = np.linalg.pinv(best.jac.T @ best.jac) * max(1.0, chi2 / dof)
    sd = np.sqrt(np.clip(np.diag(cov), 0, None))
    return FiniteSizeFit(dict(zip(names, map(float, best.x))), dict(zip(names, map(float, sd))),
                         chi2, dof, t.reset_index(drop=True))
