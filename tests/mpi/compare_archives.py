"""usage: compare_archives.py A.h5 B.h5
Passes when both archives have every replica done and bitwise identical time series and
final configurations (NaN padding compared as equal)."""
import sys

import h5py
import numpy as np

a, b = (h5py.File(p, "r") for p in sys.argv[1:3])
assert a.attrs["spec_fingerprint"] == b.attrs["spec_fingerprint"], "different campaigns"
for f, name in ((a, sys.argv[1]), (b, sys.argv[2])):
    status = f["replicas/status"][...]
    assert (status == 2).all(), f"{name}: not all replicas done: {status}"
compared = 0
for group in ("timeseries", "final", "correlation"):
    for key in a[group]:
        x, y = a[group][key][...], b[group][key][...]
        assert x.shape == y.shape, (group, key)
        same = (x == y) | (np.isnan(x) & np.isnan(y))
        assert same.all(), f"{group}/{key} differs in replicas {sorted(set(np.argwhere(~same)[:, 0]))}"
        compared += x.size
print(f"identical: {len(a['replicas/status'])} replicas, {compared} values")
