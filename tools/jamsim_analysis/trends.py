"""Do fitted values move toward the published ones as the explanation of a disagreement
predicts? Two tests of "finite size and too-high rates":
  - the collapse in one window fitted at each system size N: phi_J, q, znu, y, beta against
    log2 N (a larger system should land nearer the published values);
  - the Newtonian exponent beta as the points come closer to phi_J: eta = p/rate at its
    Newtonian plateau, the local exponents -d ln eta / d ln(phi_J - phi) between neighbouring
    phi, and their trend from ln eta = a + b ln d + c (ln d)^2, d = phi_J - phi (farther from
    phi_J the effective exponent should be below the asymptotic one). They depend on phi_J:
    each is given at the published phi_J's ends and at the size's own fitted phi_J.
A trend is a slope (per doubling of N, per halving of phi_J - phi) with its error; its verdict
compares the fitted line's two ends with the published range: toward it, away from it,
across it, leaving it or staying in it; or no trend, when the slope is within 2 errors of 0.
The published values are Paper II's, for harmonic RD0 (and CD0, the same criticality).
"""
import dataclasses

import numpy as np
import pandas as pd

from . import rheology, scaling
from .errors import AnalysisError

# Paper II (harmonic RD0 of this mixture, N = 65536, rates to 1e-7, corrections to scaling):
# the range quoted for each value. znu = y + beta.
PUBLISHED = {"phi_J": (0.8433, 0.8435), "q": (0.28, 0.28), "y": (1.08, 1.08), "beta": (2.6, 2.8),
             "znu": (3.68, 3.88)}
# A trend (or a distance) counts when it is this many standard errors from zero.
TREND_Z = 2.0


@dataclasses.dataclass
class Trend:
    """A slope (value per unit x) with its error, the fitted line's values at the smallest
    and largest x (first, last; last_error: the line's error there), and the published
    range (lo, hi) it is judged against."""
    parameter: str
    slope: float
    slope_error: float
    chi2: float
    dof: int
    published: tuple
    first: float
    last: float
    last_error: float

    @property
    def z(self):
        if self.slope == 0:
            return 0.0
        return self.slope / self.slope_error if self.slope_error > 0 else np.inf * np.sign(self.slope)

    def _gap(self, v):
        """Signed distance of v from the published range: < 0 below, > 0 above, 0 inside."""
        lo, hi = self.published
        return v - lo if v < lo else v - hi if v > hi else 0.0

    def distance_z(self):
        """How many errors the line's last value lies outside the published range (0 inside)."""
        gap = abs(self._gap(self.last))
        return gap / self.last_error if self.last_error > 0 else (np.inf if gap else 0.0)

    def verdict(self):
        if abs(self.z) < TREND_Z:
            return "no trend beyond its errors"
        g0, g1 = self._gap(self.first), self._gap(self.last)
        if g0 == 0:
            return "stays in the published range" if g1 == 0 else "leaves the published range"
        if g1 == 0:
            return "moves toward the published value, into its range"
        if np.sign(g0) != np.sign(g1):
            return "moves across the published range (overshoots it)"
        return "moves toward the published value" if abs(g1) < abs(g0) else "moves away from the published value"


def _line(parameter, x, value, error, degree=1):
    """Weighted least squares of value on a polynomial of x (degree 1 or 2); the errors are
    widened by sqrt(chi2/dof) when that exceeds 1 (scatter beyond the error bars widens
    them; the values' own errors are taken as right otherwise: with 3 sizes chi2 has one
    degree of freedom, too few to estimate the scatter from the residuals alone). Returns
    the coefficients (low to high), their covariance, chi2, dof and the x of the points used
    (finite values with finite errors > 0)."""
    x, v, e = (np.asarray(a, float) for a in (x, value, error))
    keep = np.isfinite(v) & np.isfinite(e) & (e > 0)
    x, v, e = x[keep], v[keep], e[keep]
    if len(x) < degree + 1 or np.ptp(x) == 0:
        raise AnalysisError(f"{parameter}: a trend needs values at {degree + 1} or more places ({len(x)} here)")
    w = 1 / e ** 2
    design = np.column_stack([x ** k for k in range(degree + 1)])
    cov = np.linalg.inv(design.T @ (design * w[:, None]))
    coef = cov @ (design.T @ (w * v))
    chi2 = float(np.sum(w * (v - design @ coef) ** 2))
    dof = len(x) - degree - 1
    cov = cov * (max(1.0, chi2 / dof) if dof > 0 else 1.0)
    return coef, cov, chi2, dof, x


def fit_trend(parameter, x, value, error, published):
    """Trend of one parameter: the straight line through (x, value +- error) (_line)."""
    coef, cov, chi2, dof, x = _line(parameter, x, value, error)
    ends = np.array([[1.0, x.min()], [1.0, x.max()]])
    first, last = ends @ coef
    last_error = float(np.sqrt(ends[1] @ cov @ ends[1]))
    return Trend(parameter, float(coef[1]), float(np.sqrt(cov[1, 1])), chi2, dof, published, float(first),
                 float(last), last_error)


def statement(trend, per, last_label):
    """One sentence: the verdict, the slope with its error (per `per`), and where the line's
    last value (at `last_label`) stands against the published range."""
    lo, hi = trend.published
    pub = f"{lo:g}" if lo == hi else f"{lo:g}-{hi:g}"
    gap = trend.distance_z()
    where = "inside the published range" if gap == 0 else f"{gap:.1f} errors from it"
    return (f"{trend.parameter}: {trend.verdict()} ({pub}); slope {trend.slope:+.3g} +- {trend.slope_error:.2g} "
            f"per {per} ({trend.z:+.1f} errors); at {last_label} {trend.last:.4g} +- {trend.last_error:.2g}, {where}")


def size_statements(by_size, found):
    """statement() of each trend of size_trends, per doubling of N, at the largest N fitted."""
    last = f"N = {by_size.loc[by_size['left_out'] == '', 'N'].max()}"
    return [statement(t, "doubling of N", last) for t in found]


def collapse_by_size(table, groups, observable, window, degree=3, n_boot=0, model=None, correction_degree=-1):
    """The collapse in one window (phi_min, phi_max, rate_max) fitted at every N of `model`
    (which may be None only when the groups hold one model): DataFrame N, points,
    chi2_per_dof, dof, errors (the method), and per parameter of scaling.EXPONENTS its value
    and <name>_error; a size whose fit fails (fewer than 3 rates in the window, no
    convergence) has its reason in `left_out`. With n_boot > 0 and >= 3 seeds at every point
    the errors are the bootstrap over seeds (the least-squares errors where it fails)."""
    flow = groups[groups["rate"] > 0]
    models = sorted(flow["model"].unique())
    if model is None and len(models) > 1:
        raise AnalysisError(f"the data hold models {', '.join(models)}: choose one (--model)")
    if model is not None:
        flow = flow[flow["model"] == model]
        if flow.empty:
            raise AnalysisError(f"model {model} has no flow curve here (models: {', '.join(models) or 'none'})")
    rows = [_fit_one_size(table, groups, observable, window, degree, n_boot, model, correction_degree, n)
            for n in sorted(flow["N"].unique())]
    return pd.DataFrame(rows)


def _fit_one_size(table, groups, observable, window, degree, n_boot, model, correction_degree, n):
    phi_min, phi_max, rate_max = window
    row = {"N": int(n), "points": 0, "chi2_per_dof": np.nan, "dof": 0, "errors": "", "left_out": ""}
    try:
        pts = scaling.collapse_points(groups, observable, N=n, phi_range=(phi_min, phi_max), rate_max=rate_max,
                                      model=model)
        if pts["rate"].nunique() < 3:
            raise AnalysisError(f"{pts['rate'].nunique()} rates in the window (a collapse needs 3)")
        fit = scaling.fit_collapse(pts, degree, correction_degree, observable=observable)
    except AnalysisError as e:
        row["left_out"] = str(e)
        return row
    method = "least squares (scaled by the residuals)"
    if n_boot > 0 and pts["seeds"].min() >= 3:
        rows_n = table[(table["N"] == n) & (table["phi"] >= phi_min) & (table["phi"] <= phi_max)
                       & (table["rate"] <= rate_max) & (table["rate"] > 0)]
        if model is not None:
            rows_n = rows_n[rows_n["model"] == model]
        try:
            fit = scaling.bootstrap_collapse(rows_n, observable, fit, n_boot)
            method = fit.method
        except AnalysisError as e:
            method += f" (bootstrap failed: {e})"
    row.update(points=len(fit.points), chi2_per_dof=fit.chi2_per_dof, dof=fit.dof, errors=method)
    for k in scaling.EXPONENTS:
        row[k], row[f"{k}_error"] = fit.values[k], fit.errors[k]
    return row


def size_trends(by_size, parameters=("phi_J", "q", "y", "beta")):
    """One Trend per parameter of collapse_by_size's table, against log2 N (slope per
    doubling of N)."""
    fitted = by_size[by_size["left_out"] == ""]
    if len(fitted) < 2:
        raise AnalysisError(f"the collapse was fitted at {len(fitted)} system size(s); a trend in N needs 2 or more"
                            + "".join(f"; N = {r.N}: {r.left_out}" for r in by_size.itertuples() if r.left_out))
    x = np.log2(fitted["N"].to_numpy(float))
    return [fit_trend(k, x, fitted[k], fitted[f"{k}_error"], PUBLISHED[k]) for k in parameters]


def newtonian_plateaus(groups, phi_j, N=None, model=None, observable="pressure", p_min=rheology.PLATEAU_P):
    """The Newtonian plateaus eta (rheology.plateau_values) below phi_j at one N (default:
    the size with the most of them, the largest of those): DataFrame N, phi, value, error
    sorted by phi. p_min: the plateau test's level (rheology.plateau_values)."""
    plateau = rheology.plateau_values(groups, observable, 1, phi_j, model, p_min)
    used = plateau[plateau["left_out"] == ""]
    if used.empty:
        below = plateau[~plateau["left_out"].str.startswith("phi >= phi_J")]
        example = below.iloc[-1] if len(below) else plateau.iloc[0]
        raise AnalysisError(f"none of the {len(below)} (N, phi) below phi_J = {phi_j:g} has a Newtonian plateau "
                            f"at its lowest rates (e.g. N = {int(example['N'])}, phi = {example['phi']:g}: "
                            f"{example['left_out']})")
    if N is None:
        N = rheology.size_with_most_plateaus(plateau)
    return used[used["N"] == N].sort_values("phi")[["N", "phi", "value", "error"]].reset_index(drop=True)


def effective_newtonian_exponents(plateaus, phi_j):
    """Local exponents between neighbouring phi of `plateaus`: beta_eff = -(ln eta2 - ln
    eta1) / (ln d2 - ln d1), d = phi_j - phi. DataFrame N, phi_J, phi_low, phi_high, distance
    (the geometric mean of the two d), beta_eff, beta_eff_error (each on its own;
    neighbouring ones share an eta, so their errors are correlated)."""
    phi, eta, err = (plateaus[c].to_numpy(float) for c in ("phi", "value", "error"))
    if len(phi) < 2:
        raise AnalysisError(f"{len(phi)} phi with a Newtonian plateau below phi_J = {phi_j:g}; local exponents need 2")
    d = phi_j - phi
    dl = np.diff(np.log(d))
    return pd.DataFrame(dict(N=int(plateaus["N"].iloc[0]), phi_J=phi_j, phi_low=phi[:-1], phi_high=phi[1:],
                             distance=np.sqrt(d[:-1] * d[1:]), beta_eff=-np.diff(np.log(eta)) / dl,
                             beta_eff_error=np.hypot(err[:-1] / eta[:-1], err[1:] / eta[1:]) / np.abs(dl)))


def newtonian_trend(plateaus, phi_j):
    """Trend of the local Newtonian exponent toward phi_j: ln eta = a + b u + c u^2 with
    u = -log2(phi_j - phi) (independent errors, unlike neighbouring beta_eff), so
    beta_eff(u) = (b + 2 c u) / ln 2 and its slope per halving of phi_j - phi is 2 c / ln 2;
    first and last: beta_eff at the farthest and nearest phi. Needs 3 phi."""
    u = -np.log2(phi_j - plateaus["phi"].to_numpy(float))
    eta, err = plateaus["value"].to_numpy(float), plateaus["error"].to_numpy(float)
    coef, cov, chi2, dof, u = _line("beta", u, np.log(eta), err / eta, degree=2)
    grad = lambda at: np.array([0.0, 1.0, 2.0 * at]) / np.log(2)  # noqa: E731 - d beta_eff / d coef
    first, last = (float(grad(at) @ coef) for at in (u.min(), u.max()))
    slope_grad = np.array([0.0, 0.0, 2.0]) / np.log(2)
    return Trend("beta", float(slope_grad @ coef), float(np.sqrt(slope_grad @ cov @ slope_grad)), chi2, dof,
                 PUBLISHED["beta"], first, last, float(np.sqrt(grad(u.max()) @ cov @ grad(u.max()))))


def newtonian_approach(groups, by_size=None, N=None, model=None, observable="pressure", p_min=rheology.PLATEAU_P):
    """The local Newtonian exponents and their trend at the published phi_J's two ends and,
    when by_size (collapse_by_size) has a fit at the plateaus' N, at that N's own phi_J; the N
    is chosen (newtonian_plateaus) with the published lower end. Returns the local exponents
    of every phi_J in one DataFrame (column phi_J) and a list of (label, phi_J, Trend or None,
    the reason when None)."""
    lo, hi = PUBLISHED["phi_J"]
    n = int(newtonian_plateaus(groups, lo, N, model, observable, p_min)["N"].iloc[0])
    choices = [("the published phi_J's lower end", lo), ("its upper end", hi)]
    if by_size is not None:
        own = by_size[(by_size["N"] == n) & (by_size["left_out"] == "")]
        if len(own):
            choices.append((f"the collapse's phi_J at N = {n}", float(own["phi_J"].iloc[0])))
    tables, results = [], []
    for label, phi_j in choices:
        try:
            plateaus = newtonian_plateaus(groups, phi_j, n, model, observable, p_min)
            tables.append(effective_newtonian_exponents(plateaus, phi_j))
            results.append((label, phi_j, newtonian_trend(plateaus, phi_j), ""))
        except AnalysisError as e:
            results.append((label, phi_j, None, str(e)))
    return (pd.concat(tables, ignore_index=True) if tables else pd.DataFrame()), results


def approach_statements(results):
    """One sentence per phi_J of newtonian_approach."""
    return [f"at {label} ({phi_j:.4f}): " + (statement(t, "halving of phi_J - phi", "the phi nearest phi_J")
                                              if t is not None else f"no trend ({why})")
            for label, phi_j, t, why in results]
