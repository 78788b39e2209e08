"""Figures (PNG) of the analyses. Each function takes the result of an analysis and a path."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .trends import PUBLISHED  # noqa: E402

LABELS = {"pressure": "p", "shear_stress": r"\sigma"}


def _save(fig, path, tight=True):
    """Write the figure and close it; return it (its axes and artists stay readable)."""
    if tight:
        fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return fig


def value_with_error(value, error, sep=" \u00b1 "):
    """'0.8452 ± 0.0027': the value to the error's second significant digit."""
    if not (np.isfinite(error) and error > 0):
        return f"{value:.4g}"
    scale = int(np.floor(np.log10(max(abs(value), error))))
    if -3 <= scale <= 4:
        digits = max(0, 1 - int(np.floor(np.log10(error))))
        return f"{value:.{digits}f}{sep}{error:.{digits}f}"
    v, e = value / 10.0 ** scale, error / 10.0 ** scale
    digits = max(0, 1 - int(np.floor(np.log10(e))))
    return f"({v:.{digits}f}{sep}{e:.{digits}f})e{scale:+03d}"


def fit_title(fit, label=""):
    """Title of a collapse figure: the window (label), phi_J, q, znu with errors, chi2/dof,
    dof and the p-value."""
    from scipy.stats import chi2 as dist

    v, e = fit.values, fit.errors
    p = float(dist.sf(fit.chi2, fit.dof)) if fit.dof > 0 else float("nan")
    line = (f"$\\phi_J$ = {value_with_error(v['phi_J'], e['phi_J'])}, q = {value_with_error(v['q'], e['q'])}, "
            f"$z\\nu$ = {value_with_error(v['znu'], e['znu'])}\n"
            f"$\\chi^2$/dof = {fit.chi2_per_dof:.2f} ({fit.dof} dof, p = {p:.2g}); errors: {fit.method}")
    return (label + "\n" if label else "") + line


def collapse_figure(fit, path, label="", failed=False):
    """Two-branch collapse (thesis Fig. 5.1): O/rate^q against |phi - phi_J|/rate^(1/znu),
    log-log; filled markers above phi_J, open below; the fitted scaling function. The title
    names the window (label) and carries phi_J, q, znu with errors and chi2/dof; failed: the
    fit is rejected by its chi2 (title in red, marked)."""
    v, pts = fit.values, fit.points
    q, inv = v["q"], 1 / v["znu"]
    x = (pts["phi"] - v["phi_J"]) / pts["rate"] ** inv
    scaled = pts["value"] / pts["rate"] ** q
    err = pts["error"] / pts["rate"] ** q
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    colours = plt.cm.viridis(np.linspace(0, 0.9, pts["rate"].nunique()))
    for colour, rate in zip(colours, sorted(pts["rate"].unique(), reverse=True)):
        for above in (True, False):
            s = (pts["rate"] == rate) & ((x > 0) == above)
            ax.errorbar(np.abs(x[s]), scaled[s], err[s], ls="none", marker="o", ms=4, capsize=1.5,
                        color=colour, mfc=colour if above else "white",
                        label=f"rate {rate:g}" if above else None)
    for group in fit.groups:
        for sign in (1, -1):
            xs = np.geomspace(max(np.abs(x).min(), 1e-6), np.abs(x).max(), 200) * sign
            xs = xs[(xs >= x.min()) & (xs <= x.max())]
            if len(xs):
                ax.plot(np.abs(xs), fit.scaled_value(xs, group=group), "k-" if sign > 0 else "k--", lw=1)
    name = LABELS.get(fit.observable, fit.observable)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"$|\phi-\phi_J|/\dot\gamma^{1/z\nu}$")
    ax.set_ylabel(f"${name}/\\dot\\gamma^{{q}}$")
    ax.set_title(fit_title(fit, ("FIT REJECTED (chi2): " if failed else "") + label), fontsize=8,
                 color="tab:red" if failed else "k")
    ax.plot([], [], "ko", ms=4, label=r"$\phi > \phi_J$")
    ax.plot([], [], "o", mfc="white", mec="k", ms=4, label=r"$\phi < \phi_J$")
    ax.legend(fontsize=7)
    return _save(fig, path)


def flow_curves(groups, observable, path):
    """O/rate against phi, one curve per (model, rate)."""
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    for (model, rate), part in groups[groups["rate"] > 0].groupby(["model", "rate"]):
        part = part.sort_values("phi")
        ax.errorbar(part["phi"], part[observable] / rate, part[f"{observable}_error"] / rate,
                    marker="o", ms=3, capsize=2, label=f"{model} rate {rate:g}")
    ax.set_yscale("log")
    ax.set_xlabel(r"$\phi$")
    ax.set_ylabel(f"${LABELS.get(observable, observable)}/\\dot\\gamma$")
    ax.legend(fontsize=6)
    _save(fig, path)


def divergence_figure(plateau, fit, ylabel, path):
    """Plateau values against phi_J - phi (log-log) with the fitted power law."""
    fig, ax = plt.subplots(figsize=(5, 4))
    d = fit.values["phi_J"] - fit.points["phi"]
    ax.errorbar(d, fit.points["value"], fit.points["error"], marker="o", ls="none", capsize=2, label="data")
    ds = np.geomspace(d.min(), d.max(), 100)
    ax.plot(ds, fit.curve(fit.values["phi_J"] - ds), "k-", lw=1,
            label=f"beta = {fit.values['beta']:.2f} +- {fit.errors['beta']:.2f}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"$\phi_J-\phi$")
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=8)
    _save(fig, path)


def jamming_figure(pj, fss, path):
    """P_J(phi) per (model, N) with the fitted threshold CDFs when given."""
    from scipy.special import ndtr
    fig, ax = plt.subplots(figsize=(5, 4))
    for (model, n), part in pj.groupby(["model", "N"]):
        line = ax.errorbar(part["phi"], part["P_J"], part["error"], marker="o", ms=3, capsize=2, ls="none",
                           label=f"{model} N = {int(n)}")
        if fss is not None:
            t = fss[(fss["model"] == model) & (fss["N"] == n)]
            if len(t):
                phis = np.linspace(part["phi"].min(), part["phi"].max(), 200)
                ax.plot(phis, ndtr((phis - t["mu"].iloc[0]) / t["s"].iloc[0]), color=line[0].get_color(), lw=1)
    ax.set_xlabel(r"$\phi$")
    ax.set_ylabel(r"$P_J$")
    ax.legend(fontsize=7)
    _save(fig, path)


def histogram_figure(samples, xlabel, path):
    """Normalised histograms of {label: values}; the legend beside the axes, not over them."""
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for label, v in samples.items():
        if len(v) >= 3:
            ax.hist(v, bins=max(5, min(30, len(v) // 3)), histtype="step", density=True, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("probability density")
    handles = ax.get_legend_handles_labels()[0]
    if handles:
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1), borderaxespad=0,
                  ncol=1 + len(handles) // 20)
    return _save(fig, path)


def _log_norm(values):
    from matplotlib.colors import LogNorm, Normalize
    v = np.asarray(sorted(set(values)), float)
    if np.all(v > 0):
        return LogNorm(v.min(), v.max()) if len(v) > 1 else LogNorm(v[0] / 3, v[0] * 3)
    return Normalize(v.min(), v.max()) if len(v) > 1 else Normalize(v[0] - 0.5, v[0] + 0.5)


# viridis without its last, pale yellow, eighth (lines on white stay visible)
RATE_COLOURS = matplotlib.colors.ListedColormap(plt.cm.viridis(np.linspace(0, 0.9, 256)), "viridis_dark")
PHI_COLOURS = matplotlib.colors.ListedColormap(plt.cm.plasma(np.linspace(0, 0.88, 256)), "plasma_dark")


def _grid(n, columns=3, size=(3.6, 3.0)):
    cols = min(columns, n)
    rows = int(np.ceil(n / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(size[0] * cols + 1.2, size[1] * rows), squeeze=False)
    for ax in axes.ravel()[n:]:
        ax.set_visible(False)
    return fig, axes.ravel()[:n]


def pressure_distribution_figure(states, path, min_states=3):
    """Distributions of p of jammed states (jamming.static_states, jammed == 1): one panel per
    (model, N), one step histogram of ln p per phi (log-spaced bins, density per unit ln p),
    coloured by phi on a continuous scale with its colour bar; phi with fewer than min_states
    states are left out. Returns the figure (one line per (model, N, phi) drawn)."""
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    ok = states[(states["jammed"] == 1) & (states["pressure"] > 0)]
    counts = ok.groupby(["model", "N", "phi"])["pressure"].transform("size")
    ok = ok[counts >= min_states]
    if ok.empty:
        raise ValueError(f"no (model, N, phi) with {min_states} or more jammed states of p > 0")
    panels = list(ok.groupby(["model", "N"], sort=True))
    phis = np.sort(ok["phi"].unique())
    norm = Normalize(phis.min(), phis.max()) if len(phis) > 1 else Normalize(phis[0] - 0.01, phis[0] + 0.01)
    cmap = PHI_COLOURS
    fig, axes = _grid(len(panels))
    for ax, ((model, n), part) in zip(axes, panels):
        lo, hi = np.log(part["pressure"].min()), np.log(part["pressure"].max())
        for phi, sub in part.groupby("phi", sort=True):
            lnp = np.log(sub["pressure"].to_numpy(float))
            bins = np.linspace(lo, hi if hi > lo else lo + 1, max(5, min(25, len(lnp) // 3)) + 1)
            h, edges = np.histogram(lnp, bins=bins, density=True)
            ax.step(np.exp(edges), np.append(h, h[-1]), where="post", color=cmap(norm(phi)), lw=1.2,
                    label=f"phi = {phi:g} ({len(lnp)})")
        ax.set_xscale("log")
        ax.set_title(f"{model}, N = {int(n)}: {len(part)} jammed states", fontsize=9)
        ax.set_xlabel("p (jammed states)")
        ax.set_ylabel(r"density per unit $\ln p$")
    fig.tight_layout()
    bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=list(axes), pad=0.02, fraction=0.04)
    bar.set_label(r"$\phi$")
    return _save(fig, path, tight=False)


def correlation_figure(curves, minima, path):
    """Velocity correlations. curves: {(model, N, phi, rate): (x, g, err)}; minima: x_min per
    (model, N, phi, rate) (correlations.correlation_minima). One panel of g_y(x) per (model,
    N, phi), every rate drawn, coloured by rate on a logarithmic scale (one colour bar for the
    figure: no colour repeats within a panel), its x_min marked; a last panel with x_min
    against rate, one line per (model, N, phi) coloured by phi (marker per model). Returns
    the figure (panel k's lines: the curves of its (model, N, phi))."""
    from matplotlib.cm import ScalarMappable

    keys = sorted(curves, key=lambda k: (str(k[0]), k[1], k[2], k[3]))
    panels = sorted({k[:3] for k in keys}, key=lambda k: (str(k[0]), k[1], k[2]))
    rates = sorted({k[3] for k in keys})
    norm = _log_norm(rates)
    cmap = RATE_COLOURS
    fig, axes = _grid(len(panels) + 1)
    for ax, panel in zip(axes, panels):
        for key in [k for k in keys if k[:3] == panel]:
            x, g, _ = curves[key]
            if len(x) == 0:
                continue
            colour = cmap(norm(key[3]))
            ax.plot(x, g, lw=1, color=colour, label=f"rate {key[3]:g}")
            m = minima[(minima["model"] == panel[0]) & (minima["N"] == panel[1]) & (minima["phi"] == panel[2])
                       & (minima["rate"] == key[3])] if minima is not None and len(minima) else []
            if len(m):
                ax.plot([m["x_min"].iloc[0]], [np.interp(m["x_min"].iloc[0], x, g)], marker="v", ms=4,
                        color=colour, ls="none")
        ax.axhline(0, color="k", lw=0.5)
        ax.set_title(f"{panel[0]}, N = {int(panel[1])}, phi = {panel[2]:g}", fontsize=9)
        ax.set_xlabel(r"$x$ ($d_s$)")
        ax.set_ylabel(r"$g_y(x)$")
    bx = axes[-1]
    if minima is not None and len(minima):
        phis = sorted(minima["phi"].unique())
        pnorm = _log_norm(phis) if len(phis) > 1 else None
        markers = dict(zip(sorted(minima["model"].unique()), "osD^vP*"))
        for (model, n, phi), part in minima.groupby(["model", "N", "phi"]):
            part = part.sort_values("rate")
            err = part["x_min_error"] if part["x_min_error"].notna().any() else None
            colour = plt.cm.plasma(0.85 * (pnorm(phi) if pnorm is not None else 0.5))
            bx.errorbar(part["rate"], part["x_min"], err, marker=markers[model], ms=4, capsize=2, color=colour,
                        label=f"{model} N = {int(n)} phi = {phi:g}")
        bx.set_xscale("log")
        bx.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.02, 1), borderaxespad=0)
    bx.set_title(r"$x_{min}$ (seed mean) against rate", fontsize=9)
    bx.set_xlabel(r"$\dot\gamma$")
    bx.set_ylabel(r"$x_{min}$ ($d_s$)")
    fig.tight_layout()
    bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=list(axes[:-1]), pad=0.02, fraction=0.04)
    bar.set_label(r"shear rate $\dot\gamma$ (curve colour; $\blacktriangledown$: $x_{min}$)")
    return _save(fig, path, tight=False)


def order_figure(series, path):
    """psi6 (global and local) against strain, one line per replica, coloured by size ratio."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharex=True)
    ratios = sorted(series["size_ratio"].unique())
    colours = {r: c for r, c in zip(ratios, plt.rcParams["axes.prop_cycle"].by_key()["color"] * 4)}
    seen = set()
    for r, part in series.groupby("replica"):
        ratio = part["size_ratio"].iat[0]
        label = None if ratio in seen else (f"size ratio {ratio:g}" + (" (monodisperse)" if ratio == 1 else ""))
        seen.add(ratio)
        for ax, column in zip(axes, ("psi6_global", "psi6_local")):
            ax.plot(part["strain"], part[column], color=colours[ratio], lw=1, alpha=0.8,
                    label=label if column == "psi6_global" else None)
    axes[0].set_ylabel(r"global $|\langle\psi_6\rangle|$")
    axes[1].set_ylabel(r"local $\langle|\psi_{6,i}|\rangle$")
    for ax in axes:
        ax.set_xlabel(r"strain $\gamma$")
        ax.set_ylim(0, 1)
    axes[0].legend(fontsize=8)
    _save(fig, path)


def comparison_figure(comparison, path, replicas=None, label="model"):
    """Steady-state averages of several groups (comparison.AveragesComparison). Per observable
    a column: on top each group's seed average with its 1-sigma error at every shared state
    point (groups side by side, one colour each; the replica means as small dots when
    `replicas` is given); below, each pair's difference in units of its error (filled:
    significant after Holm's adjustment; dashed lines at +-1.96). With one state point the
    title carries the difference, its sigmas and the test's p."""
    from .comparison import point_label

    obs, labels, d = comparison.observables, comparison.labels, comparison.differences
    keys = [k for k in ("N", "phi", "rate") if k in comparison.averages]
    points = comparison.averages[keys].drop_duplicates().sort_values(keys).reset_index(drop=True)
    names = [point_label(r, keys) for _, r in points.iterrows()]
    colours = dict(zip(labels, plt.rcParams["axes.prop_cycle"].by_key()["color"] * 3))
    width = max(4.0, 0.5 * len(points) * len(labels) + 2)
    fig, axes = plt.subplots(2, len(obs), figsize=(width * len(obs), 6.5), squeeze=False,
                             gridspec_kw=dict(height_ratios=(3, 2)), sharex="col")
    offsets = (np.arange(len(labels)) - (len(labels) - 1) / 2) * 0.6 / max(len(labels), 1)
    pairs = list(dict.fromkeys(zip(d["group_a"], d["group_b"])))
    for col, o in enumerate(obs):
        ax, bx = axes[0, col], axes[1, col]
        for k, g in enumerate(labels):
            part = comparison.averages[comparison.averages[label] == g].merge(points.reset_index(), on=keys)
            ax.errorbar(part["index"] + offsets[k], part[o], part[f"{o}_error"], marker="o", ls="none", capsize=3,
                        color=colours[g], label=f"{g}")
            if replicas is not None:
                r = replicas[(replicas[label] == g) & (replicas["left_out"] == "")].merge(points.reset_index(), on=keys)
                ax.plot(r["index"] + offsets[k] + 0.08, r[o], ".", ms=3, color=colours[g], alpha=0.6)
        values = comparison.averages[o].to_numpy(float)
        if np.all(values > 0) and values.max() / values.min() > 20:
            ax.set_yscale("log")
        ax.set_ylabel(f"${LABELS.get(o, o)}$ (steady average)" if o in LABELS else o)
        ax.legend(fontsize=7, title=f"{label} (dots: replicas)" if replicas is not None else label, title_fontsize=7)
        rows = d[d["observable"] == o]
        for j, (a, b) in enumerate(pairs):
            pr = rows[(rows["group_a"] == a) & (rows["group_b"] == b)].merge(points.reset_index(), on=keys)
            z = pr["difference"] / pr["difference_error"]
            shift = (j - (len(pairs) - 1) / 2) * 0.1
            for sig in (True, False):
                s = pr["significant"] == sig
                if not s.any():
                    continue
                bx.plot(pr.loc[s, "index"] + shift, z[s], "o", color=f"C{j}", mfc=f"C{j}" if sig else "white",
                        label=f"{a} - {b}" + (" (significant)" if sig else ""))
        for y in (-1.96, 1.96):
            bx.axhline(y, color="0.5", ls="--", lw=0.8)
        bx.axhline(0, color="k", lw=0.5)
        bx.set_ylabel("difference / error")
        top = max(3.0, float(np.nanmax(np.abs(rows["sigmas"]))) * 1.3) if len(rows) else 3.0
        bx.set_ylim(-top, top)
        bx.legend(fontsize=6, loc="lower left", ncol=2)
        bx.set_xticks(range(len(points)))
        bx.set_xticklabels(names, rotation=30 if len(points) > 2 else 0, ha="right" if len(points) > 2 else "center",
                           fontsize=7)
        bx.set_xlim(-0.6, len(points) - 0.4)
        title = LABELS.get(o, o)
        title = f"${title}$" if o in LABELS else title
        if len(rows) == 1:
            r = rows.iloc[0]
            title += (f": {r['group_a']} $-$ {r['group_b']} = "
                      f"{value_with_error(r['difference'], r['difference_error'])}"
                      f"\n({r['sigmas']:.1f}$\\sigma$; {r['test']}, p = {r['p_value']:.2g}"
                      f"{': significant' if r['significant'] else ': not significant'})")
        ax.set_title(title, fontsize=9)
    return _save(fig, path)


def trends_figure(by_size, trends, local, path):
    """One panel per parameter of the collapse against N (log2), the published range shaded
    and the trend's straight line; with local exponents (trends.newtonian_approach, may be
    empty) a last panel: beta_eff against phi_J - phi, one series per phi_J."""
    fitted = by_size[by_size["left_out"] == ""]
    panels = len(trends) + (len(local) > 0)
    fig, axes = _grid(panels, columns=min(panels, 3))
    x = np.log2(fitted["N"].to_numpy(float))
    for ax, t in zip(axes, trends):
        _trend_panel(ax, x, fitted[t.parameter].to_numpy(float), fitted[f"{t.parameter}_error"].to_numpy(float), t)
        ax.set_xticks(x, [str(int(n)) for n in fitted["N"]])
        ax.set_xlabel("N")
    if len(local):
        ax = axes[-1]
        _published(ax, PUBLISHED["beta"])
        for k, (phi_j, part) in enumerate(local.groupby("phi_J", sort=False)):
            ax.errorbar(part["distance"] * (1 + 0.02 * k), part["beta_eff"], part["beta_eff_error"], marker="o",
                        capsize=2, label=f"$\\phi_J$ = {phi_j:.4f}")
        ax.set_xscale("log")
        ax.invert_xaxis()
        ax.set_xlabel(r"$\phi_J-\phi$ (N = %d; closer to $\phi_J$ to the right)" % int(local["N"].iloc[0]))
        ax.set_ylabel(r"local Newtonian $\beta$")
        ax.legend(fontsize=7)
    return _save(fig, path)


def _published(ax, published):
    lo, hi = published
    if lo == hi:
        ax.axhline(lo, color="0.6", lw=3, label="published")
    else:
        ax.axhspan(lo, hi, color="0.85", label="published")


def _trend_panel(ax, x, value, error, trend):
    _published(ax, trend.published)
    keep = np.isfinite(value) & np.isfinite(error) & (error > 0)
    ax.errorbar(x[keep], value[keep], error[keep], marker="o", ls="none", capsize=2, color="C0")
    xs = np.array([x[keep].min(), x[keep].max()])
    ax.plot(xs, [trend.first, trend.last], "k--", lw=1)
    ax.set_ylabel(trend.parameter)
    ax.set_title(f"{trend.parameter}: {trend.verdict()}", fontsize=8)
    ax.legend(fontsize=7)
