#!/usr/bin/python3
"""Figures from a jamsim campaign archive.

usage: tools/plot_campaign.py ARCHIVE.h5 OUTDIR [--replica ID]

Writes
  OUTDIR/flow_curves.png      p/rate and sigma/rate against phi, one curve per rate
  OUTDIR/stress_vs_rate.png   sigma and p against rate, one curve per phi (log-log)
  OUTDIR/replica_<ID>.png     time series of one replica (default: the first done one)
Averages: each replica's mean over strain >= its transient, then mean and standard error
over the seeds of each (N, phi, rate). Only replicas with status "done" are used.
"""
import argparse
import collections
import os
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def steady_means(f):
    r = f["replicas"]
    status = r["status"][...]
    out = collections.defaultdict(lambda: {"p": [], "s": []})
    ts = f["timeseries"]
    for k in np.flatnonzero(status == 2):
        n = int(r["n_samples"][k])
        strain = ts["strain"][k, :n]
        keep = strain >= r["transient"][k]
        key = (int(r["N"][k]), float(r["phi"][k]), float(r["rate"][k]))
        out[key]["p"].append(ts["pressure"][k, :n][keep].mean())
        out[key]["s"].append(ts["shear_stress"][k, :n][keep].mean())
    table = {}
    for key, v in out.items():
        p, s = np.array(v["p"]), np.array(v["s"])
        err = lambda a: a.std(ddof=1) / np.sqrt(a.size) if a.size > 1 else 0.0
        table[key] = (p.mean(), err(p), s.mean(), err(s), p.size)
    return table


def flow_curves(table, path, title):
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    rates = sorted({k[2] for k in table})
    for rate in rates:
        pts = sorted((k[1], v) for k, v in table.items() if k[2] == rate)
        phi = [p for p, _ in pts]
        for ax, (m, e) in zip(axes, ((0, 1), (2, 3))):
            ax.errorbar(phi, [v[m] / rate for _, v in pts], [v[e] / rate for _, v in pts],
                        marker="o", ms=3, capsize=2, label=f"rate = {rate:g}")
    for ax, name in zip(axes, ("p", r"\sigma")):
        ax.set_yscale("log")
        ax.set_xlabel(r"$\phi$")
        ax.set_ylabel(f"${name}/\\dot\\gamma$")
    axes[0].legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def stress_vs_rate(table, path, title):
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    phis = sorted({k[1] for k in table})
    colors = plt.cm.viridis(np.linspace(0, 1, len(phis)))
    for phi, c in zip(phis, colors):
        pts = sorted((k[2], v) for k, v in table.items() if k[1] == phi)
        rate = [r for r, _ in pts]
        axes[0].errorbar(rate, [v[2] for _, v in pts], [v[3] for _, v in pts], marker="o",
                         ms=3, color=c, capsize=2, label=f"$\\phi$ = {phi:g}")
        axes[1].errorbar(rate, [v[0] for _, v in pts], [v[1] for _, v in pts], marker="o",
                         ms=3, color=c, capsize=2)
    for ax, name in zip(axes, (r"\sigma", "p")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(r"$\dot\gamma$")
        ax.set_ylabel(f"${name}$")
    axes[0].legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def replica_series(f, k, path):
    r, ts = f["replicas"], f["timeseries"]
    n = int(r["n_samples"][k])
    strain = ts["strain"][k, :n]
    panels = [("pressure", "$p$"), ("shear_stress", r"$\sigma$"),
              ("energy_per_particle", "$E/N$"), ("contact_number", "$z$")]
    fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(6, 8))
    for ax, (name, label) in zip(axes, panels):
        v = ts[name][k, :n]
        ax.plot(strain, v, lw=0.8)
        if name == "energy_per_particle" and (v > 0).all():
            ax.set_yscale("log")
        ax.set_ylabel(f"{label} [{ts[name].attrs['units']}]")
    axes[-1].set_xlabel(r"strain $\dot\gamma t$")
    axes[0].set_title(f"replica {k}: N={int(r['N'][k])} $\\phi$={r['phi'][k]:g} "
                      f"$\\dot\\gamma$={r['rate'][k]:g} seed={int(r['seed'][k])}")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("archive")
    ap.add_argument("outdir")
    ap.add_argument("--replica", type=int, default=None)
    a = ap.parse_args()
    try:
        f = h5py.File(a.archive, "r", locking=False)
    except OSError as e:
        sys.exit(f"plot_campaign: cannot open '{a.archive}' as HDF5: {e}")
    os.makedirs(a.outdir, exist_ok=True)
    with f:
        if "replicas" not in f:
            sys.exit(f"plot_campaign: '{a.archive}' is not a jamsim campaign archive")
        done = np.flatnonzero(f["replicas/status"][...] == 2)
        if done.size == 0:
            sys.exit(f"plot_campaign: no finished replica in '{a.archive}' yet")
        title = f"{f.attrs['campaign']} ({f.attrs['model']})"
        table = steady_means(f)
        written = [os.path.join(a.outdir, "flow_curves.png"),
                   os.path.join(a.outdir, "stress_vs_rate.png")]
        flow_curves(table, written[0], title)
        stress_vs_rate(table, written[1], title)
        k = a.replica if a.replica is not None else int(done[0])
        if k not in done:
            sys.exit(f"plot_campaign: replica {k} is not done")
        written.append(os.path.join(a.outdir, f"replica_{k}.png"))
        replica_series(f, k, written[-1])
    for w in written:
        print(f"figure written to {w}")


if __name__ == "__main__":
    main()
