"""Figures of the flow curves of jamsim sheared-flow campaigns (one archive, its shards, or
several archives together).

usage: tools/plot_campaign.py ARCHIVE [ARCHIVE ...] OUTDIR [--replica R]

ARCHIVE: campaign archives, shards of one campaign or single-replica files of a sheared-flow
model (RD0, CD0, RD0T, RD, CD, CDn, CDt), read together: shards are merged, and a replica
held by several archives (a campaign and its grown or merged version) is counted once.
OUTDIR: the output directory (created if needed). Writes
  OUTDIR/flow_curves.png      p/rate and sigma/rate against phi, one curve per (N, rate)
  OUTDIR/stress_vs_rate.png   sigma and p against rate, one curve per (N, phi) (log-log)
  OUTDIR/replica_<R>.png      time series of replica R (--replica R; default: the first
                              finished one); R numbers the replicas of the archives read
                              together as `jamsim_analyze.py summary ARCHIVE...` lists them
                              (for one archive: its replica id)
Averages: each replica's mean over strain >= its transient, then mean and standard error
over the seeds of each (model, N, phi, rate). Only replicas with status "done" are used.
A thin command over tools/jamsim_analysis (stats.py).
"""
import argparse
import os
import sys

# numpy, matplotlib (Agg) and the analysis modules are imported where they are used, so that
# --help and argument errors do not wait for them.
from .. import AnalysisError
from ..command_support import describe_ids, output_directory, prog_name, pyplot, run_script

OBSERVABLES = ["pressure", "shear_stress"]


def seed_averages(run):
    """Mean and standard error over seeds per (model, N, phi, rate) of the finished replicas
    with rate > 0."""
    from .. import stats
    table = stats.replica_averages(run, OBSERVABLES, detect=False)
    table = table[(table["left_out"] == "") & (table["rate"] > 0)]
    if table.empty:
        raise AnalysisError("no finished replica with rate > 0 to draw flow curves from")
    return stats.group_averages(table, OBSERVABLES)


def label(row_keys, models):
    return ", ".join(f"{k} = {v:g}" if k != "model" else str(v) for k, v in row_keys.items()
                     if k != "model" or len(models) > 1)


def flow_curves(groups, path, title):
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    models = sorted(groups["model"].unique())
    for key, part in groups.groupby(["model", "N", "rate"]):
        part = part.sort_values("phi")
        rate = key[2]
        for ax, name in zip(axes, OBSERVABLES):
            ax.errorbar(part["phi"], part[name] / rate, part[f"{name}_error"] / rate, marker="o", ms=3,
                        capsize=2, label=label(dict(model=key[0], N=key[1], rate=rate), models))
    for ax, name in zip(axes, ("p", r"\sigma")):
        ax.set_yscale("log")
        ax.set_xlabel(r"$\phi$")
        ax.set_ylabel(f"${name}/\\dot\\gamma$")
    axes[0].legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def stress_vs_rate(groups, path, title):
    import numpy as np
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    models = sorted(groups["model"].unique())
    keys = list(groups.groupby(["model", "N", "phi"]).groups)
    colors = plt.cm.viridis(np.linspace(0, 1, max(len(keys), 1)))
    for key, c in zip(keys, colors):
        part = groups[(groups["model"] == key[0]) & (groups["N"] == key[1]) & (groups["phi"] == key[2])]
        part = part.sort_values("rate")
        for ax, name in zip(axes, ("shear_stress", "pressure")):
            ax.errorbar(part["rate"], part[name], part[f"{name}_error"], marker="o", ms=3, color=c, capsize=2,
                        label=label(dict(model=key[0], N=key[1], phi=key[2]), models))
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


def replica_series(run, r, path):
    plt = pyplot()
    rep = run.replicas.iloc[r]
    strain = run.series(r, "strain")
    panels = [("pressure", "$p$"), ("shear_stress", r"$\sigma$"),
              ("energy_per_particle", "$E/N$"), ("contact_number", "$z$")]
    fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(6, 8))
    for ax, (name, text) in zip(axes, panels):
        v = run.series(r, name)
        ax.plot(strain, v, lw=0.8)
        if name == "energy_per_particle" and (v > 0).all():
            ax.set_yscale("log")
        ax.set_ylabel(text)
    axes[-1].set_xlabel(r"strain $\dot\gamma t$")
    axes[0].set_title(f"replica {r}: {rep['model']} N={int(rep['N'])} $\\phi$={rep['phi']:g} "
                      f"$\\dot\\gamma$={rep['rate']:g} seed={int(rep['seed'])}")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot(a):
    from .. import open_archives
    run = open_archives(a.archives)
    from ..report import MASSIVE, OVERDAMPED  # after the archives: a missing one is reported sooner
    other = sorted(set(run.models) - set(OVERDAMPED + MASSIVE))
    if other:
        raise AnalysisError(f"{', '.join(a.archives)}: model {', '.join(other)} has no flow curves; "
                            f"plot_campaign.py needs sheared-flow campaigns ({', '.join(OVERDAMPED + MASSIVE)}); "
                            "for static campaigns use analyze_jamming.py")
    done = run.done()
    if done.empty:
        raise AnalysisError(f"no finished replica in {', '.join(a.archives)}: {run.why_none_done()}")
    groups = seed_averages(run)
    if a.replica is not None and a.replica not in set(done["replica"]):
        raise AnalysisError(f"--replica {a.replica} is not a finished replica (allowed: "
                            f"{describe_ids(done['replica'].to_list())})")
    output_directory(a.outdir)
    campaigns = sorted(set(run.replicas["campaign"]))
    title = f"{' + '.join(campaigns)} ({', '.join(run.models)})"
    written = [os.path.join(a.outdir, "flow_curves.png"), os.path.join(a.outdir, "stress_vs_rate.png")]
    flow_curves(groups, written[0], title)
    stress_vs_rate(groups, written[1], title)
    r = a.replica if a.replica is not None else int(done["replica"].iloc[0])
    written.append(os.path.join(a.outdir, f"replica_{r}.png"))
    replica_series(run, r, written[-1])
    for w in written:
        print(f"figure written to {w}")


def parser():
    ap = argparse.ArgumentParser(prog=prog_name("plot_campaign.py"), description=__doc__.split("\n\n")[0],
                                 epilog=__doc__.split("\n\n", 2)[2],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("archives", nargs="+", metavar="ARCHIVE",
                    help="campaign archives, shards or single-replica files (read together)")
    ap.add_argument("outdir", metavar="OUTDIR", help="output directory (created if needed)")
    ap.add_argument("--replica", type=int, default=None, metavar="R",
                    help="the replica whose time series is drawn (default: the first finished one)")
    return ap


def main(argv=None):
    """The command line (exit status: 0, or 2 on bad input)."""
    return run_script(prog_name("plot_campaign.py"), plot, parser().parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
