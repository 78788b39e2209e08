"""usage: compare_replica_sets.py A.h5 B.h5
Passes when archives A and B hold the same replicas (matched by N, phi, rate and seed, at any
position in their sweeps), every one done in both, with the same identity and bitwise identical
time series, final configurations and g_y (NaN padding compared as equal)."""
import sys

import h5py
import numpy as np
from archive_rows import replica_row

a, b = (h5py.File(p, "r") for p in sys.argv[1:3])


def keys(f):
    r = f["replicas"]
    out = {}
    for k in range(len(r["status"])):
        key = (int(r["N"][k]), float(r["phi"][k]), float(r["rate"][k]), int(r["seed"][k]))
        assert key not in out, f"replica {key} twice"
        out[key] = k
    return out


ka, kb = keys(a), keys(b)
assert set(ka) == set(kb), f"different replicas: only in A {sorted(set(ka) - set(kb))}, only in B {sorted(set(kb) - set(ka))}"
moved = 0
for key in sorted(ka):
    i, j = ka[key], kb[key]
    moved += i != j
    assert a["replicas/status"][i] == 2 and b["replicas/status"][j] == 2, f"{key} not done"
    assert a["replicas/identity"][i] == b["replicas/identity"][j], key
    for group in ("timeseries", "final", "correlation"):
        for name in a[group]:
            x = np.atleast_1d(replica_row(a, group, name, i))
            y = np.atleast_1d(replica_row(b, group, name, j))
            m = min(x.size, y.size)  # padding (NaN) follows each campaign's largest replica
            assert np.isnan(x[m:]).all() and np.isnan(y[m:]).all(), (key, group, name)
            same = (x[:m] == y[:m]) | (np.isnan(x[:m]) & np.isnan(y[:m]))
            assert same.all(), f"{key}: {group}/{name} differs"
print(f"{len(ka)} replicas bitwise equal ({moved} at other positions)")
