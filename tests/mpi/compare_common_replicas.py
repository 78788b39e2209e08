"""usage: compare_common_replicas.py A.h5 B.h5 EXPECTED
Passes when the replicas that archives A and B share (same N, phi, rate and seed) have the same
identity and bitwise identical time series, final configurations and g_y, and there are
EXPECTED of them: a replica depends only on its own parameters, not on its place in a sweep."""
import sys

import h5py
import numpy as np
from archive_rows import replica_row

a, b = (h5py.File(p, "r") for p in sys.argv[1:3])
expected = int(sys.argv[3])


def keys(f):
    r = f["replicas"]
    return {(int(r["N"][k]), float(r["phi"][k]), float(r["rate"][k]), int(r["seed"][k])): k
            for k in range(len(r["status"]))}


ka, kb = keys(a), keys(b)
common = sorted(set(ka) & set(kb))
assert len(common) == expected, (len(common), expected)
for key in common:
    i, j = ka[key], kb[key]
    assert i != j or key == common[0], "test needs replicas at different sweep positions"
    assert a["replicas/status"][i] == 2 and b["replicas/status"][j] == 2, key
    assert a["replicas/identity"][i] == b["replicas/identity"][j], key
    for group in ("timeseries", "final", "correlation"):
        for name in a[group]:
            x = np.atleast_1d(replica_row(a, group, name, i))
            y = np.atleast_1d(replica_row(b, group, name, j))
            m = min(x.size, y.size)  # padding (NaN) follows the campaign's largest replica
            assert np.isnan(x[m:]).all() and np.isnan(y[m:]).all(), (key, group, name)
            x, y = x[:m], y[:m]
            same = (x == y) | (np.isnan(x) & np.isnan(y))
            assert same.all(), f"{key}: {group}/{name} differs"
ids = b["replicas/identity"][...]
assert len(set(ids.tolist())) == len(set((n, p, r) for n, p, r, _ in kb)), "identity ignores the seed, keys the rest"
print(f"{len(common)} shared replicas bitwise equal at sweep positions",
      [ka[k] for k in common], "and", [kb[k] for k in common])
