"""Figures (PNG) of the analyses. Each function takes the result of an analysis and a path."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

LABELS = {"pressure": "p", "shear_stress": r"\sigma"}


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def collapse_figure(fit, path):
    """Two-branch collapse (thesis Fig. 5.1): O/rate^q against |phi - phi_J|/rate^(1/znu),
    log-log; filled markers above phi_J, open below; the fitted scaling function."""
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
    ax.set_title(f"phi_J = {v['phi_J']:.4f}, q = {v['q']:.3f}, znu = {v['znu']:.2f}, "
                 f"chi2/dof = {fit.chi2_per_dof:.2f}\nfilled: phi > phi_J, open: phi < phi_J", fontsize=8)
    ax.legend(fontsize=7)
    _save(fig, path)


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
    """Normalised histograms of {label: values}."""
    fig, ax = plt.subplots(figsize=(5, 4))
    for label, v in samples.items():
        if len(v) >= 3:
            ax.hist(v, bins=max(5, min(30, len(v) // 3)), histtype="step", density=True, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("probability density")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)
    _save(fig, path)


def correlation_figure(curves, minima, path):
    """g_y(x) per rate ({label: (x, g, err)}) and x_min against rate."""
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4))
    for label, (x, g, e) in curves.items():
        ax.plot(x, g, lw=1, label=label)
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel(r"$x$ ($d_s$)")
    ax.set_ylabel(r"$g_y(x)$")
    ax.legend(fontsize=6)
    for (model, n, phi), part in minima.groupby(["model", "N", "phi"]):
        err = part["x_min_error"] if part["x_min_error"].notna().any() else None
        bx.errorbar(part["rate"], part["x_min"], err, marker="o", capsize=2,
                    label=f"{model} N = {int(n)} phi = {phi:g}")
    bx.set_xscale("log")
    bx.set_xlabel(r"$\dot\gamma$")
    bx.set_ylabel(r"$x_{min}$ ($d_s$)")
    bx.legend(fontsize=6)
    _save(fig, path)


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
