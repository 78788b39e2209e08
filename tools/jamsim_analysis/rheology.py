"""Rheology below jamming: local slopes of the flow curves, the Newtonian viscosity
eta_p = p/rate (overdamped models) and the Bagnold coefficient B_p = p/rate^2 (massive
models) extrapolated to rate -> 0, and their divergence at phi_J:
    C(phi) = A (phi_J - phi)^-beta [1 + c (phi_J - phi)]   (the bracket: leading correction).
"""
import dataclasses

import numpy as np
import pandas as pd
from scipy import stats as sps
from scipy.optimize import least_squares

from . import stats
from .errors import AnalysisError

# A local slope is consistent with a value when within this many standard errors.
SLOPE_Z = 2.0
# Lowest rates form a plateau of O/rate^power when a constant fits them with this p value.
PLATEAU_P = 0.001


def local_slopes(groups, observable):
    """d ln O / d ln rate between consecutive rates per (model, N, phi): DataFrame with
    model, N, phi, rate_low, rate_high, slope, slope_error and regime: "Newtonian" (slope 1),
    "Bagnold" (2), "shear thinning" (< 1), "intermediate" (between) or "undetermined"
    (consistent with both 1 and 2)."""
    rows = []
    g = groups[groups["rate"] > 0]
    for key, part in g.groupby([k for k in ("model", "N", "phi") if k in g], sort=True):
        part = part.sort_values("rate")
        r, o, e = (part[c].to_numpy(float) for c in ("rate", observable, f"{observable}_error"))
        for i in range(len(r) - 1):
            if o[i] <= 0 or o[i + 1] <= 0:
                continue
            dl = np.log(r[i + 1] / r[i])
            s = np.log(o[i + 1] / o[i]) / dl
            se = np.hypot(e[i] / o[i], e[i + 1] / o[i + 1]) / dl
            rows.append(dict(zip(("model", "N", "phi"), key), rate_low=r[i], rate_high=r[i + 1],
                             slope=s, slope_error=se, regime=_regime(s, se)))
    return pd.DataFrame(rows)


def _regime(s, se):
    newton, bagnold = abs(s - 1) <= SLOPE_Z * se, abs(s - 2) <= SLOPE_Z * se
    if newton and bagnold:
        return "undetermined"
    if newton:
        return "Newtonian"
    if bagnold:
        return "Bagnold"
    return "shear thinning" if s < 1 else "intermediate"


@dataclasses.dataclass
class Divergence:
    """Fit of C(phi) = A (phi_J - phi)^-beta [1 + c (phi_J - phi)]: values/errors of
    beta, phi_J (given or fitted), A and c (with the correction); chi2, dof; the points
    fitted (phi, value, error)."""
    values: dict
    errors: dict
    chi2: float
    dof: int
    points: pd.DataFrame
    phi_j_fixed: bool

    @property
    def chi2_per_dof(self):
        return self.chi2 / self.dof if self.dof > 0 else float("nan")

    def curve(self, phi):
        d = self.values["phi_J"] - np.asarray(phi, float)
        return self.values["A"] * d ** -self.values["beta"] * (1 + self.values.get("c", 0.0) * d)


def fit_divergence(phi, value, error, phi_j=None, correction=False, start_beta=2.5):
    """Weighted least squares of ln C against (phi_J - phi) for the points with phi < phi_J;
    phi_j=None fits phi_J too. Errors scaled by the residuals: times t sqrt(chi2/dof)
    (stats.residual_scale)."""
    phi, value, error = (np.asarray(a, float) for a in (phi, value, error))
    keep = (value > 0) & (error > 0) & np.isfinite(value)
    if phi_j is not None:
        keep &= phi < phi_j
    phi, value, error = phi[keep], value[keep], error[keep]
    names = ["lnA", "beta"] + ([] if phi_j is not None else ["phi_J"]) + (["c"] if correction else [])
    if len(phi) <= len(names):
        raise AnalysisError(f"{len(phi)} points below phi_J: a divergence fit with {len(names)} "
                            f"parameters ({', '.join(names)}) needs more")
    ln_v, ln_e = np.log(value), error / value

    def unpack(t):
        d = dict(zip(names, t))
        return d["lnA"], d["beta"], d.get("phi_J", phi_j), d.get("c", 0.0)

    def residuals(t):
        ln_a, beta, pj, c = unpack(t)
        d = np.maximum(pj - phi, 1e-12)
        return (ln_v - (ln_a - beta * np.log(d) + np.log(np.maximum(1 + c * d, 1e-12)))) / ln_e

    best = None
    gaps = [None] if phi_j is not None else [0.002, 0.01, 0.03]
    for gap in gaps:
        t0 = [0.0, start_beta] + ([] if gap is None else [phi.max() + gap]) + ([0.0] if correction else [])
        pj0 = phi_j if gap is None else phi.max() + gap
        t0[0] = np.mean(ln_v + start_beta * np.log(pj0 - phi))
        lower = [-np.inf, -np.inf] + ([] if gap is None else [phi.max() + 1e-9]) + ([-np.inf] if correction else [])
        try:
            res = least_squares(residuals, t0, bounds=(lower, np.inf), x_scale="jac", max_nfev=5000)
        except ValueError:
            continue
        if best is None or res.cost < best.cost:
            best = res
    if best is None:
        raise AnalysisError("the divergence fit did not converge")
    chi2 = float(np.sum(best.fun ** 2))
    dof = len(phi) - len(names)
    cov = np.linalg.pinv(best.jac.T @ best.jac) * stats.residual_scale(chi2, dof)
    sd = np.sqrt(np.clip(np.diag(cov), 0, None))
    ln_a, beta, pj, c = unpack(best.x)
    values = {"beta": beta, "phi_J": pj, "A": float(np.exp(ln_a))}
    errors = {"beta": sd[1], "phi_J": sd[names.index("phi_J")] if "phi_J" in names else 0.0,
              "A": float(np.exp(ln_a) * sd[0])}
    if correction:
        values["c"], errors["c"] = c, sd[names.index("c")]
    pts = pd.DataFrame({"phi": phi, "value": value, "error": error})
    return Divergence({k: float(v) for k, v in values.items()}, {k: float(v) for k, v in errors.items()},
                      chi2, dof, pts, phi_j is not None)


def plateau_values(groups, observable, power, phi_j=None, model=None, p_min=PLATEAU_P):
    """Per (N, phi) the rate -> 0 limit of C = O/rate^power (power 1: Newtonian viscosity,
    2: Bagnold coefficient): the weighted mean of C over the largest set of lowest rates
    (at least 2) whose C agree with one constant (chi-squared p value >= p_min). DataFrame
    N, phi, value, error, rates_used, left_out (the reason, "" for points used)."""
    regime = {1: "Newtonian", 2: "Bagnold"}[power]
    g = groups[groups["rate"] > 0]
    if model is not None:
        g = g[g["model"] == model]
    rows = []
    for (n, phi), part in g.groupby(["N", "phi"], sort=True):
        part = part.sort_values("rate")
        row = {"N": n, "phi": phi, "value": np.nan, "error": np.nan, "rates_used": 0, "left_out": ""}
        rate = part["rate"].to_numpy(float)
        c = part[observable].to_numpy(float) / rate ** power
        e = stats.fit_errors(part, observable).to_numpy(float) / rate ** power
        if phi_j is not None and phi >= phi_j:
            row["left_out"] = f"phi >= phi_J = {phi_j:.4f}"
        elif len(part) < 2 or not np.all(e[:2] > 0):
            row["left_out"] = "fewer than 2 rates with errors"
        else:
            for used in range(len(c), 1, -1):
                w = 1 / e[:used] ** 2
                mean = np.sum(w * c[:used]) / np.sum(w)
                chi2 = np.sum(w * (c[:used] - mean) ** 2)
                if sps.chi2.sf(chi2, used - 1) >= p_min:
                    row.update(value=mean, error=1 / np.sqrt(np.sum(w)), rates_used=used)
                    break
            else:
                row["left_out"] = (f"not {regime} at the lowest rates: O/rate^{power} differs between "
                                   f"{rate[0]:g} and {rate[1]:g} (p < {p_min:g})")
        rows.append(row)
    return pd.DataFrame(rows)


def size_with_most_plateaus(plateau):
    """The N of plateau_values' table with the most phi at their plateau (the largest of
    those); None when no phi has one."""
    used = plateau[plateau["left_out"] == ""].groupby("N")["phi"].count()
    return max(used.index[used == used.max()]) if len(used) else None


def _divergence_of(groups, observable, power, phi_j, correction, N, model, p_min):
    plateau = plateau_values(groups, observable, power, phi_j, model, p_min)
    sizes = sorted(plateau["N"].unique())
    if not sizes:
        raise AnalysisError("no flow curve with rate > 0")
    if N is None:
        N = size_with_most_plateaus(plateau) or sizes[-1]
    table = plateau[plateau["N"] == N]
    used = table[table["left_out"] == ""]
    fit = fit_divergence(used["phi"], used["value"], used["error"], phi_j, correction,
                         start_beta=2.5 if power == 1 else 5.0)
    return table, fit


def newtonian_divergence(groups, observable="pressure", phi_j=None, correction=False, N=None, model=None,
                         p_min=PLATEAU_P):
    """eta_O = O/rate extrapolated to rate -> 0 (Newtonian plateau) per phi below phi_J, and
    its divergence eta ~ (phi_J - phi)^-beta, at N (default: the size with the most phi at
    their plateau). Returns (plateau table, Divergence)."""
    return _divergence_of(groups, observable, 1, phi_j, correction, N, model, p_min)


def bagnold_analysis(groups, observable="pressure", phi_j=None, correction=True, N=None, model=None,
                     p_min=PLATEAU_P):
    """B_O = O/rate^2 at the Bagnold plateau per phi below phi_J and its divergence
    B ~ (phi_J - phi)^-beta (1 + c (phi_J - phi)), at N (default: the size with the most phi
    at their plateau). Returns (plateau table, Divergence)."""
    return _divergence_of(groups, observable, 2, phi_j, correction, N, model, p_min)
