#!/usr/bin/python3
"""Critical scaling of the flow curves of a jamsim campaign (thesis §5.2; Olsson & Teitel 2007).

usage: tools/analyze_scaling.py ARCHIVE.h5 OUTDIR [--observable pressure|shear_stress]
           [--N N] [--phi-min X] [--phi-max X] [--rate-max R] [--degree K]
           [--start PHI_J Q ZNU]

Near point J an observable of the steady state scales as
    O(phi, rate) = rate^q F(x),   x = (phi - phi_J) / rate^(1/znu),   q = y/znu,
(eq. 5.2). The fit is weighted least squares of ln O on
    ln O = q ln rate + sum_{k=0..K} a_k x^k
over the (phi, rate) points of one N within the window, with the standard error of ln O
over the seeds as weights. Reported: phi_J, q, znu, y = q znu and beta = znu - y (the
Newtonian divergence O/rate ~ |phi - phi_J|^-beta below jamming), with standard errors from
the covariance of the fit (multiplied by sqrt(chi2/dof) when that exceeds 1), and
chi2/dof. Averages: each replica's mean over strain >= its transient, then mean and
standard error over the seeds (as tools/plot_campaign.py); points with fewer than 2 seeds
are left out (no error estimate).

Writes OUTDIR/scaling_<observable>.tsv (the fitted parameters) and
OUTDIR/collapse_<observable>.png (O/rate^q against x: one curve if the scaling holds).
"""
import argparse
import os
import sys

import h5py
import matplotlib
import numpy as np
from scipy.optimize import least_squares

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLUMNS = {"pressure": "pressure", "shear_stress": "shear_stress"}


def fail(message):
    print(f"analyze_scaling.py: {message}", file=sys.stderr)
    sys.exit(2)


def steady_table(path, observable):
    """{(N, phi, rate): [replica means]} over finished replicas with rate > 0."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        fail(f"cannot open archive '{path}': {e}")
    with f:
        if "timeseries" not in f or "replicas" not in f:
            fail(f"'{path}' is not a jamsim campaign archive (no /timeseries or /replicas)")
        r, ts = f["replicas"], f["timeseries"]
        status = r["status"][...]
        out = {}
        for k in np.flatnonzero(status == 2):
            rate = float(r["rate"][k])
            if rate <= 0:
                continue
            n = int(r["n_samples"][k])
            keep = ts["strain"][k, :n] >= r["transient"][k]
            v = ts[COLUMNS[observable]][k, :n][keep]
            if v.size == 0 or not np.all(np.isfinite(v)):
                continue
            out.setdefault((int(r["N"][k]), float(r["phi"][k]), rate), []).append(v.mean())
    return out


def fit(phi, rate, lnO, err, degree, start):
    """Weighted least squares of ln O = q ln rate + P(x); returns params, covariance, chi2, dof."""
    def residuals(theta):
        phi_j, q, inv_znu = theta[:3]
        x = (phi - phi_j) / rate ** inv_znu
        model = q * np.log(rate) + np.polyval(theta[3:][::-1], x)
        return (lnO - model) / err

    phi_j0, q0, znu0 = start
    theta0 = np.concatenate([[phi_j0, q0, 1.0 / znu0], np.zeros(degree + 1)])
    # the polynomial's constant term from the data at the start values
    x0 = (phi - phi_j0) / rate ** (1.0 / znu0)
    theta0[3:] = np.polyfit(x0, lnO - q0 * np.log(rate), degree, w=1.0 / err)[::-1]
    res = least_squares(residuals, theta0, method="lm", x_scale="jac", max_nfev=20000)
    if not res.success:
        fail(f"the fit did not converge: {res.message}")
    chi2 = float(np.sum(res.fun ** 2))
    dof = len(lnO) - len(theta0)
    jtj = res.jac.T @ res.jac
    cov = np.linalg.pinv(jtj)
    return res.x, cov, chi2, dof


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("archive")
    ap.add_argument("outdir")
    ap.add_argument("--observable", choices=sorted(COLUMNS), default="pressure")
    ap.add_argument("--N", type=int, help="system size to fit (default: the largest)")
    ap.add_argument("--phi-min", type=float, default=-np.inf)
    ap.add_argument("--phi-max", type=float, default=np.inf)
    ap.add_argument("--rate-max", type=float, default=np.inf)
    ap.add_argument("--degree", type=int, default=3, help="degree K of ln F(x) (default 3)")
    ap.add_argument("--start", type=float, nargs=3, default=[0.843, 0.28, 3.5],
                    metavar=("PHI_J", "Q", "ZNU"), help="start values (default 0.843 0.28 3.5)")
    a = ap.parse_args()
    if a.degree < 0:
        fail(f"--degree = {a.degree} is not allowed: an integer >= 0")
    table = steady_table(a.archive, a.observable)
    sizes = sorted({k[0] for k in table})
    if not sizes:
        fail(f"'{a.archive}' has no finished replicas with rate > 0")
    n = a.N if a.N is not None else sizes[-1]
    if n not in sizes:
        fail(f"--N = {n} is not in '{a.archive}' (sizes there: {', '.join(map(str, sizes))})")
    pts = [(phi, rate, np.mean(v), np.std(v, ddof=1) / np.sqrt(len(v)))
           for (nn, phi, rate), v in sorted(table.items())
           if nn == n and len(v) >= 2 and a.phi_min <= phi <= a.phi_max and rate <= a.rate_max]
    pts = [p for p in pts if p[2] > 0 and p[3] > 0]
    phi, rate, O, dO = (np.array(c) for c in zip(*pts)) if pts else ([],) * 4
    n_params = 3 + a.degree + 1
    if len(pts) <= n_params:
        fail(f"{len(pts)} (phi, rate) points with >= 2 seeds in the window for N = {n}: a fit "
             f"with degree {a.degree} needs more than {n_params}")
    lnO, err = np.log(O), dO / O
    theta, cov, chi2, dof = fit(phi, rate, lnO, err, a.degree, a.start)
    scale = max(1.0, np.sqrt(chi2 / dof))
    sd = np.sqrt(np.diag(cov)) * scale
    phi_j, q, inv = theta[:3]
    znu = 1.0 / inv
    d_znu = sd[2] / inv ** 2
    # y = q znu and beta = znu - y = znu (1 - q), errors by linear propagation with covariance
    c = cov[:3, :3] * scale ** 2
    g_y = np.array([0.0, znu, -q / inv ** 2])
    g_b = np.array([0.0, -znu, -(1.0 - q) / inv ** 2])
    y, d_y = q * znu, np.sqrt(g_y @ c @ g_y)
    beta, d_beta = znu * (1.0 - q), np.sqrt(g_b @ c @ g_b)
    os.makedirs(a.outdir, exist_ok=True)
    rows = [("N", n), ("points", len(pts)), ("degree", a.degree), ("phi_J", phi_j), ("phi_J_error", sd[0]),
            ("q", q), ("q_error", sd[1]), ("znu", znu), ("znu_error", d_znu), ("y", y), ("y_error", d_y),
            ("beta", beta), ("beta_error", d_beta), ("chi2_per_dof", chi2 / dof)]
    tsv = os.path.join(a.outdir, f"scaling_{a.observable}.tsv")
    with open(tsv, "w") as t:
        for k, v in rows:
            t.write(f"{k}\t{v}\n")
    print(f"{a.observable}, N = {n}, {len(pts)} points, ln F of degree {a.degree}:")
    print(f"  phi_J = {phi_j:.5f} +- {sd[0]:.5f}   q = {q:.4f} +- {sd[1]:.4f}   znu = {znu:.3f} +- {d_znu:.3f}")
    print(f"  y = {y:.3f} +- {d_y:.3f}   beta = {beta:.3f} +- {d_beta:.3f}   chi2/dof = {chi2 / dof:.2f}")
    x = (phi - phi_j) / rate ** inv
    fig, ax = plt.subplots(figsize=(5, 4))
    for r in sorted(set(rate)):
        s = rate == r
        ax.errorbar(x[s], O[s] / r ** q, dO[s] / r ** q, marker="o", ms=3, ls="none", capsize=2,
                    label=f"rate = {r:g}")
    xs = np.linspace(x.min(), x.max(), 200)
    ax.plot(xs, np.exp(np.polyval(theta[3:][::-1], xs)), "k-", lw=1, label="fit")
    ax.set_yscale("log")
    ax.set_xlabel(r"$(\phi-\phi_J)/\dot\gamma^{1/z\nu}$")
    ax.set_ylabel(f"{a.observable} / " + r"$\dot\gamma^{q}$")
    ax.set_title(f"N = {n}: phi_J = {phi_j:.4f}, q = {q:.3f}, znu = {znu:.2f}", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(a.outdir, f"collapse_{a.observable}.png"), dpi=120)
    print(f"table {tsv}, figure {a.outdir}/collapse_{a.observable}.png")


if __name__ == "__main__":
    main()
