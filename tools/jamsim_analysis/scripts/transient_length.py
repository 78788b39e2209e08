"""Transient length of the pressure in jamsim sheared-flow campaigns.

usage: transient_length.py ARCHIVE [ARCHIVE ...] [--rate R] [--settled-from S]

ARCHIVE: campaign archives, shards of one campaign or several campaigns read together
(shards merged; a replica held by several archives counted once); finished replicas with
rate > 0 only.
--rate R: only this shear rate. --settled-from S: the strain from which every run is steady
(default: the second half of each group's runs).

For each (model, N, phi, rate) the pressure is averaged over seeds, row by row. The
steady-state value is its mean over strain >= S and its error the standard error over seeds
of the per-seed means there. The seed average is smoothed over 0.1 strain; the band is twice
the scatter of that smoothed curve over the steady part (how far a 0.1-strain average of
these seeds strays in steady state). The transient is the strain at which the smoothed curve
first comes within the band (later excursions are the noise the band measures).
Prints one line per (model, N, phi, rate): N, phi, rate, seeds, steady p, its error, the
band and the transient strain (nan: never within the band)."""
import argparse
import sys

# numpy and the archive reader are imported where they are used, so that --help and argument
# errors do not wait for them.
from .. import AnalysisError
from ..command_support import prog_name, run_script


def groups_of(run, rate):
    """Finished replicas with rate > 0 per (model, N, phi, rate)."""
    import numpy as np
    done = run.done()
    done = done[done["rate"] > 0] if "rate" in done else done.iloc[0:0]
    if run.done().empty:
        raise AnalysisError(f"no finished replica: {run.why_none_done()}")
    if done.empty:
        raise AnalysisError("no finished replica with rate > 0: transient_length.py needs sheared-flow "
                            f"campaigns (models here: {', '.join(run.models)})")
    groups = {}
    for rep in done.itertuples():
        key = (rep.model, int(rep.N), float(rep.phi), float(rep.rate))
        if rate is None or np.isclose(key[3], rate):
            groups.setdefault(key, []).append(int(rep.replica))
    if not groups:
        raise AnalysisError(f"--rate {rate:g} is not in the data (rates: "
                            f"{', '.join(f'{v:g}' for v in sorted(done['rate'].unique()))})")
    return groups


def transient(a):
    import numpy as np
    from .. import open_archives
    run = open_archives(a.archives)
    groups = groups_of(run, a.rate)
    models = {k[0] for k in groups}
    # Printed once every group is computed: a refusal comes alone (the header came before it).
    lines = [("model  " if len(models) > 1 else "") +
             f"{'N':>6} {'phi':>6} {'rate':>8} {'seeds':>5} {'steady p':>11} {'error':>9} {'band':>9} "
             f"{'transient strain':>16}"]
    for (model, n, phi, rate), ks in sorted(groups.items()):
        p_rows = [run.series(k, "pressure") for k in ks]
        m = min(len(v) for v in p_rows)
        strain = run.series(ks[0], "strain")[:m]
        p = np.array([v[:m] for v in p_rows])
        if m < 2:
            raise AnalysisError(f"N = {n}, phi = {phi:g}, rate = {rate:g}: fewer than 2 samples")
        where = f"N = {n}, phi = {phi:g}, rate = {rate:g}"
        if not (np.all(np.isfinite(p)) and np.all(np.isfinite(strain)) and np.all(np.diff(strain) > 0)):
            raise AnalysisError(f"{where}: the pressure or strain series is not finite and increasing (a damaged "
                                "archive?)")
        start = a.settled_from if a.settled_from is not None else strain[-1] / 2
        settled = strain >= start
        if settled.sum() < 2:
            raise AnalysisError(f"--settled-from = {start:g} is not allowed: the runs of {where} end at strain "
                                f"{strain[-1]:g}; at least 2 samples must follow it")
        per_seed = p[:, settled].mean(axis=1)
        steady = per_seed.mean()
        error = per_seed.std(ddof=1) / np.sqrt(len(ks)) if len(ks) > 1 else float("nan")
        mean = p.mean(axis=0)
        width = min(m, max(1, int(round(0.1 / (strain[1] - strain[0])))))
        smooth = np.convolve(mean, np.ones(width) / width, mode="valid")  # whole windows only
        centres = np.arange(len(smooth)) + width // 2
        inside_steady = smooth[settled[centres]]
        band = 2 * np.std(inside_steady, ddof=1) if len(inside_steady) > 1 else float("nan")
        inside = centres[np.abs(smooth - steady) <= band]
        length = strain[inside[0] - width // 2] if len(inside) else float("nan")
        lines.append((f"{model:<6} " if len(models) > 1 else "") +
                     f"{n:>6} {phi:>6.3f} {rate:>8.1e} {len(ks):>5} {steady:>11.4e} {error:>9.2e} {band:>9.2e} "
                     f"{length:>16.2f}")
    print("\n".join(lines))


def main(argv=None):
    ap = argparse.ArgumentParser(prog=prog_name("transient_length.py"), description=__doc__.split("\n\n")[0],
                                 epilog=__doc__.split("\n\n", 2)[2],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("archives", nargs="+", metavar="ARCHIVE", help="campaign archives or shards (read together)")
    ap.add_argument("--rate", type=float, metavar="R", help="only this shear rate")
    ap.add_argument("--settled-from", type=float, metavar="S", help="strain from which the run is steady")
    a = ap.parse_args(argv)
    if a.settled_from is not None and not (a.settled_from >= 0 and a.settled_from < float("inf")):
        ap.error(f"--settled-from = {a.settled_from} is not allowed: a strain >= 0 within the runs")
    return run_script(prog_name("transient_length.py"), transient, a)


if __name__ == "__main__":
    sys.exit(main())
