"""Check a replica file written by `jamsim replica` against the documented layout."""
import re
import sys

import h5py
import numpy as np

path, log = sys.argv[1], sys.argv[2]
columns = ["time", "strain", "energy_per_particle", "pressure", "shear_stress",
           "contact_number", "nonaffine_velocity_sq"]
with h5py.File(path, "r") as f:
    a = f.attrs
    assert a["model"] == "RD0" and a["N"] == 64 and a["phi"] == 0.8 and a["rate"] == 1e-3
    assert a["seed"] == 5 and a["integrator"] == "euler" and a["dt"] == 0.2
    assert len(a["code_version"]) > 0 and len(a["build_flags"]) > 0
    ts = f["timeseries"]
    n = len(ts["time"])
    # strain 0.3 at 0.01 per sample: 31 rows (both ends included)
    assert n == 31, n
    for c in columns:
        d = ts[c]
        assert d.shape == (n,), (c, d.shape)
        assert "units" in d.attrs and "description" in d.attrs, c
        assert np.all(np.isfinite(d[...])), c
    assert np.allclose(ts["strain"][...], 1e-3 * ts["time"][...])
    assert np.all(np.diff(ts["time"][...]) > 0)
    assert np.all(ts["pressure"][...] > 0)
    fin = f["final"]
    L = fin.attrs["box_side"]
    assert -0.5 <= fin.attrs["box_strain"] < 0.5
    x, y, d = fin["x"][...], fin["y"][...], fin["diameter"][...]
    assert x.shape == y.shape == d.shape == (64,)
    assert np.all((0 <= x) & (x < L)) and np.all((0 <= y) & (y < L))
    assert np.sum(d == 1.0) == 32 and np.sum(d == 1.4) == 32
    assert abs(np.sum(np.pi * d**2 / 4) / L**2 - 0.8) < 1e-12
    strain = ts["strain"][...]
    mean_p = ts["pressure"][...][strain >= 0.1].mean()
    assert abs(mean_p - a["mean_pressure"]) <= 1e-12 * abs(mean_p)
printed = open(log).read()
m = re.search(r"<p>\s*=\s*(\S+)", printed)
assert m and abs(float(m.group(1)) - mean_p) <= 1e-8 * abs(mean_p), printed
print("replica file OK:", n, "rows")
