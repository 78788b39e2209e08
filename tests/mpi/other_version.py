"""usage: other_version.py ARCHIVE.h5
Rewrites the archive's fingerprint as if an older jamsim (campaign fingerprint v1) had
written it, so that resuming or merging it must be refused."""
import sys

import h5py

with h5py.File(sys.argv[1], "r+") as f:
    old = f.attrs["spec_fingerprint"]
    old = old.decode() if isinstance(old, bytes) else str(old)
    head, sep, rest = old.partition(" campaign v")
    f.attrs["spec_fingerprint"] = head + sep + "1" + rest[rest.index(" "):]
