"""usage: compare_archives.py A.h5 B.h5
Passes when both archives have every replica done and bitwise identical time series and
final configurations, and configuration frames where the archives keep them (NaN padding
compared as equal)."""
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
# Configuration frames: the strains (NaN where none) and each frame's disks where one exists.
assert ("frames" in a) == ("frames" in b), "frames in one archive only"
if "frames" in a:
    for key in ("strain", "box_strain"):
        x, y = a["frames"][key][...], b["frames"][key][...]
        assert x.shape == y.shape and ((x == y) | (np.isnan(x) & np.isnan(y))).all(), f"frames/{key} differs"
        compared += x.size
    offset, n = a["replicas/particle_offset"][...], a["replicas/N"][...].astype(int)
    strain = a["frames/strain"][...]
    for key in ("x", "y"):
        x, y = a["frames"][key][...], b["frames"][key][...]
        for r in range(len(offset)):
            for k in np.flatnonzero(~np.isnan(strain[r])):
                cols = slice(offset[r], offset[r] + n[r])
                assert (x[k, cols] == y[k, cols]).all(), f"frames/{key} differs: replica {r}, frame {k}"
                compared += n[r]
print(f"identical: {len(a['replicas/status'])} replicas, {compared} values")
