"""usage: damage_checkpoint.py FILE KIND
Damages a jamsim checkpoint (or an archive's final state) the way a disk, a kill or a hand
does: truncated, zero_filled, short_column (one time series column a row short),
fewer_disks (every particle array two disks short), nan_position, edited_step (the step
attribute moved by one checkpoint interval), edited_step_no_checksum (the same, and the
checksum attribute removed), heap_zeroed (the objects of its first global
heap zeroed, as a crash can leave them: HDF5 1.10 loops for ever reading its text
attributes), other_diameter (an archive: one final disk of
replica 0 given another diameter)."""
import os
import sys

import h5py
import numpy as np

path, kind = sys.argv[1:3]
if kind == "truncated":
    os.truncate(path, os.path.getsize(path) // 3)
elif kind == "zero_filled":
    size = os.path.getsize(path)
    with open(path, "r+b") as f:
        f.write(b"\0" * size)
elif kind == "heap_zeroed":
    with open(path, "r+b") as f:  # "GCOL", version, reserved, the collection's size, objects
        data = f.read()
        at = data.index(b"GCOL")
        size = int.from_bytes(data[at + 8:at + 16], "little")
        f.seek(at + 16)
        f.write(bytes(size - 16))
elif kind == "other_diameter":
    with h5py.File(path, "r+", locking=False) as f:
        d = f["final/diameter"]
        d[3] = 1.2
else:
    with h5py.File(path, "r+", locking=False) as f:
        if kind == "short_column":
            name = sorted(f["timeseries"])[0]
            data = f["timeseries"][name][...]
            assert data.size > 1, "a column of one row"
            del f["timeseries"][name]
            f["timeseries"].create_dataset(name, data=data[:-1])
        elif kind == "fewer_disks":
            for name in list(f["particles"]):
                data = f["particles"][name][...]
                del f["particles"][name]
                f["particles"].create_dataset(name, data=data[:-2])
        elif kind == "nan_position":
            x = f["particles/x"]
            x[0] = np.nan
        elif kind in ("edited_step", "edited_step_no_checksum"):
            step = int(f.attrs["step"])
            f.attrs["step"] = np.int64(step - 100 if step >= 100 else step + 100)
            if kind == "edited_step_no_checksum":  # and the checksum that would show it, removed
                del f.attrs["checksum"]
        else:
            sys.exit(f"unknown damage {kind}")
print(f"damaged {path}: {kind}")
