"""Critical scaling collapse in the (phi, rate) plane (thesis eqs. 5.2-5.8).

Model (ln of an observable O > 0, e.g. p or sigma, averaged over seeds):
    ln O = q ln(rate) + P(x) [+ ln(1 + rate^w Q(x))],   x = (phi - phi_J) / rate^(1/znu),
P a polynomial of degree K (ln of the scaling function), and, optionally, the leading
correction to scaling O = rate^q e^P(x) (1 + rate^w Q(x)) (eq. 5.8 with b = rate^(-1/z),
w = omega/z), Q a polynomial of degree Kc. Derived: y = q znu, beta = znu - y (the
Newtonian divergence O/rate ~ (phi_J - phi)^-beta below phi_J, eq. 5.4).

Several groups (e.g. models RD0 and CD0) can share phi_J, q and znu with a P (and Q) of
their own: the joint fit of compare_collapses.
"""
import dataclasses

import numpy as np
import pandas as pd
from scipy import stats as sps
from scipy.optimize import least_squares

from . import stats
from .errors import AnalysisError

EXPONENTS = ("phi_J", "q", "znu", "y", "beta")


@dataclasses.dataclass
class ScalingFit:
    """Result of a collapse fit. values/errors: phi_J, q, znu, y, beta (and w with the
    correction); errors are the fit's standard errors scaled by the residuals, times
    t sqrt(chi2/dof) (stats.residual_scale; with a bootstrap, bootstrap_collapse: its widened
    standard deviation where that is larger). theta: raw parameters [phi_J, q, 1/znu, P coefficients per
    group (low to high), (w, Q coefficients per group)]; points: the data fitted (phi,
    rate, value, error, group)."""
    observable: str
    degree: int
    correction_degree: int  # -1: no correction
    groups: list
    theta: np.ndarray
    covariance: np.ndarray
    chi2: float
    dof: int
    values: dict
    errors: dict
    points: pd.DataFrame
    method: str = "least squares"
    # With a bootstrap (bootstrap_collapse): the resampled parameters' standard deviations,
    # widened for the seeds' count, before the least-squares errors are taken where larger.
    bootstrap_errors: dict = None

    @property
    def chi2_per_dof(self):
        return self.chi2 / self.dof if self.dof > 0 else float("nan")

    def scaled_value(self, x, rate=None, group=None):
        """O / rate^q at scaling variable x (and rate, for the correction) for `group`."""
        layout = _Layout(self.degree, self.correction_degree, len(self.groups))
        g = self.groups.index(group) if group is not None else 0
        p = np.polyval(self.theta[layout.p_slice(g)][::-1], x)
        if layout.correction and rate is not None:
            w = self.theta[layout.w_index]
            p = p + np.log(np.maximum(1 + rate ** w * np.polyval(self.theta[layout.q_slice(g)][::-1], x), 1e-12))
        return np.exp(p)


@dataclasses.dataclass
class _Layout:
    """Where each parameter sits in theta."""
    degree: int
    correction_degree: int
    n_groups: int

    @property
    def correction(self):
        return self.correction_degree >= 0

    def p_slice(self, g):
        k = self.degree + 1
        return slice(3 + g * k, 3 + (g + 1) * k)

    @property
    def w_index(self):
        return 3 + self.n_groups * (self.degree + 1)

    def q_slice(self, g):
        k = self.correction_degree + 1
        start = self.w_index + 1 + g * k
        return slice(start, start + k)

    @property
    def size(self):
        n = 3 + self.n_groups * (self.degree + 1)
        return n + (1 + self.n_groups * (self.correction_degree + 1) if self.correction else 0)


def _model(theta, layout, phi, rate, group):
    phi_j, q, inv_znu = theta[:3]
    x = (phi - phi_j) / rate ** inv_znu
    out = q * np.log(rate)
    for g in range(layout.n_groups):
        s = group == g
        out[s] += np.polyval(theta[layout.p_slice(g)][::-1], x[s])
        if layout.correction:
            corr = rate[s] ** theta[layout.w_index] * np.polyval(theta[layout.q_slice(g)][::-1], x[s])
            out[s] += np.log(np.maximum(1 + corr, 1e-12))
    return out


def _derived(theta, cov):
    """values and errors of phi_J, q, znu, y, beta from theta[:3] and its covariance."""
    phi_j, q, inv = theta[:3]
    znu = 1.0 / inv
    values = {"phi_J": phi_j, "q": q, "znu": znu, "y": q * znu, "beta": znu * (1 - q)}
    grads = {"phi_J": [1, 0, 0], "q": [0, 1, 0], "znu": [0, 0, -znu ** 2],
             "y": [0, znu, -q * znu ** 2], "beta": [0, -znu, -(1 - q) * znu ** 2]}
    c = cov[:3, :3]
    errors = {k: float(np.sqrt(max(np.array(g) @ c @ np.array(g), 0.0))) for k, g in grads.items()}
    return {k: float(v) for k, v in values.items()}, errors


def _prepare(points):
    need = {"phi", "rate", "value", "error"}
    if not need <= set(points.columns):
        raise AnalysisError(f"collapse points need the columns {sorted(need)}")
    pts = points[(points["value"] > 0) & (points["error"] > 0) & (points["rate"] > 0)].copy()
    if "group" not in pts:
        pts["group"] = ""
    return pts


def fit_collapse(points, degree=3, correction_degree=-1, start=(0.843, 0.28, 3.5),
                 observable="pressure", multistart=True):
    """Weighted least-squares collapse of `points` (DataFrame: phi, rate, value, error and
    optionally group). degree: K of P; correction_degree: Kc of Q (-1: no correction).
    start: (phi_J, q, znu) start values; with multistart, phi_J and znu are also started on
    a small grid and the lowest chi2 kept. Raises AnalysisError when the data cannot
    determine the fit (fewer than 3 rates or not more points than parameters)."""
    pts = _prepare(points)
    groups = sorted(pts["group"].unique())
    layout = _Layout(degree, correction_degree, len(groups))
    phi, rate = pts["phi"].to_numpy(float), pts["rate"].to_numpy(float)
    ln_o = np.log(pts["value"].to_numpy(float))
    err = pts["error"].to_numpy(float) / pts["value"].to_numpy(float)
    gid = np.array([groups.index(g) for g in pts["group"]])
    rates = np.unique(rate)
    if len(rates) < 3:
        raise AnalysisError(f"a collapse needs at least 3 shear rates with data; the window has "
                            f"{len(rates)} ({', '.join(f'{r:g}' for r in rates) or 'none'})")
    if len(pts) <= layout.size:
        raise AnalysisError(f"{len(pts)} (phi, rate) points in the window: a collapse with "
                            f"degree {degree}{' and a correction' if layout.correction else ''} "
                            f"needs more than {layout.size}")

    def residuals(theta):
        return (ln_o - _model(theta, layout, phi, rate, gid)) / err

    def initial(phi_j, q, znu, w):
        theta = np.zeros(layout.size)
        theta[:3] = phi_j, q, 1.0 / znu
        x = (phi - phi_j) / rate ** (1.0 / znu)
        for g in range(len(groups)):
            s = gid == g
            k = min(degree, max(len(np.unique(x[s])) - 1, 0))
            coef = np.polyfit(x[s], ln_o[s] - q * np.log(rate[s]), k, w=1 / err[s])[::-1]
            theta[layout.p_slice(g)][: k + 1] = coef
        if layout.correction:
            theta[layout.w_index] = w
        return theta

    phi_j0, q0, znu0 = start
    starts = [(phi_j0, q0, znu0)]
    if multistart:
        span = np.ptp(phi) if np.ptp(phi) > 0 else 0.01
        starts += [(phi_j0 + d * span, q0, z) for d in (-0.15, 0.0, 0.15) for z in (2.5, 3.5, 5.0)]
    ws = (0.3, 0.7) if layout.correction else (0.0,)
    best = None
    for s in starts:
        for w in ws:
            try:
                res = least_squares(residuals, initial(*s, w), method="lm", x_scale="jac", max_nfev=4000)
            except (ValueError, np.linalg.LinAlgError):
                continue
            if np.all(np.isfinite(res.fun)) and (best is None or res.cost < best.cost):
                best = res
    if best is None:
        raise AnalysisError("the collapse fit did not converge from any start value")
    chi2 = float(np.sum(best.fun ** 2))
    dof = len(pts) - layout.size
    cov = np.linalg.pinv(best.jac.T @ best.jac) * stats.residual_scale(chi2, dof)
    values, errors = _derived(best.x, cov)
    if layout.correction:
        values["w"] = float(best.x[layout.w_index])
        errors["w"] = float(np.sqrt(max(cov[layout.w_index, layout.w_index], 0.0)))
    return ScalingFit(observable, degree, correction_degree, groups, best.x, cov, chi2, dof,
                      values, errors, pts.reset_index(drop=True))


def collapse_points(groups, observable, N=None, phi_range=(-np.inf, np.inf), rate_max=np.inf,
                    min_seeds=2, model=None):
    """The (phi, rate) points of one N (default: the largest) from group_averages output:
    DataFrame phi, rate, value, error (the fit weights, stats.fit_errors), seeds, group
    (= model). Points with fewer than min_seeds seeds (no error estimate) are left out."""
    g = groups[groups["rate"] > 0]
    if model is not None:
        g = g[g["model"] == model]
    if g.empty:
        raise AnalysisError("no replica with rate > 0: a collapse needs sheared flow curves")
    sizes = sorted(g["N"].unique())
    n = sizes[-1] if N is None else N
    if n not in sizes:
        raise AnalysisError(f"N = {n} is not in the data (sizes: {', '.join(str(int(s)) for s in sizes)})")
    sized = g[g["N"] == n]
    in_window = sized[(sized["phi"] >= phi_range[0]) & (sized["phi"] <= phi_range[1]) & (sized["rate"] <= rate_max)]
    g = in_window[in_window["seeds"] >= min_seeds]
    if g.empty:
        window = f"{phi_range[0]:g} <= phi <= {phi_range[1]:g}, rate <= {rate_max:g}"
        found = (f"{len(in_window)} point(s) there, with at most {int(in_window['seeds'].max())} seed(s)"
                 if len(in_window) else "the data of that N have phi " +
                 f"{sized['phi'].min():g} to {sized['phi'].max():g} and rate {sized['rate'].min():g} to {sized['rate'].max():g}")
        raise AnalysisError(f"no (phi, rate) point of N = {int(n)} with at least {min_seeds} seeds in the window "
                            f"{window} ({found})")
    return pd.DataFrame({"phi": g["phi"], "rate": g["rate"], "value": g[observable],
                         "error": stats.fit_errors(g, observable), "seeds": g["seeds"],
                         "group": g["model"] if "model" in g else ""}).reset_index(drop=True)


def bootstrap_collapse(replica_table, observable, fit, n_boot=200, seed=1):
    """Bootstrap over seeds: resample the replicas of every (group, phi, rate) point of
    `fit` with replacement, refit from fit's values (weights kept), and return a copy of
    fit whose errors are the standard deviations of the resampled parameters, widened by
    sqrt(k/(k - 1)) (a resampled mean of k seeds varies by (k - 1)/k of the mean's variance:
    k the mean of k/(k - 1) over the points), and never below fit's own errors (the
    least-squares errors scaled by the residuals, which also hold a misfit that resampling
    the seeds does not: a bootstrap of 3 seeds gave phi_J +- 0.017 where those gave 0.032)."""
    rng = np.random.default_rng(seed)
    pts = fit.points
    groups_of = {}
    tab = replica_table
    if "left_out" in tab.columns:
        tab = tab[tab["left_out"] == ""]
    for i, p in pts.iterrows():
        sel = (np.isclose(tab["phi"], p["phi"])) & (np.isclose(tab["rate"], p["rate"]))
        if "model" in tab and p["group"] != "":
            sel &= tab["model"] == p["group"]
        if "N" in tab and "N" in p:
            sel &= tab["N"] == p["N"]
        groups_of[i] = tab.loc[sel, observable].to_numpy(float)
    start = (fit.values["phi_J"], fit.values["q"], fit.values["znu"])
    samples = []
    for _ in range(n_boot):
        resampled = pts.copy()
        resampled["value"] = [rng.choice(v, len(v)).mean() if len(v) else p
                              for v, p in zip(groups_of.values(), pts["value"])]
        try:
            f = fit_collapse(resampled, fit.degree, fit.correction_degree, start, fit.observable,
                             multistart=False)
        except AnalysisError:
            continue
        samples.append([f.values[k] for k in fit.values])
    if len(samples) < max(10, n_boot // 2):
        raise AnalysisError(f"only {len(samples)} of {n_boot} bootstrap fits converged")
    samples = np.array(samples)
    seeds = np.array([len(v) for v in groups_of.values() if len(v) >= 2], float)
    widen = float(np.sqrt(np.mean(seeds / (seeds - 1)))) if len(seeds) else 1.0
    out = dataclasses.replace(fit, method=f"bootstrap over seeds ({len(samples)} resamples, widened by "
                                          f"{widen:.3g} for the seeds' count), or least squares where larger")
    out.bootstrap_errors = {k: widen * float(np.std(samples[:, j], ddof=1)) for j, k in enumerate(fit.values)}
    out.errors = {k: max(out.bootstrap_errors[k], fit.errors[k]) for k in fit.values}
    return out


@dataclasses.dataclass
class CollapseComparison:
    """Joint fit (shared phi_J, q, znu; own scaling functions) against separate fits.
    f_statistic = ((chi2_joint - chi2_separate) / extra_dof) / (chi2_separate / dof_separate),
    p_value from the F distribution; same_criticality: p_value >= alpha. The test takes the
    point errors as known: errors estimated from few seeds make it anticonservative (use
    many seeds per point, or compare the separate fits' exponents with bootstrap errors)."""
    joint: ScalingFit
    separate: dict
    chi2_separate: float
    dof_separate: int
    f_statistic: float
    p_value: float
    alpha: float

    @property
    def same_criticality(self):
        return self.p_value >= self.alpha

    def statement(self):
        names = " and ".join(self.separate)
        if self.same_criticality:
            return (f"{names}: a joint collapse with one phi_J, q and znu is as good as separate ones "
                    f"(F = {self.f_statistic:.2f}, p = {self.p_value:.3g}): the data support the same criticality.")
        return (f"{names}: separate collapses fit significantly better than a joint one "
                f"(F = {self.f_statistic:.2f}, p = {self.p_value:.3g}): the data do not support the same criticality.")


def compare_collapses(points, degree=3, correction_degree=-1, start=(0.843, 0.28, 3.5),
                      observable="pressure", alpha=0.05):
    """Joint against separate collapses of the groups in points["group"] (>= 2 groups)."""
    pts = _prepare(points)
    names = sorted(pts["group"].unique())
    if len(names) < 2:
        raise AnalysisError(f"a joint collapse needs two models; the data hold {names or 'none'}")
    separate = {g: fit_collapse(pts[pts["group"] == g], degree, correction_degree, start, observable)
                for g in names}
    joint = fit_collapse(pts, degree, correction_degree, start, observable)
    chi2_sep = sum(f.chi2 for f in separate.values())
    dof_sep = sum(f.dof for f in separate.values())
    extra = joint.dof - dof_sep
    f_stat = max(joint.chi2 - chi2_sep, 0.0) / extra / (chi2_sep / dof_sep)
    p = float(sps.f.sf(f_stat, extra, dof_sep))
    return CollapseComparison(joint, separate, chi2_sep, dof_sep, float(f_stat), p, alpha)


@dataclasses.dataclass
class WindowChoice:
    """The collapse window chosen by choose_window: phi_min, phi_max, rate_max; the fit in it;
    p_value = P(chi2 >= the fit's chi2 | dof) (scipy.stats.chi2.sf); acceptable: p_value >=
    the level; tried: DataFrame of every window fitted (phi_min, phi_max, rate_max, points,
    chi2_per_dof, p_value, phi_J)."""
    phi_min: float
    phi_max: float
    rate_max: float
    fit: ScalingFit
    p_value: float
    acceptable: bool
    level: float
    tried: pd.DataFrame

    def describe(self):
        verdict = (f"acceptable at the {self.level:g} level" if self.acceptable else
                   f"no window acceptable at the {self.level:g} level: the best p-value")
        return (f"phi {self.phi_min:g}..{self.phi_max:g}, rate <= {self.rate_max:g} "
                f"({len(self.fit.points)} points, chi2/dof = {self.fit.chi2_per_dof:.2f}, "
                f"p = {self.p_value:.3g}: {verdict}; {len(self.tried)} windows tried)")


def choose_window(points, degree=3, correction_degree=-1, start=(0.843, 0.28, 3.5),
                  observable="pressure", level=0.05, min_rates=3, min_phis=3, max_fits=400):
    """The critical window of a collapse, chosen from the data (the practice of Olsson and
    Teitel: shrink the window around phi_J towards low rates until the scaling fits).

    points: collapse_points output (every point; the window is chosen here). Candidate
    windows: every contiguous range of the phi values with at least `min_phis` of them,
    times rate_max over the distinct rates (the highest dropped first, at least `min_rates`
    left); when there are more than `max_fits`, every k-th range (evenly thinned). Each is
    fitted. A window is acceptable when its fit's chi2 p-value is >= `level` and its fitted
    phi_J lies inside it (both branches of the collapse). The chosen window has the most
    points among the acceptable ones (ties: the wider phi range, then the higher rate_max);
    when none is acceptable, the one with the best p-value, flagged. Raises AnalysisError
    when no window can be fitted."""
    from scipy.stats import chi2 as chi2_distribution

    pts = _prepare(points)
    rates = np.sort(pts["rate"].unique())[::-1]
    if len(rates) < min_rates:
        raise AnalysisError(f"a collapse needs at least {min_rates} shear rates with data; the data have {len(rates)}")
    phis = np.unique(pts["phi"])
    if len(phis) < min_phis:
        raise AnalysisError(f"{len(phis)} phi values in the data: a window needs at least {min_phis}")
    ranges = [(float(phis[a]), float(phis[b])) for a in range(len(phis)) for b in range(a + min_phis - 1, len(phis))]
    windows = [(lo, hi, float(r)) for r in rates[: len(rates) - min_rates + 1] for lo, hi in ranges]
    if len(windows) > max_fits:
        windows = [windows[k] for k in np.unique(np.linspace(0, len(windows) - 1, max_fits).round().astype(int))]
    # Each window's fit starts from the fit to every point (one multistart fit, not one per
    # window: the windows' fits take a few Levenberg-Marquardt runs each).
    try:
        whole = fit_collapse(pts, degree, correction_degree, start, observable)
        first = (whole.values["phi_J"], whole.values["q"], whole.values["znu"])
        if not (np.isfinite(first).all() and first[2] > 0):
            first = start
    except AnalysisError:
        first = start
    tried, fits = [], {}
    for lo, hi, rate_max in windows:
        sub = pts[(pts["phi"] >= lo) & (pts["phi"] <= hi) & (pts["rate"] <= rate_max)]
        try:
            fit = fit_collapse(sub, degree, correction_degree, first, observable, multistart=False)
            if first != tuple(start):  # and from the caller's start, keeping the better
                other = fit_collapse(sub, degree, correction_degree, start, observable, multistart=False)
                fit = other if other.chi2 < fit.chi2 else fit
        except AnalysisError:
            continue
        p = float(chi2_distribution.sf(fit.chi2, fit.dof))
        fits[(lo, hi, rate_max)] = (fit, p)
        tried.append(dict(phi_min=lo, phi_max=hi, rate_max=rate_max, points=len(sub),
                          chi2_per_dof=fit.chi2_per_dof, p_value=p, phi_J=fit.values["phi_J"]))
    if not fits:
        raise AnalysisError("no candidate window could be fitted (too few points or rates in each)")
    good = [k for k, (fit, p) in fits.items() if p >= level and k[0] < fit.values["phi_J"] < k[1]]
    if good:
        chosen = max(good, key=lambda k: (len(fits[k][0].points), k[1] - k[0], k[2]))
    else:
        chosen = max(fits, key=lambda k: fits[k][1])
    fit, p = fits[chosen]
    return WindowChoice(chosen[0], chosen[1], chosen[2], fit, p, bool(good), level, pd.DataFrame(tried))
