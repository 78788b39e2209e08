"""usage: compare_replica_files.py A.h5 B.h5
Passes when two replica files (jamsim replica -o) hold bitwise the same data: every dataset
(NaN equal to NaN) and every attribute but the wall time and the build description."""
import sys

import h5py
import numpy as np

a, b = (h5py.File(p, "r") for p in sys.argv[1:3])
names = []
a.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
other = []
b.visititems(lambda n, o: other.append(n) if isinstance(o, h5py.Dataset) else None)
assert sorted(names) == sorted(other), f"datasets differ: {sorted(set(names) ^ set(other))}"
for n in names:
    x, y = a[n][...], b[n][...]
    same = x.shape == y.shape and ((x == y) | (np.isnan(x) & np.isnan(y))).all()
    assert same, f"{n} differs"
for key in a.attrs:
    if key in ("wall_seconds", "build_flags"):
        continue
    x, y = a.attrs[key], b.attrs.get(key)
    assert np.array_equal(x, y) or (np.asarray(x).dtype.kind == "f" and np.isnan(x) and np.isnan(y)), \
        f"attribute {key}: {x} against {y}"
print(f"identical: {len(names)} datasets")
