"""usage: check_checkpoints_final.py ARCHIVE.h5
After a campaign finished: every checkpoint left beside the archive is a final one (kept so a
longer run can continue from it) of a finished replica; no .tmp is left."""
import os
import sys

import h5py

archive = sys.argv[1]
folder = archive + ".checkpoints"
with h5py.File(archive, "r") as f:
    status = f["replicas/status"][...]
names = sorted(os.listdir(folder)) if os.path.isdir(folder) else []
for name in names:
    assert not name.endswith(".tmp"), f"{name} left behind"
    replica = int(name[len("replica_"):-len(".h5")])
    with h5py.File(os.path.join(folder, name), "r") as c:
        assert c.attrs["final"] == 1, f"{name} is not final"
    assert status[replica] == 2, (name, status[replica])
print(f"{len(names)} final checkpoints of finished replicas, nothing else")
