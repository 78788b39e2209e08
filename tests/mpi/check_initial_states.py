"""usage: check_initial_states.py SOURCE.h5 STARTED.h5
Every replica of STARTED began from the final state of the SOURCE replica with the same N,
phi and seed: its first row's E/N and pressure equal the source's. The positions are the same
but summed in another order and, in the source, formed as base + offset: 1e-12 relative, and
an absolute floor for unjammed states (overlaps ~1e-8 d_s) from the positions' round-off
eps L ~ 1e-15 d_s: 1e-20 k_e in E/N, 1e-15 k_e/d_s^2 in p."""
import sys

import h5py
import numpy as np

src, run = (h5py.File(p, "r") for p in sys.argv[1:3])
assert run.attrs["initial"] == "static-small.h5"
r, s = run["replicas"], src["replicas"]
checked = 0
for k in range(len(r["status"])):
    key = (r["N"][k], r["phi"][k], r["seed"][k])
    j = [i for i in range(len(s["status"])) if (s["N"][i], s["phi"][i], s["seed"][i]) == key]
    assert len(j) == 1, (key, j)
    for name, floor in (("energy_per_particle", 1e-20), ("pressure", 1e-15)):
        a, b = run["timeseries/" + name][k, 0], src["timeseries/" + name][j[0], 0]
        assert abs(a - b) <= 1e-12 * abs(b) + floor, (k, name, a, b)
    checked += 1
print(f"{checked} replicas start from their source states")
