"""usage: check_ladder.py ARCHIVE.h5  (a campaign whose last sample falls on the last step)
A rate-ladder archive: every replica with a predecessor has the same N, phi and seed and the
next higher rate, and its first row is the state its predecessor ended in (E/N and p equal to
the predecessor's last row to 1e-12: the same positions, forces summed after a fresh
neighbour list, so in another order)."""
import sys

import h5py

with h5py.File(sys.argv[1], "r") as f:
    r, ts = f["replicas"], f["timeseries"]
    linked = 0
    for k in range(len(r["status"])):
        j = int(r["predecessor"][k])
        if j < 0:
            assert r["ladder_from"][k] == 0
            continue
        assert (r["N"][k], r["phi"][k], r["seed"][k]) == (r["N"][j], r["phi"][j], r["seed"][j])
        assert r["rate"][j] > r["rate"][k] and r["ladder_from"][k] == r["rate"][j]
        last = int(r["n_samples"][j]) - 1
        for name in ("energy_per_particle", "pressure"):
            a, b = ts[name][k, 0], ts[name][j, last]
            assert abs(a - b) <= 1e-12 * abs(b), (k, j, name, a, b)
        linked += 1
print(f"{linked} replicas start where their predecessors ended")
