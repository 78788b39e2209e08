"""usage: check_partial_rows.py ARCHIVE.h5
An interrupted campaign's archive: every running replica shows its rows so far (rows_written
> 0, finite rows up to there, NaN after) and its progress strictly between 0 and 1."""
import sys

import h5py
import numpy as np

with h5py.File(sys.argv[1], "r") as f:
    r = f["replicas"]
    running = np.flatnonzero(r["status"][...] == 1)
    assert len(running) > 0, "no running replica"
    for k in running:
        m = int(r["rows_written"][k])
        p = float(r["progress"][k])
        assert m > 0 and 0 < p < 1, (k, m, p)
        row = f["timeseries/pressure"][k]
        assert np.isfinite(row[:m]).all() and np.isnan(row[m:]).all(), k
        assert m < int(r["n_samples"][k]), (k, m)
    print(f"{len(running)} running replicas with partial rows:",
          [(int(k), int(r["rows_written"][k]), round(float(r["progress"][k]), 3)) for k in running])
