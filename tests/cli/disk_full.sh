#!/usr/bin/env bash
# usage: disk_full.sh JAMSIM WORKDIR
# On a small tmpfs mounted here (root only; exit 77 = skipped otherwise): a campaign whose
# archive does not fit is refused before anything is created, with the sizes in the message;
# the same campaign fits once --output points at a larger filesystem (dry run); a run that
# fills it stops in words and finishes once space is freed; minimize --lammps-data there fails
# and leaves no file, and so does a replica there.
set -euo pipefail
jamsim=$1 work=$2
[[ $(id -u) -eq 0 ]] || { echo "skipped: mounting a tmpfs needs root"; exit 77; }
mkdir -p "$work/small"
mountpoint -q "$work/small" && umount "$work/small"
mount -t tmpfs -o size=4M tmpfs "$work/small"
rm -rf "$work/ref.h5" "$work/ref.h5.checkpoints"
# (an MPI singleton's helper process may keep its working directory there for a moment)
trap 'cd /; for _ in 1 2 3 4 5 6 7 8 9 10; do umount "$work/small" 2>/dev/null && break; sleep 0.5; done; mountpoint -q "$work/small" && umount -l "$work/small"' EXIT
cat > "$work/small/big.toml" <<'TOML'
[campaign]
name = "too-big"
output = "big.h5"
[run]
strain = 2
sample_interval = 0.002
[sweep]
N = [512]
phi = [0.84]
rate = [1e-2]
seeds = 40
TOML
cd "$work/small"
before=$(ls -A)
rc=0; "$jamsim" run big.toml > "$work/refused.txt" 2>&1 || rc=$?
cat "$work/refused.txt"
[[ $rc -eq 2 ]] || { echo "FAIL: exit $rc, expected 2"; exit 1; }
grep -Eq "big.toml: the archive 'big.h5' needs [0-9.]+ MB more \(.* of archive for 40 replicas, N up to 512, up to 1001 samples each, .* of checkpoints\), but its filesystem has [0-9.]+ MB free" "$work/refused.txt"
! grep -Eq "MPI_ABORT|HDF5-DIAG" "$work/refused.txt"
[[ "$(ls -A)" == "$before" ]] || { echo "FAIL: files were created: $(ls -A)"; exit 1; }
"$jamsim" run big.toml --dry-run --no-calibrate -o "$work/big.h5" | grep -Eq "^archive .*big.h5: [0-9.]+ MB when complete"
echo "ok: refused on a 4 MB filesystem, nothing created"

# A filesystem filled by someone else during the run: the run stops saying "no space left on
# device"; once there is space again, the same command finishes the campaign, bitwise the
# same as an undisturbed run.
sed -i 's/seeds = 40/seeds = 10/' big.toml
"$jamsim" run big.toml -o "$work/ref.h5" > /dev/null
rm -rf "$work"/ref.h5.checkpoints
"$jamsim" run big.toml --progress lines --progress-interval 0.2 > "$work/filled.txt" 2>&1 & run=$!
for _ in $(seq 300); do grep -Eq "\] [1-9][0-9]*/10 done" "$work/filled.txt" && break; sleep 0.05; done
dd if=/dev/zero of=filler bs=64k 2>/dev/null || true  # until the filesystem is full
rc=0; wait "$run" || rc=$?
grep -v "^\[" "$work/filled.txt" | head -3
[[ $rc -ne 0 ]] || { echo "FAIL: the run did not notice the full filesystem"; exit 1; }
grep -q "no space left on device: writing the archive 'big.h5' failed .*run the same command again to continue" "$work/filled.txt"
rm filler
"$jamsim" run big.toml > "$work/after.txt"
"$jamsim" status big.h5 | grep -q "10/10 done"
/usr/bin/python3 "$(dirname "$0")/../mpi/compare_archives.py" "$work/ref.h5" big.h5
echo "ok: a filesystem filled during the run: stopped with a clear message, finished after space was freed, bitwise equal"
# jamsim minimize --lammps-data on the full filesystem: an error, and no file, not an empty
# one with exit 0.
dd if=/dev/zero of=filler bs=64k 2>/dev/null || true
rc=0; "$jamsim" minimize --N 64 --lammps-data start.data > "$work/minimize.txt" 2>&1 || rc=$?
[[ $rc -ne 0 ]] || { cat "$work/minimize.txt"; echo "FAIL: minimize wrote to a full filesystem with exit 0"; exit 1; }
grep -q "writing LAMMPS data file 'start.data' failed" "$work/minimize.txt" || { cat "$work/minimize.txt"; exit 1; }
! compgen -G "start.data*" > /dev/null || { echo "FAIL: a partial data file is left: $(ls start.data*)"; exit 1; }
echo "ok: minimize --lammps-data on a full filesystem: refused, nothing left"
# jamsim merge into the full filesystem: refused before it writes, in words about its output
# (it named the campaign file the archive was once run from).
rc=0; "$jamsim" merge m.h5 "$work/ref.h5" > "$work/merge.txt" 2>&1 || rc=$?
[[ $rc -eq 2 ]] || { cat "$work/merge.txt"; echo "FAIL: merge exit $rc, expected 2"; exit 1; }
grep -q "^jamsim merge: the archive 'm.h5' needs [0-9.]* [kM]B more" "$work/merge.txt" || { cat "$work/merge.txt"; exit 1; }
! compgen -G "m.h5*" > /dev/null || { echo "FAIL: left by the refused merge: $(ls m.h5*)"; exit 1; }
echo "ok: merge into a full filesystem: refused before it writes"
# jamsim replica -o on the full filesystem: refused before the run, which it used to run to the
# end and then lose in the write.
rc=0; "$jamsim" replica --N 64 --strain 0.5 -o r.h5 > "$work/replica.txt" 2>&1 || rc=$?
cat "$work/replica.txt"
[[ $rc -eq 2 ]] || { echo "FAIL: exit $rc, expected 2"; exit 1; }
grep -Eq "^jamsim replica: the replica file 'r.h5' needs about [0-9.]+ [kM]B \(N = 64, 51 samples\), but its filesystem has [0-9.]+ [kM]?B free" "$work/replica.txt"
! grep -q "replica RD0 N=64" "$work/replica.txt" || { echo "FAIL: the replica ran"; exit 1; }
! compgen -G "r.h5*" > /dev/null || { echo "FAIL: a replica file is left: $(ls r.h5*)"; exit 1; }
rm filler
echo "ok: replica -o on a full filesystem: refused before the run"

# An extension to longer runs writes the new archive whole beside the old one before it
# replaces it: with room for the growth but not for the whole new archive it is refused before
# anything is written (it used to pass the size check and abort half-way through the new
# copy), and the archive is unchanged.
mount -o remount,size=12M "$work/small"
sed 's/^strain = 2$/strain = 2.5/' big.toml > longer.toml
dd if=/dev/zero of=filler bs=64k 2>/dev/null || true
rc=0; "$jamsim" run longer.toml > "$work/longer.txt" 2>&1 || rc=$?
rm filler
[[ $rc -eq 2 ]] || { cat "$work/longer.txt"; echo "FAIL: exit $rc on a full filesystem, expected 2"; exit 1; }
needed=$(/usr/bin/python3 - "$work/longer.txt" <<'PY'
import re, sys
m = re.search(r"needs ([0-9.]+) (kB|MB) more \(", open(sys.argv[1]).read())
print(int(float(m.group(1)) * {"kB": 1e3, "MB": 1e6}[m.group(2)]))
PY
)
# (that check took the growth alone: what the new archive needs beyond the old one's blocks)
present=$(( $(stat -c '%b * %B' big.h5) ))
free=$(df -B1 --output=avail . | tail -1)
# Free space for the growth and half the old archive more, not for the whole new archive.
leave=$(( (needed + present / 2) * 10 / 9 ))
(( free > leave )) || { echo "FAIL: the test's filesystem is too small ($free bytes free, $leave wanted)"; exit 1; }
dd if=/dev/zero of=filler bs=4096 count=$(( (free - leave) / 4096 )) 2>/dev/null
before=$(sha256sum < big.h5)
rc=0; "$jamsim" run longer.toml > "$work/longer.txt" 2>&1 || rc=$?
cat "$work/longer.txt"
[[ $rc -eq 2 ]] || { echo "FAIL: exit $rc with room for the growth only, expected 2"; exit 1; }
grep -q "written whole beside the old one before it replaces it" "$work/longer.txt"
[[ "$(sha256sum < big.h5)" == "$before" ]] || { echo "FAIL: the archive changed"; exit 1; }
! compgen -G "big.h5.extending*" > /dev/null || { echo "FAIL: left beside it: $(ls big.h5.extending*)"; exit 1; }
rm filler
echo "ok: an extension that the filesystem cannot hold whole is refused before it writes"

# What a failed extension left (its new copy, Open MPI's lock files of an aborted singleton)
# is removed before the size check, which it used to fail with the space it held itself.
free=$(df -B1 --output=avail . | tail -1)
dd if=/dev/zero of=big.h5.extending bs=4096 count=$(( (free - (needed + present) * 10 / 9 / 2) / 4096 )) 2>/dev/null
: > big.h5.extending-1-4242.lock
: > big.h5-3-4243.lock
: > big.h5-x-1.lock  # not Open MPI's name: kept
"$jamsim" run longer.toml > "$work/longer.txt" 2>&1 || { cat "$work/longer.txt"; echo "FAIL: the extension after a failed one"; exit 1; }
grep -q "removed 'big.h5.extending', left by an extension that a kill interrupted" "$work/longer.txt"
grep -q "removed '.*big.h5.extending-1-4242.lock', an MPI lock file left by a run that was killed or aborted" "$work/longer.txt"
[[ ! -e big.h5.extending-1-4242.lock && ! -e big.h5-3-4243.lock && -e big.h5-x-1.lock ]] || { ls; echo "FAIL: lock files"; exit 1; }
"$jamsim" status big.h5 | grep -q "10/10 done"
echo "ok: a failed extension's leftovers removed first, then extended"
