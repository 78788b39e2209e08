#!/usr/bin/python3
"""Critical scaling of the flow curves of jamsim sheared-flow campaigns (thesis §5.2; Olsson & Teitel 2007).

usage: tools/analyze_scaling.py ARCHIVE [ARCHIVE ...] OUTDIR [--observable pressure|shear_stress]
           [--N N] [--phi-min X] [--phi-max X] [--rate-max R] [--degree K]
           [--start PHI_J Q ZNU]

ARCHIVE: campaign archives, shards of one campaign or several campaigns of one model read
together (shards merged; a replica held by several archives counted once). OUTDIR: the
output directory (created if needed).

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
are left out (no error estimate). A thin command over tools/jamsim_analysis (scaling.py);
jamsim_analyze.py collapse adds steady-state detection, corrections to scaling and a
bootstrap over seeds.

Writes OUTDIR/scaling_<observable>.tsv (the fitted parameters) and
OUTDIR/collapse_<observable>.png (O/rate^q against |x|, both branches: one curve each if
the scaling holds).
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from jamsim_analysis import AnalysisError  # noqa: E402
from jamsim_analysis import figures, scaling, stats  # noqa: E402
from jamsim_analysis.cli import _flow_archive, output_directory, run_script  # noqa: E402

COLUMNS = {"pressure": "pressure", "shear_stress": "shear_stress"}


def seed_averages(paths, observable):
    """Averages over seeds per (model, N, phi, rate) of each finished replica's mean over
    strain >= its transient (the package's steady windows)."""
    run = _flow_archive(paths)
    table = stats.replica_averages(run, [observable], detect=False)
    table = table[table["left_out"] == ""]
    if "rate" not in table or not (table["rate"] > 0).any():
        raise AnalysisError(f"{', '.join(paths)} has no finished replicas with rate > 0")
    if len(set(table["model"])) > 1:
        raise AnalysisError(f"{', '.join(paths)} hold models {', '.join(sorted(set(table['model'])))}: "
                            "fit one model at a time (jamsim_analyze.py compare fits two together)")
    return stats.group_averages(table[table["rate"] > 0], [observable])


def parser():
    ap = argparse.ArgumentParser(prog="analyze_scaling.py", description=__doc__.split("\n")[0],
                                 epilog=__doc__.split("\n\n", 1)[1],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("archives", nargs="+", metavar="ARCHIVE",
                    help="campaign archives or shards of one model (read together)")
    ap.add_argument("outdir", metavar="OUTDIR", help="output directory (created if needed)")
    ap.add_argument("--observable", choices=sorted(COLUMNS), default="pressure")
    ap.add_argument("--N", type=int, help="system size to fit (default: the largest)")
    ap.add_argument("--phi-min", type=float, default=-np.inf)
    ap.add_argument("--phi-max", type=float, default=np.inf)
    ap.add_argument("--rate-max", type=float, default=np.inf)
    ap.add_argument("--degree", type=int, default=3, help="degree K of ln F(x) (default 3)")
    ap.add_argument("--start", type=float, nargs=3, default=[0.843, 0.28, 3.5],
                    metavar=("PHI_J", "Q", "ZNU"), help="start values (default 0.843 0.28 3.5)")
    return ap


def analyze(a):
    if a.degree < 0:
        raise AnalysisError(f"--degree = {a.degree} is not allowed: an integer >= 0")
    output_directory(a.outdir, create=False)
    groups = seed_averages(a.archives, a.observable)
    sizes = sorted(int(n) for n in groups["N"].unique())
    n = a.N if a.N is not None else sizes[-1]
    if n not in sizes:
        raise AnalysisError(f"--N = {n} is not in {', '.join(a.archives)} (sizes there: {', '.join(map(str, sizes))})")
    try:
        pts = scaling.collapse_points(groups, a.observable, n, (a.phi_min, a.phi_max), a.rate_max)
        fit = scaling.fit_collapse(pts, a.degree, start=tuple(a.start), observable=a.observable,
                                   multistart=False)
    except AnalysisError as e:
        raise AnalysisError(f"{e} (N = {n}, points with >= 2 seeds)") from None
    v, sd = fit.values, fit.errors
    phi_j, q, znu, y, beta = (v[k] for k in ("phi_J", "q", "znu", "y", "beta"))
    chi2, dof = fit.chi2, fit.dof
    pts = fit.points
    output_directory(a.outdir)
    rows = [("N", n), ("points", len(pts)), ("degree", a.degree), ("phi_J", phi_j), ("phi_J_error", sd["phi_J"]),
            ("q", q), ("q_error", sd["q"]), ("znu", znu), ("znu_error", sd["znu"]), ("y", y), ("y_error", sd["y"]),
            ("beta", beta), ("beta_error", sd["beta"]), ("chi2_per_dof", chi2 / dof)]
    tsv = os.path.join(a.outdir, f"scaling_{a.observable}.tsv")
    with open(tsv, "w") as t:
        for k, v in rows:
            t.write(f"{k}\t{v}\n")
    print(f"{a.observable}, N = {n}, {len(pts)} points, ln F of degree {a.degree}:")
    print(f"  phi_J = {phi_j:.5f} +- {sd['phi_J']:.5f}   q = {q:.4f} +- {sd['q']:.4f}   znu = {znu:.3f} +- {sd['znu']:.3f}")
    print(f"  y = {y:.3f} +- {sd['y']:.3f}   beta = {beta:.3f} +- {sd['beta']:.3f}   chi2/dof = {chi2 / dof:.2f}")
    figures.collapse_figure(fit, os.path.join(a.outdir, f"collapse_{a.observable}.png"))
    print(f"table {tsv}, figure {a.outdir}/collapse_{a.observable}.png")


if __name__ == "__main__":
    sys.exit(run_script("analyze_scaling.py", analyze, parser().parse_args()))
