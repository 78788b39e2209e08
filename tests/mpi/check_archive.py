"""usage: check_archive.py ARCHIVE.h5 RANKS
Reads a finished campaign archive with h5py and checks it against the documented layout."""
import sys

import h5py
import numpy as np
from archive_rows import final

# Columns that only minimisation models (QS, RAND, COMPRESS) fill; NaN for the dynamics.
STATIC_ONLY = {"contact_number_nonrattler", "rattler_fraction", "excess_contacts", "jammed", "max_force"}

path, ranks = sys.argv[1], int(sys.argv[2])
with h5py.File(path, "r") as f:
    for key in ("campaign", "spec_text", "spec_fingerprint", "code_version", "build_flags",
                "created", "run_started", "run_finished"):
        assert key in f.attrs and len(str(f.attrs[key])) > 0, key
    assert f.attrs["n_ranks"] == ranks
    r = f["replicas"]
    n = len(r["status"])
    assert n == f.attrs["n_replicas"]
    assert (r["status"][...] == 2).all(), r["status"][...]
    assert set(r["rank"][...]) == set(range(ranks)), ("every rank computes", r["rank"][...])
    assert (r["wall_seconds"][...] > 0).all()
    for name in ("timeseries", "final", "replicas", "correlation"):
        for key, d in f[name].items():
            assert "units" in d.attrs and "description" in d.attrs, (name, key)
    ts = f["timeseries"]
    for k in range(n):
        m = int(r["n_samples"][k])
        for key, d in ts.items():
            row = d[k]
            assert np.isnan(row[m:]).all(), (key, k)
            if key in STATIC_ONLY:  # minimised states only: not applicable to dynamics
                assert np.isnan(row[:m]).all(), (key, k)
            else:
                assert np.isfinite(row[:m]).all(), (key, k)
        assert (ts["packing_fraction"][k, :m] == r["phi"][k]).all()
        assert np.allclose(ts["strain"][k, :m], r["rate"][k] * ts["time"][k, :m])
        N = int(r["N"][k])
        x = final(f, "x", k)
        assert x.size == N and np.isfinite(x).all()
        L = f["final/box_side"][k]
        d = final(f, "diameter", k)
        assert abs(np.sum(np.pi * d**2 / 4) / L**2 - r["phi"][k]) < 1e-12
print(f"archive OK: {n} replicas on {ranks} ranks")
