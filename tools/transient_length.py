#!/usr/bin/python3
"""Transient length of the pressure in a campaign archive.

usage: transient_length.py ARCHIVE.h5 [--rate R] [--settled-from S]

For each (N, phi, rate) the pressure is averaged over seeds, row by row. The steady-state
value is its mean over strain >= S (default: the second half of the run) and its error the
standard error over seeds of the per-seed means there. The seed average is smoothed over
0.1 strain; the band is twice the scatter of that smoothed curve over the steady part (how
far a 0.1-strain average of these seeds strays in steady state). The transient is the strain
at which the smoothed curve first comes within the band (later excursions are the noise the
band measures). Prints one line per (N, phi, rate)."""
import argparse

import h5py
import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("archive")
    ap.add_argument("--rate", type=float, help="only this shear rate")
    ap.add_argument("--settled-from", type=float, help="strain from which the run is steady")
    a = ap.parse_args()
    with h5py.File(a.archive, "r") as f:
        r, ts = f["replicas"], f["timeseries"]
        groups = {}
        for k in np.flatnonzero(r["status"][...] == 2):
            key = (int(r["N"][k]), float(r["phi"][k]), float(r["rate"][k]))
            if a.rate is None or np.isclose(key[2], a.rate):
                groups.setdefault(key, []).append(k)
        print(f"{'N':>6} {'phi':>6} {'rate':>8} {'seeds':>5} {'steady p':>11} {'error':>9} {'band':>9} {'transient strain':>16}")
        for (n, phi, rate), ks in sorted(groups.items()):
            m = min(int(r["n_samples"][k]) for k in ks)
            strain = ts["strain"][ks[0], :m]
            p = np.array([ts["pressure"][k, :m] for k in ks])
            settled = strain >= (a.settled_from if a.settled_from is not None else strain[-1] / 2)
            per_seed = p[:, settled].mean(axis=1)
            steady, error = per_seed.mean(), per_seed.std(ddof=1) / np.sqrt(len(ks))
            mean = p.mean(axis=0)
            width = max(1, int(round(0.1 / (strain[1] - strain[0]))))
            smooth = np.convolve(mean, np.ones(width) / width, mode="valid")  # whole windows only
            centres = np.arange(len(smooth)) + width // 2
            band = 2 * np.std(smooth[settled[centres]], ddof=1)
            inside = centres[np.abs(smooth - steady) <= band]
            transient = strain[inside[0] - width // 2] if len(inside) else float("nan")
            print(f"{n:>6} {phi:>6.3f} {rate:>8.1e} {len(ks):>5} {steady:>11.4e} {error:>9.2e} {band:>9.2e} {transient:>16.2f}")


if __name__ == "__main__":
    main()
