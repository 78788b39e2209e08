"""usage: check_grown.py BEFORE.h5 AFTER.h5 NEW
Passes when AFTER (an archive grown from a copy of BEFORE) holds every replica of BEFORE
(matched by N, phi, rate and seed, wherever it sits in either sweep) with the same status and
bitwise the same data and bookkeeping, including its wall time and rank, so it was kept, not
computed again; and exactly NEW further replicas, each done."""
import sys

import h5py
import numpy as np
from archive_rows import replica_row

before, after = (h5py.File(p, "r") for p in sys.argv[1:3])
expected_new = int(sys.argv[3])


def keys(f):
    r = f["replicas"]
    return {(int(r["N"][k]), float(r["phi"][k]), float(r["rate"][k]), int(r["seed"][k])): k
            for k in range(len(r["status"]))}


def same(x, y):
    x, y = np.atleast_1d(x), np.atleast_1d(y)
    m = min(x.size, y.size)  # rows are padded with NaN to each campaign's longest replica
    if not (np.isnan(x[m:]).all() and np.isnan(y[m:]).all()):
        return False
    x, y = x[:m], y[:m]
    return bool(((x == y) | (np.isnan(x) & np.isnan(y))).all())


kb, ka = keys(before), keys(after)
missing = set(kb) - set(ka)
assert not missing, f"replicas of {sys.argv[1]} lost: {sorted(missing)}"
for key, i in kb.items():
    j = ka[key]
    assert before["replicas/status"][i] == after["replicas/status"][j], (key, "status")
    if before["replicas/status"][i] == 0:
        continue
    for name in ("wall_seconds", "rank", "force_evaluations", "rows_written", "identity"):
        assert same(before["replicas"][name][i], after["replicas"][name][j]), \
            f"{key}: replicas/{name} differs: computed again, not kept"
    for group in ("timeseries", "final", "correlation"):
        for name in before[group]:
            assert same(replica_row(before, group, name, i), replica_row(after, group, name, j)), \
                f"{key}: {group}/{name} differs"
new = sorted(set(ka) - set(kb))
assert len(new) == expected_new, (len(new), expected_new)
for key in new:
    assert after["replicas/status"][ka[key]] == 2, f"new replica {key} not done"
print(f"{len(kb)} replicas kept bitwise (wall time and rank included), {len(new)} new ones done")
