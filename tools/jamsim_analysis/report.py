"""One report per archive: the analyses that fit the campaign's models and sweep, written
as PNG figures plus report.md and report.html in an output directory.

Dynamics (RD0, CD0, RD0T, RD, CD, CDn, CDt): steady averages per (model, N, phi, rate),
replicas left out and why, flow curves; with two or more models, their averages compared at
the state points they share (any number of rates: a difference, its error in sigmas and a
Welch t, or t of the time errors for one seed); per model with >= 3 rates the collapse of p and sigma in the window
chosen from the data (bootstrap over seeds when every point has >= 3 seeds), then the fit
to every point, marked when its chi2 rejects it; the Newtonian divergence (overdamped
models) or the Bagnold analysis (massive models), at the size with the most phi at their
plateau; the joint collapse of RD0 and CD0 when both are present; for harmonic RD0 and CD0
with two or more sizes, the collapse's window fitted at each N and whether the values move
toward the published ones as N grows, and the local Newtonian exponents toward phi_J;
g_y(x) and its minimum; a picture of a final configuration; with configuration frames
([run] frame_interval), psi6 over strain and an animation.
Static (RAND, COOL, COMPRESS, COOL_COMPRESS, SHEARED): P_J(phi, N), thresholds per N,
finite-size scaling with >= 3 sizes, pressure distributions, a picture of a jammed state.
QS: averages per (N, phi) and a picture.
An analysis that cannot run is listed with its reason; the report is an error (exit 2) only
when no analysis at all could run (no finished replica, every replica left out).
"""
import dataclasses
import os

import numpy as np
import pandas as pd

from . import comparison, correlations, figures, jamming, order, pictures, rheology, scaling, stats, trends
from .archive import open_archives
from .document import Document
from .errors import AnalysisError

OVERDAMPED = ("RD0", "CD0", "RD0T")
MASSIVE = ("RD", "CD", "CDn", "CDt")
OBSERVABLES = ("pressure", "shear_stress")
# Largest N drawn in a picture (the pair search is O(N^2)).
PICTURE_MAX_N = 16384


@dataclasses.dataclass
class ReportOptions:
    """degree: of ln F; correction: leading correction to scaling in the collapse;
    n_boot: bootstrap resamples (0: none); N: system size for fits (default: the largest; the
    Newtonian and Bagnold fits: the size with the most phi at their plateau);
    phi_min, phi_max, rate_max: the collapse's window (default: every point), for fits
    restricted to the critical region; auto_window (the default when no window is given):
    choose the window of each collapse from the data (scaling.choose_window; the RD0/CD0
    joint collapse uses RD0's pressure window), shown first, and the fit to every point
    after it, marked when its chi2 rejects it."""
    degree: int = 3
    correction: bool = False
    n_boot: int = 100
    N: int = None
    phi_min: float = -np.inf
    phi_max: float = np.inf
    rate_max: float = np.inf
    auto_window: bool = True


# A fit is flagged when its chi2 is this improbable in either tail (chi2/dof far from 1).
FLAG_P = 0.01
ADVICE = ("try the collapse window chosen from the data (--auto-window), more seeds per point "
          "(error bars from the spread between seeds need several), or lower rates (closer to the "
          "scaling regime)")


def fit_quality(chi2, dof):
    """(p-value P(chi2' >= chi2), flag): flag is "" for an acceptable fit, else says whether
    chi2/dof is too large (p < FLAG_P: model or error bars wrong) or too small (P(chi2' <=
    chi2) < FLAG_P: error bars too large)."""
    from scipy.stats import chi2 as dist

    if chi2 is None or not dof or not np.isfinite(chi2):
        return np.nan, ""
    p = float(dist.sf(chi2, dof))
    if p < FLAG_P:
        return p, f"chi2/dof = {chi2 / dof:.3g} too large (p = {p:.2g})"
    if dist.cdf(chi2, dof) < FLAG_P:
        return p, f"chi2/dof = {chi2 / dof:.3g} too small (p(below) = {dist.cdf(chi2, dof):.2g})"
    return p, ""


def fit_rows(name, values, errors, chi2=None, dof=None, extra="", scaled=True):
    """Table rows (one per parameter) of a fit. scaled: True when the errors already include
    the factor sqrt(max(1, chi2/dof)) (least-squares fits here), "residuals" when they are
    scaled by the residuals, t sqrt(chi2/dof) (stats.residual_scale: the fits to seed
    averages), False for errors without either (e.g. a bootstrap). A fit flagged by
    fit_quality with chi2/dof > 1 also gets error_inflated = the plain error times
    sqrt(chi2/dof) (for "residuals", the error itself: it carries that factor already)."""
    p, flag = fit_quality(chi2, dof)
    factor = np.sqrt(chi2 / dof) if flag and chi2 > dof else np.nan
    if scaled == "residuals":
        factor = 1.0 if np.isfinite(factor) else np.nan
        done = 1.0
    else:
        done = np.sqrt(max(1.0, chi2 / dof)) if scaled and np.isfinite(factor) else 1.0
    rows = [dict(analysis=name, parameter=k, value=v, error=errors.get(k, np.nan),
                 chi2_per_dof=(chi2 / dof if dof else np.nan) if chi2 is not None else np.nan,
                 dof=dof if dof is not None else "", note=extra, p_value=p,
                 error_inflated=errors.get(k, np.nan) / done * factor, flag=flag) for k, v in values.items()]
    return rows


class Report:
    """Collects sections, fitted values and skipped analyses, then writes the files."""

    def __init__(self, title, outdir):
        self.doc = Document(title)
        self.outdir = outdir
        self.fits = []
        self.skipped = []
        self.ran = []  # the analyses that produced a section
        self.windows = {}  # (model, observable) -> (phi_min, phi_max, rate_max) chosen from the data
        try:
            os.makedirs(outdir, exist_ok=True)
        except OSError as e:
            raise AnalysisError(f"cannot create OUTDIR '{outdir}': {e.strerror}") from None

    def path(self, name):
        return os.path.join(self.outdir, name)

    def attempt(self, name, func):
        """Run one analysis; an AnalysisError becomes a skipped entry."""
        place = len(self.ran)  # before the analyses it runs itself
        try:
            func()
            self.ran.insert(place, name)
        except AnalysisError as e:
            self.skipped.append(dict(analysis=name, reason=str(e)))
        except Exception as e:  # noqa: BLE001 - one failed analysis must not stop the report
            self.skipped.append(dict(analysis=name, reason=f"failed: {type(e).__name__}: {e}"))

    def write(self):
        d = self.doc
        body = len(d.blocks)
        d.heading("Analyses run")
        d.paragraph("; ".join(self.ran) if self.ran else "none")
        d.heading("Fitted values")
        if self.fits:
            table = pd.DataFrame(self.fits)
            d.table(table)
            flagged = table[table["flag"] != ""].drop_duplicates("analysis")
            if len(flagged):
                d.paragraph(f"Flagged fits (chi2 p-value below {FLAG_P:g} in either tail): "
                            + "; ".join(f"{r.analysis}: {r.flag}" for r in flagged.itertuples())
                            + ". Their errors are also given inflated by sqrt(chi2/dof) (error_inflated) "
                            "where chi2/dof > 1; a fit this far from its error bars is not to be quoted as it "
                            f"stands: {ADVICE}.")
            else:
                d.paragraph(f"Every fit's chi2/dof is consistent with 1 (p-value >= {FLAG_P:g} in both tails).")
        else:
            d.paragraph("No fit could run on this archive.")
        d.heading("Analyses not run")
        d.table(pd.DataFrame(self.skipped or [dict(analysis="-", reason="every analysis ran")]))
        # the summary first: move the sections just added after the first paragraph (files)
        head = 1 if body and d.blocks[0][0] == "p" else 0
        d.blocks = d.blocks[:head] + d.blocks[body:] + d.blocks[head:body]
        with open(self.path("report.md"), "w") as f:
            f.write(d.markdown())
        with open(self.path("report.html"), "w") as f:
            f.write(d.html())


def _dynamics(rep, archive, opts):
    table = stats.replica_averages(archive, list(OBSERVABLES))
    left = table[table["left_out"] != ""]
    d = rep.doc
    d.heading("Steady-state averages")
    d.paragraph("Each replica's window starts at its declared transient plus an MSER-5 truncation (the "
                "start within the first quarter that minimises the standard error of the remaining mean); a "
                f"replica whose first and last thirds then differ by more than {stats.DRIFT_Z} standard errors "
                "(from the integrated autocorrelation time; Student's t of the same tail probability for the "
                "dof of that error, drift_limit) drifts and is left out. A replica's time error comes from its "
                "integrated autocorrelation time, corrected for the sample mean, with its dof (<obs>_dof). "
                "Averages per (model, N, phi, rate): mean over seeds; error = the seeds' time errors combined "
                "with the spread between seeds beyond them, widened by Student's t for few seeds "
                "(stats.seed_average; never below the time errors). With one seed it is that seed's time error "
                "times Student's t for its dof, which misses the spread between seeds.")
    if note := stats.weak_drift_note(table):
        d.paragraph(note[len("note: "):])
    d.paragraph(f"Replicas left out: {len(left)} of {len(table)}.")
    if len(left):
        d.table(left[["replica", "model", "N", "phi", "rate", "seed", "left_out"]])
    kept = table[table["left_out"] == ""]
    if kept.empty:
        reasons = [f"replica {int(r)}: {why}" for r, why in zip(left["replica"], left["left_out"])]
        more = f"; and {len(reasons) - 5} more" if len(reasons) > 5 else ""
        raise AnalysisError("every replica was left out (" + "; ".join(reasons[:5]) + more + ")")
    d.table(kept[["replica", "model", "N", "phi", "rate", "seed", "window_start", "samples",
                  "pressure", "pressure_error", "pressure_tau", "drift_z", "drift_limit"]])
    groups = stats.group_averages(table, list(OBSERVABLES))
    d.table(groups[["model", "N", "phi", "rate", "seeds", "pressure", "pressure_error",
                    "shear_stress", "shear_stress_error"]])
    for o in OBSERVABLES:
        figures.flow_curves(groups, o, rep.path(f"flow_{o}.png"))
        d.figure(f"flow_{o}.png", f"{o}/rate against phi")
    rep.ran.append("steady-state averages")
    if groups["model"].nunique() >= 2:
        rep.attempt("steady-state averages compared between models",
                    lambda: _compare_averages(rep, table, groups))
    phi_j = {}
    for model in sorted(groups["model"].unique()):
        for o in OBSERVABLES:
            rep.attempt(f"collapse {model} {o}", lambda m=model, o=o: _collapse(rep, table, groups, m, o, opts, phi_j))
        if model in OVERDAMPED:
            rep.attempt(f"Newtonian divergence {model}",
                        lambda m=model: _divergence(rep, groups, m, 1, phi_j.get(m), opts))
        elif model in MASSIVE:
            rep.attempt(f"Bagnold analysis {model}",
                        lambda m=model: _divergence(rep, groups, m, 2, phi_j.get(m), opts))
        if model in ("RD0", "CD0") and _harmonic(archive, model) and \
                groups.loc[(groups["model"] == model) & (groups["rate"] > 0), "N"].nunique() >= 2:
            rep.attempt(f"fitted values by system size {model}",
                        lambda m=model: _size_trends(rep, table, groups, m, opts))
    models = set(groups["model"]) & {"RD0", "CD0"}
    if len(models) == 2:
        rep.attempt("RD0 against CD0: joint collapse", lambda: _compare(rep, groups, opts))
    rep.attempt("velocity correlations", lambda: _correlations(rep, archive, table))
    rep.attempt("configuration picture", lambda: _picture(rep, archive, kept))
    if any(archive.has_frames(int(r)) for r in archive.done()["replica"]):
        rep.attempt("bond-orientational order", lambda: _order(rep, archive))


def _harmonic(archive, model):
    """Whether the model's replicas use the harmonic potential (alpha = 2; Paper II's values)."""
    r = archive.replicas
    if "alpha" not in r:
        return True
    return bool(np.all(r.loc[r["model"] == model, "alpha"].fillna(2.0) == 2.0))


def _size_trends(rep, table, groups, model, opts):
    """The pressure collapse's window fitted at every N and each value's trend in N; the
    local Newtonian exponents and their trend toward phi_J (trends.newtonian_approach)."""
    window = rep.windows.get((model, "pressure"), (opts.phi_min, opts.phi_max, opts.rate_max))
    by_size = trends.collapse_by_size(table, groups, "pressure", window, opts.degree, opts.n_boot, model,
                                      0 if opts.correction else -1)
    found = trends.size_trends(by_size)
    d = rep.doc
    d.heading(f"Fitted values by system size: {model}")
    shown = "every point" if not np.isfinite(window).any() else (
        f"phi {window[0]:g}..{window[1]:g}, rate <= {window[2]:g}")
    d.paragraph(f"The pressure collapse in one window ({shown}) fitted at each N; a trend is the slope of a "
                "weighted straight line against log2 N (its error widened by sqrt(chi2/dof) when that exceeds 1; "
                f"with 3 sizes that check has 1 degree of freedom), counted when {trends.TREND_Z:g} errors from 0, "
                "and judged by the line's ends against Paper II's values (N = 65536, harmonic RD0). Finite size "
                "predicts that they move toward the published ones.")
    d.table(by_size)
    d.paragraph(" ".join(s + "." for s in trends.size_statements(by_size, found)))
    local = pd.DataFrame()
    try:
        local, approach = trends.newtonian_approach(groups, by_size, opts.N, model)
        d.paragraph("Local Newtonian exponents beta_eff = -d ln eta / d ln(phi_J - phi) between neighbouring phi "
                    "with a Newtonian plateau (farther from phi_J the effective exponent is expected below the "
                    "asymptotic one). They depend on phi_J, so each is given at three: the published range's ends "
                    "and the collapse's own phi_J at this N. The trend comes from ln eta = a + b u + c u^2, "
                    "u = -log2(phi_J - phi), per halving of phi_J - phi:")
        d.table(local)
        d.paragraph(" ".join(s + "." for s in trends.approach_statements(approach)))
    except AnalysisError as e:
        d.paragraph(f"Local Newtonian exponents: not computed ({e}).")
    figures.trends_figure(by_size, found, local, rep.path(f"sizes_{model}.png"))
    d.figure(f"sizes_{model}.png", f"collapse values against N ({model}), the published range shaded; "
             "local Newtonian exponents")


def _window_text(pts, n, opts):
    return (f"N = {n}, phi {pts['phi'].min():g}..{pts['phi'].max():g}, rate {pts['rate'].min():g}.."
            f"{pts['rate'].max():g}, {len(pts)} points, degree {opts.degree}"
            + (", with correction" if opts.correction else ""))


def _explicit_window(opts):
    return bool(np.isfinite(opts.phi_min) or np.isfinite(opts.phi_max) or np.isfinite(opts.rate_max))


def _collapse(rep, table, groups, model, observable, opts, phi_j):
    """The collapse of one model and observable. Without a window given by hand (and with
    auto_window) the window chosen from the data comes first, with the bootstrap; the fit to
    every point follows when it is another window, marked when its chi2 rejects it."""
    phi_min, phi_max, rate_max = opts.phi_min, opts.phi_max, opts.rate_max
    choice, no_choice = None, ""
    if opts.auto_window and not _explicit_window(opts):
        every = scaling.collapse_points(groups, observable, N=opts.N, model=model)
        every["group"] = model
        try:
            choice = scaling.choose_window(every, opts.degree, 0 if opts.correction else -1, observable=observable)
        except AnalysisError as e:
            no_choice = str(e)
        if choice is not None:
            phi_min, phi_max, rate_max = choice.phi_min, choice.phi_max, choice.rate_max
            rep.windows[(model, observable)] = (phi_min, phi_max, rate_max)
    pts = scaling.collapse_points(groups, observable, N=opts.N, model=model,
                                  phi_range=(phi_min, phi_max), rate_max=rate_max)
    pts["group"] = model
    fit = scaling.fit_collapse(pts, opts.degree, 0 if opts.correction else -1, observable=observable)
    method = "least squares"
    n = int(groups.loc[groups["model"] == model, "N"].max()) if opts.N is None else opts.N
    if opts.n_boot > 0 and pts["seeds"].min() >= 3:
        rows = table[(table["model"] == model) & (table["N"] == n) & (table["phi"] >= phi_min)
                     & (table["phi"] <= phi_max) & (table["rate"] <= rate_max)]
        fit = scaling.bootstrap_collapse(rows, observable, fit, opts.n_boot)
        method = fit.method
    name = f"collapse {model} {observable}"
    window = _window_text(pts, n, opts)
    kind = ("window chosen from the data" if choice is not None else
            "window given" if _explicit_window(opts) else "every point (full window)")
    rep.fits += fit_rows(name, fit.values, fit.errors, fit.chi2, fit.dof, f"{window}; {kind}; errors: {method}",
                         scaled="residuals")  # a bootstrap's errors are never below the scaled ones
    if observable == "pressure":
        phi_j[model] = fit.values["phi_J"]
    fname = f"collapse_{model}_{observable}.png"
    p, flag = fit_quality(fit.chi2, fit.dof)
    figures.collapse_figure(fit, rep.path(fname), label=f"{model} {observable}, {kind}: {window}",
                            failed=bool(flag) and p < FLAG_P)
    rep.doc.heading(f"Scaling collapse: {model}, {observable}")
    rep.doc.paragraph(f"Window ({kind}): {window}. Errors: {method}. chi2/dof = {fit.chi2_per_dof:.2f} ({fit.dof} dof, "
                      f"p = {p:.3g})." + (f" FLAGGED: {flag}; the errors inflated by sqrt(chi2/dof) are in the "
                                         f"table of fitted values; {ADVICE}." if flag else ""))
    if choice is not None:
        rep.doc.paragraph(f"Window chosen from the data (--auto-window): {choice.describe()}. The largest "
                          f"window whose fit has a chi2 p-value >= {choice.level:g} and its phi_J inside it; "
                          "the windows tried:")
        rep.doc.table(choice.tried.sort_values(["points", "p_value"], ascending=False).head(15))
    elif no_choice:
        rep.doc.paragraph(f"No window could be chosen from the data ({no_choice}): every point is fitted.")
    rep.doc.figure(fname, f"collapse of {observable} ({model}), {kind}")
    if choice is not None:
        every = scaling.collapse_points(groups, observable, N=opts.N, model=model)
        if len(every) > len(pts):
            rep.attempt(f"{name} (full window)", lambda: _full_window(rep, every, model, observable, opts, n))


def _full_window(rep, pts, model, observable, opts, n):
    """The fit to every point (pts), after the chosen window's when that is smaller, marked
    REJECTED when its chi2 p-value is below FLAG_P."""
    pts["group"] = model
    fit = scaling.fit_collapse(pts, opts.degree, 0 if opts.correction else -1, observable=observable)
    window = _window_text(pts, n, opts)
    p, flag = fit_quality(fit.chi2, fit.dof)
    rejected = bool(flag) and p < FLAG_P
    name = f"collapse {model} {observable} (full window)"
    rep.fits += fit_rows(name, fit.values, fit.errors, fit.chi2, fit.dof,
                         f"{window}; every point; errors: least squares" + ("; REJECTED" if rejected else ""),
                         scaled="residuals")
    fname = f"collapse_{model}_{observable}_full.png"
    figures.collapse_figure(fit, rep.path(fname), label=f"{model} {observable}, every point: {window}",
                            failed=rejected)
    rep.doc.heading(f"Scaling collapse: {model}, {observable}, every point" + (" (REJECTED)" if rejected else ""), 3)
    rep.doc.paragraph(f"For comparison, the fit to every point ({window}): chi2/dof = {fit.chi2_per_dof:.2f} "
                      f"({fit.dof} dof, p = {p:.3g})."
                      + (f" REJECTED: {flag}; the scaling form does not describe the points outside the "
                         "window chosen above, and its values are not to be quoted." if rejected else
                         (f" FLAGGED: {flag}." if flag else " Acceptable, but the window above is the one chosen.")))
    rep.doc.figure(fname, f"collapse of {observable} ({model}), every point"
                   + (": rejected by its chi2" if rejected else ""))


def _divergence(rep, groups, model, power, phi_j, opts):
    kind = "Newtonian" if power == 1 else "Bagnold"
    func = rheology.newtonian_divergence if power == 1 else rheology.bagnold_analysis
    slopes = rheology.local_slopes(groups[groups["model"] == model], "pressure")
    rep.doc.heading(f"{kind} rheology: {model}")
    if len(slopes):
        rep.doc.paragraph("Local slopes d ln p / d ln rate and their regime:")
        rep.doc.table(slopes)
    plateau, fit = func(groups, "pressure", phi_j=phi_j, N=opts.N, model=model,
                        correction=(power == 2))
    rep.doc.table(plateau)
    n = int(plateau["N"].iloc[0])
    collapse_n = int(groups.loc[groups["model"] == model, "N"].max()) if opts.N is None else opts.N
    note = (f"N = {n}" + ("" if opts.N else " (the size with the most plateaus)") + "; phi_J "
            + (f"from the collapse (N = {collapse_n})" if phi_j is not None else "fitted")
            + f"; points: {len(fit.points)}")
    rep.fits += fit_rows(f"{kind} divergence {model} p/rate^{power}", fit.values, fit.errors, fit.chi2, fit.dof, note,
                         scaled="residuals")
    fname = f"{kind.lower()}_{model}.png"
    figures.divergence_figure(plateau, fit, f"$p/\\dot\\gamma^{power}$ (rate -> 0)", rep.path(fname))
    rep.doc.figure(fname, f"{kind} coefficient of p against phi_J - phi ({model})")


def _compare(rep, groups, opts):
    phi_min, phi_max, rate_max = rep.windows.get(("RD0", "pressure"), (opts.phi_min, opts.phi_max, opts.rate_max))
    pts = pd.concat([scaling.collapse_points(groups, "pressure", N=opts.N, model=m,
                                             phi_range=(phi_min, phi_max), rate_max=rate_max)
                     for m in ("RD0", "CD0")])
    cmp = scaling.compare_collapses(pts, opts.degree, 0 if opts.correction else -1)
    rep.doc.heading("RD0 against CD0: joint collapse")
    rep.doc.paragraph(cmp.statement())
    rep.fits += fit_rows("joint collapse RD0+CD0 pressure", cmp.joint.values, cmp.joint.errors,
                         cmp.joint.chi2, cmp.joint.dof, f"F = {cmp.f_statistic:.2f}, p = {cmp.p_value:.3g}",
                         scaled="residuals")
    figures.collapse_figure(cmp.joint, rep.path("collapse_joint.png"))
    rep.doc.figure("collapse_joint.png", "joint collapse of RD0 and CD0")


def _compare_averages(rep, table, groups, label="model"):
    """The steady averages of the models at the state points they share (comparison.py)."""
    cmp = comparison.compare_averages(groups, list(OBSERVABLES), label=label, replica_table=table)
    d = rep.doc
    d.heading(f"Steady-state averages compared: {' against '.join(map(str, cmp.labels))}")
    d.paragraph("At each state point (N, phi, rate) that two or more models share, each pair's difference of "
                "seed averages, its error sqrt(error_a^2 + error_b^2) from the 1-sigma errors of the table above "
                "and the difference in those errors (sigmas). " + TEST_TEXT)
    d.table(cmp.averages)
    d.table(cmp.differences[[c for c in DIFFERENCE_COLUMNS if c in cmp.differences]])
    d.paragraph(cmp.statement())
    comparison.write_tables(cmp, rep.outdir)
    figures.comparison_figure(cmp, rep.path("compare.png"), replicas=table, label=label)
    d.figure("compare.png", "seed averages with 1-sigma errors per group (dots: replica means) and each "
             "difference in units of its error (filled: significant)")


TEST_TEXT = ("Test of equal means, two-sided: Welch's t over the replica means when both groups have 2 or "
             "more seeds, else a t test of the time errors with their dof; Holm's adjustment over every test of the "
             "comparison. Tables: compare_averages.tsv, compare.tsv.")
DIFFERENCE_COLUMNS = ("N", "phi", "rate", "observable", "group_a", "group_b", "difference", "difference_error",
                      "relative_difference", "sigmas", "test", "statistic", "dof", "p_value", "p_adjusted",
                      "significant")


def _correlations(rep, archive, table):
    per, grouped = correlations.correlation_minima(archive, table)
    rep.doc.heading("Velocity correlations")
    rep.doc.table(grouped)
    curves = {key: correlations.mean_curves(archive, part["replica"])
              for key, part in per.groupby(["model", "N", "phi", "rate"])}
    figures.correlation_figure(curves, grouped, rep.path("correlation.png"))
    pd.concat([pd.DataFrame(dict(model=k[0], N=k[1], phi=k[2], rate=k[3], x=x, g_y=g, g_y_error=e))
               for k, (x, g, e) in curves.items()]).to_csv(rep.path("correlation.tsv"), sep="\t", index=False)
    rep.doc.figure("correlation.png", f"g_y(x), seed mean, one panel per (model, N, phi) with every rate "
                   f"({len(curves)} curves, in correlation.tsv; colour: rate, triangles: x_min), and x_min "
                   "against rate (last panel)")
    for (model, n, phi), part in grouped.groupby(["model", "N", "phi"]):
        try:
            g = correlations.fit_minimum_growth(part["rate"], part["x_min"], part["x_min_error"])
        except AnalysisError:
            continue
        rep.fits += fit_rows(f"x_min growth {model} N={int(n)} phi={phi:g}", {"a": g.a, "A": g.A},
                             {"a": g.a_error, "A": g.A_error}, g.chi2, g.dof, "x_min = A rate^-a")


def _picture(rep, archive, kept):
    small = kept[kept["N"] <= PICTURE_MAX_N]
    if small.empty:
        raise AnalysisError(f"no kept replica with N <= {PICTURE_MAX_N} to draw")
    order = [c for c in ("N", "phi", "rate") if c in small]
    pick = small.sort_values(order, ascending=[False, False, True][: len(order)]).iloc[0]
    r = int(pick["replica"])
    alpha = float(pick["alpha"]) if "alpha" in pick and np.isfinite(pick["alpha"]) else 2.0
    strain = archive.final_strain(r)
    final = archive.final(r)
    params = (f"{pick['model']} N = {int(pick['N'])}, phi = {pick['phi']:g}"
              + (f", rate = {pick['rate']:g}" if "rate" in pick and np.isfinite(pick["rate"]) and pick["rate"] > 0
                 else ""))
    net, ratt = pictures.draw_configuration(final, rep.path("configuration.png"), alpha, strain=strain,
                                            caption=f"replica {r}: {params}")
    rep.doc.heading("Final configuration")
    rep.doc.paragraph(f"Replica {r} ({params}), {pictures.strain_text(strain, final.box_strain)}: "
                      f"{len(net.force)} contacts, {int(ratt.sum())} rattlers.")
    rep.doc.figure("configuration.png", "final configuration in the lab frame of the sheared cell: disks "
                   "coloured by size, rattlers grey with a red cross, contact forces as lines of width "
                   "proportional to the force")


def _order(rep, archive):
    series, summary = order.order_by_size_ratio(archive)
    d = rep.doc
    d.heading("Bond-orientational order over strain")
    d.paragraph("psi6 from each configuration frame (Delaunay neighbours, periodic images): global "
                "|<psi6_i>| and local <|psi6_i|>; late-strain averages over the frames after each "
                "replica's transient, mean over replicas, error = standard error over replicas.")
    d.table(summary)
    for _, row in summary.iterrows():
        rep.fits += fit_rows(f"psi6 size ratio {row['size_ratio']:g}",
                             {"psi6_global": row["psi6_global"], "psi6_local": row["psi6_local"]},
                             {"psi6_global": row["psi6_global_error"], "psi6_local": row["psi6_local_error"]},
                             extra=f"{int(row['replicas'])} replicas, {int(row['frames'])} frames")
    figures.order_figure(series, rep.path("psi6.png"))
    d.figure("psi6.png", "psi6 against strain, per replica")
    # An animation of the smallest replica with the most frames, per size ratio.
    for ratio, part in series.groupby("size_ratio"):
        counts = part.groupby(["replica", "N"]).size().reset_index(name="frames")
        pick = counts.sort_values(["frames", "N"], ascending=[False, True]).iloc[0]
        if pick["N"] > PICTURE_MAX_N:
            continue
        name = f"frames_size_ratio_{ratio:g}.gif"
        drawn = pictures.animate_frames(archive, int(pick["replica"]), rep.path(name), max_frames=60)
        d.paragraph(f"Animation ({drawn} frames) of replica {int(pick['replica'])}, size ratio {ratio:g}, "
                    f"N = {int(pick['N'])}: [{name}]({name})")


def _static(rep, archive, opts):
    states = jamming.static_states(archive)
    d = rep.doc
    d.heading("Jammed states")
    pj = jamming.jamming_probability(states)
    d.table(pj)
    thr = jamming.thresholds(states)
    if len(thr):
        d.paragraph("Threshold per N: mean mu and width s (compression protocols: of phi_J; "
                    "RAND and COOL: maximum-likelihood normal CDF fitted to P_J).")
        d.table(thr)
        for _, t in thr.iterrows():
            rep.fits += fit_rows(f"threshold {t['model']} N={int(t['N'])}", {"mu": t["mu"], "s": t["s"]},
                                 {"mu": t["mu_error"], "s": t["s_error"]},
                                 extra=f"{int(t['configurations'])} configurations")
    figures.jamming_figure(pj, thr if len(thr) else None, rep.path("pj.png"))
    d.figure("pj.png", "jamming probability P_J(phi) per N")
    jammed = states[states["jammed"] == 1]
    rep.ran.append("jamming probability")
    rep.attempt("pressure distributions", lambda: _pressure_distributions(rep, states))
    for model in sorted(states["model"].unique()):
        rep.attempt(f"finite-size scaling {model}", lambda m=model: _fss(rep, thr, m, opts))
    kept = archive.done().merge(jammed[["replica"]], on="replica")
    rep.attempt("configuration picture", lambda: _picture(rep, archive, kept))


def _pressure_distributions(rep, states):
    try:
        figures.pressure_distribution_figure(states, rep.path("pressure_distribution.png"))
    except ValueError as e:
        raise AnalysisError(str(e)) from None
    rep.doc.figure("pressure_distribution.png", "distributions of p of jammed states per phi (colour), one panel "
                   "per model and N")


def _fss(rep, thr, model, opts):
    t = thr[thr["model"] == model] if len(thr) else thr
    fit = jamming.finite_size_scaling(t, correction=opts.correction)
    rep.fits += fit_rows(f"finite-size scaling {model}", fit.values, fit.errors, fit.chi2, fit.dof,
                         f"sizes {', '.join(str(int(n)) for n in t['N'])}")


def _quasistatic(rep, archive):
    table = stats.replica_averages(archive, list(OBSERVABLES))
    groups = stats.group_averages(table, list(OBSERVABLES), keys=("model", "N", "phi"))
    rep.doc.heading("Quasistatic shear averages")
    rep.doc.table(groups)
    rep.ran.append("quasistatic shear averages")
    kept = table[table["left_out"] == ""]
    rep.attempt("configuration picture", lambda: _picture(rep, archive, kept))


def build_report(paths, outdir, opts=None):
    """Write the report of the archive(s) at `paths` into outdir; returns the Report."""
    opts = opts or ReportOptions()
    archive = open_archives(paths)
    if archive.done().empty:
        raise AnalysisError(f"{', '.join(paths)}: no finished replica (status done) to analyse")
    if opts.N is not None:
        sizes = sorted({int(n) for n in archive.done()["N"]})
        if opts.N not in sizes:
            raise AnalysisError(f"--N = {opts.N} is not allowed: no finished replica has N = {opts.N} (the finished "
                                f"sizes: {', '.join(map(str, sizes))})")
    attrs = archive.attributes()
    rep = Report(f"jamsim report: {', '.join(sorted(set(archive.replicas['campaign'])))}", outdir)
    rep.doc.paragraph(f"Files: {', '.join(paths)}; models: {', '.join(archive.models)}; code version "
                      f"{attrs.get('code_version', '?')}; layout {attrs.get('layout_version', '?')}; "
                      f"{len(archive.done())} of {len(archive.replicas)} replicas done.")
    models = set(archive.models)
    if models <= set(OVERDAMPED + MASSIVE):
        _dynamics(rep, archive, opts)
    elif models <= set(jamming.QUENCHED + jamming.COMPRESSED):
        _static(rep, archive, opts)
    elif models == {"QS"}:
        _quasistatic(rep, archive)
    else:
        raise AnalysisError(f"models {', '.join(sorted(models))}: one report covers dynamics, "
                            "jamming protocols or QS, not a mixture")
    rep.write()
    return rep
