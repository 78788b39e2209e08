"""usage: check_rate_zero.py REPO_ROOT ARCHIVE.h5
Checks an archive of dynamics at rate 0 (tests/data/campaigns/rate_zero.toml: time 20,
transient 5, a sample every 1, a frame every 5): every replica finished with its samples at
times 0, 1, ..., 20 and strain 0, its frames at times 0, 5, ..., 20; and the analysis
(jamsim_analysis.stats.replica_averages) measures the transient in time, so each replica's
steady window starts at time 5 or later and keeps at most the 16 samples after it."""
import sys

import h5py
import numpy as np

root, path = sys.argv[1:3]
sys.path.insert(0, f"{root}/tools")
from jamsim_analysis.archive import Archive  # noqa: E402
from jamsim_analysis.stats import replica_averages  # noqa: E402

with h5py.File(path, "r") as f:
    r, ts = f["replicas"], f["timeseries"]
    assert (r["status"][...] == 2).all(), r["status"][...]
    assert (r["rate"][...] == 0).all() and (r["time"][...] == 20).all()
    for k in range(r["status"].shape[0]):
        m = int(r["n_samples"][k])
        assert m == 21, m
        assert np.allclose(ts["time"][k, :m], np.arange(21.0)), ts["time"][k, :m]
        assert (ts["strain"][k, :m] == 0).all()
        assert np.allclose(f["frames/strain"][k], np.arange(0.0, 21.0, 5.0)), f["frames/strain"][k]
table = replica_averages(Archive([path]), ["pressure"], detect=False)
assert len(table) == 2, table
for _, row in table.iterrows():
    assert row["window_start"] >= 5 and row["samples"] <= 16, row
    assert np.isfinite(row["pressure"]) and not str(row["left_out"]).startswith("empty"), row
print("ok")
