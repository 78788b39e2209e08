"""Plot the time series of one jamsim replica: from a single-replica file (`jamsim replica
-o FILE`) or one replica of campaign archives.

usage: tools/plot_replica.py FILE [FILE ...] FIGURE.png [--replica R]

FILE: a single-replica file, or campaign archives / shards of one campaign (read together
as `jamsim_analyze.py summary FILE...` lists them; shards are merged and a replica held by
several archives is counted once).
FIGURE.png: the figure to write (its directory must exist).
--replica R: which replica to draw, numbered as in that summary (for one archive: its
replica id); needed when the files hold more than one replica.

Draws pressure, shear stress, energy per particle and contact number against the
accumulated strain, with the means over strain >= the replica's transient as dashed lines.
A replica still running is drawn up to its last written row.
"""
import argparse
import sys

# numpy, matplotlib (Agg) and the archive reader are imported where they are used, so that
# --help and argument errors do not wait for them.
from .. import AnalysisError
from ..command_support import FIGURE_SUFFIXES, describe_ids, output_file, prog_name, pyplot, run_script

PANELS = [("pressure", "$p$"), ("shear_stress", r"$\sigma$"), ("energy_per_particle", "$E/N$"),
          ("contact_number", "$z$")]


def choose(run, a):
    """The replica to draw: --replica, or the only one."""
    table = run.replicas
    n = len(table)
    if a.replica is None:
        if n == 1:
            return 0
        raise AnalysisError(f"{', '.join(a.files)} holds {n} replicas: choose one with --replica R "
                            f"(0..{n - 1}; finished: {describe_ids(run.done()['replica'].to_list())}), "
                            "or draw the whole campaign with plot_campaign.py")
    if not 0 <= a.replica < n:
        raise AnalysisError(f"--replica {a.replica} is not allowed: 0..{n - 1} ({', '.join(a.files)})")
    if table["valid_rows"].iat[a.replica] <= 0:
        raise AnalysisError(f"--replica {a.replica} has no rows yet (status {table['status_name'].iat[a.replica]})")
    return a.replica


def plot(a):
    import numpy as np
    from .. import open_archives
    run = open_archives(a.files)
    output_file(a.figure, "FIGURE", a.files, FIGURE_SUFFIXES)
    r = choose(run, a)
    plt = pyplot()
    rep = run.replicas.iloc[r]
    strain = run.series(r, "strain")
    transient = rep.get("transient", 0.0)
    transient = float(transient) if transient is not None and np.isfinite(transient) else 0.0
    fig, axes = plt.subplots(len(PANELS), 1, sharex=True, figsize=(6, 8))
    for ax, (name, text) in zip(axes, PANELS):
        values = run.series(r, name)
        ax.plot(strain, values, lw=0.8, marker="o" if len(values) < 3 else None)
        if name == "energy_per_particle" and len(values) and (values > 0).all():
            ax.set_yscale("log")  # the start-up transient spans decades
        steady = values[strain >= transient]
        if steady.size:
            ax.axhline(steady.mean(), ls="--", color="k", lw=0.8)
        ax.set_ylabel(text)
    axes[-1].set_xlabel(r"strain $\dot\gamma t$")
    rate = rep.get("rate", np.nan)
    axes[0].set_title(f"{rep['model']}  N={int(rep['N'])}  $\\phi$={rep['phi']:g}  "
                      f"$\\dot\\gamma$={rate:g}  seed={int(rep['seed'])}"
                      + (f"  ({rep['status_name']})" if rep["status_name"] != "done" else ""))
    fig.tight_layout()
    fig.savefig(a.figure, dpi=120)
    plt.close(fig)
    print(f"figure written to {a.figure}")


def parser():
    ap = argparse.ArgumentParser(prog=prog_name("plot_replica.py"), description=__doc__.split("\n\n")[0],
                                 epilog=__doc__.split("\n\n", 2)[2],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="+", metavar="FILE",
                    help="a single-replica file, or campaign archives / shards (read together)")
    ap.add_argument("figure", metavar="FIGURE.png", help="the figure to write")
    ap.add_argument("--replica", type=int, metavar="R", help="the replica to draw (needed for a campaign)")
    return ap


def main(argv=None):
    """The command line (exit status: 0, or 2 on bad input)."""
    return run_script(prog_name("plot_replica.py"), plot, parser().parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
