"""usage: check_frames.py ARCHIVE.h5
Checks the configuration frames of a finished campaign with [run] frame_interval: each
replica has floor(steps / frame_every) + 1 frames at strains k * frame_every * dt * rate
(time at rate 0), NaN past them; frame 0 is the start (strain 0) and the last frame at the
run's end is the final configuration, bitwise; every frame lies in the cell [0, L) with its
Lees-Edwards strain in [-1/2, 1/2), and disks move between frames."""
import math
import sys

import h5py
import numpy as np

f = h5py.File(sys.argv[1], "r")
strain = f["frames/strain"][...]
box_strain = f["frames/box_strain"][...]
x, y = f["frames/x"], f["frames/y"]
offset, n = f["replicas/particle_offset"][...], f["replicas/N"][...].astype(int)
rate, dt = f["replicas/rate"][...], f["replicas/dt"][...]
run_strain = f["replicas/strain"][...]
side = f["final/box_side"][...]
assert (f["replicas/status"][...] == 2).all(), "not all replicas done"
checked = 0
for r in range(len(offset)):
    every = max(1, round(f["replicas/frame_interval"][r] / rate[r] / dt[r]))
    steps = math.ceil(run_strain[r] / rate[r] / dt[r] - 1e-9)
    frames = steps // every + 1
    expected = np.arange(frames) * every * dt[r] * rate[r]
    got = strain[r]
    assert np.allclose(got[:frames], expected, rtol=1e-12, atol=1e-15), (r, got[:frames], expected)
    assert np.isnan(got[frames:]).all(), f"replica {r}: frames past its run"
    assert np.all((box_strain[r, :frames] >= -0.5) & (box_strain[r, :frames] < 0.5)), r
    cols = slice(offset[r], offset[r] + n[r])
    fx, fy = x[:frames, cols], y[:frames, cols]
    assert np.all((fx >= 0) & (fx < side[r]) & (fy >= 0) & (fy < side[r])), f"replica {r}: frame outside the cell"
    assert np.any(fx[0] != fx[1]), f"replica {r}: disks did not move between frames 0 and 1"
    if steps % every == 0:  # the last frame is the end state
        assert (fx[-1] == f["final/x"][cols]).all() and (fy[-1] == f["final/y"][cols]).all(), r
        assert box_strain[r, frames - 1] == f["final/box_strain"][r], r
        checked += 1
assert checked > 0, "no replica whose last frame is its end state"
print(f"frames ok: {len(offset)} replicas, up to {strain.shape[1]} frames, {checked} end states matched")
