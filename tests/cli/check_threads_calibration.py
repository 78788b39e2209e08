"""usage: check_threads_calibration.py ARCHIVE DRY_RUN_OUTPUT
Passes when the archive's one replica is done on 2 threads (/replicas/threads) and the dry run
on that archive estimates it at its wall time times the speed-up model's factor for 2 threads
at its N (the pair loop's serial fraction 0.21 below N = 16384: 1 / (0.21 + 0.79 / 2)), plus
its archive writes, within
the 3 digits the dry run prints: the calibration counts a threaded run's seconds at one thread."""
import re
import sys

import h5py

archive, listing = sys.argv[1:3]
with h5py.File(archive, "r") as f:
    assert f["replicas/status"][0] == 2, "the replica is not done"
    threads = float(f["replicas/threads"][0])
    wall = float(f["replicas/wall_seconds"][0])
assert threads == 2.0, f"/replicas/threads = {threads}, expected 2 (one rank, its own 2 threads throughout)"
text = open(listing).read()
assert "1 groups from the archive's finished replicas" in text, "the dry run did not calibrate from the archive"
total = float(re.search(r"^total: \S+ core-hours, (\S+) core-seconds", text, re.M).group(1))
# Plus the replica's archive writes, measured beside the output (printed to 2 digits, in ms).
writes = re.search(r"each replica's archive writes ([0-9.e+-]+) ms", text)
assert writes, "the dry run did not price the archive's writes"
expected = wall / (0.21 + 0.79 / 2) + float(writes.group(1)) / 1e3
assert abs(total - expected) <= 0.006 * expected, f"estimated {total} s, expected {expected} s (wall {wall} s on 2 threads)"
print(f"ok: {wall:.3f} s on 2 threads counted as {total} s on one (expected {expected:.4g})")
