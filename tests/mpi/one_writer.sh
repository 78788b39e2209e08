#!/usr/bin/env bash
# usage: one_writer.sh JAMSIM CAMPAIGN.toml WORKDIR PYTHON_DIR
# One writer per archive, with real runs:
#  1. two runs started together on a new archive: one runs, the other is refused (exit 2)
#     naming the holder; the archive equals an undisturbed run bitwise;
#  2. a process that holds the lock as a lingering rank would (a shared record lock): run and
#     merge are refused naming it, and the archive is not touched (hash before and after);
#  3. mpirun killed with SIGKILL, then resumed at once and again until it runs: every attempt
#     is either refused naming the old run or runs after it, and the result equals the
#     undisturbed run bitwise.
set -euo pipefail
jamsim=$1 spec=$2 work=$3 py=$4
mpirun=${MPIEXEC:-mpiexec}
mkdir -p "$work"
cd "$work"
rm -rf ref.h5* a.h5* b.h5* together.h5*
timeout 300 "$mpirun" -n 2 "$jamsim" run "$spec" -o ref.h5 > ref.log

# 1. Two at once.
timeout 300 "$mpirun" -n 2 "$jamsim" run "$spec" -o together.h5 > first.log 2>&1 & one=$!
timeout 300 "$mpirun" -n 1 "$jamsim" run "$spec" -o together.h5 > second.log 2>&1 & two=$!
rc1=0 rc2=0
wait "$one" || rc1=$?
wait "$two" || rc2=$?
echo "together: exit $rc1 and $rc2"
if [[ $rc1 -eq 0 && $rc2 -eq 2 ]]; then refused=second.log; elif [[ $rc1 -eq 2 && $rc2 -eq 0 ]]; then refused=first.log
else echo "FAIL: expected one run and one refusal"; cat first.log second.log; exit 1; fi
grep -q "'together.h5' is being written by jamsim run .*(PID [0-9]* on .*started 20" "$refused" ||
  { echo "FAIL: the refusal does not name the holder"; cat "$refused"; exit 1; }
/usr/bin/python3 "$py/compare_archives.py" ref.h5 together.h5

# 2. A lingering holder (a shared lock, as every rank of a run holds).
cp ref.h5 b.h5
before=$(sha256sum b.h5)
/usr/bin/python3 - b.h5.lock <<'PY' &
import fcntl, os, sys, time
fd = os.open(sys.argv[1], os.O_RDWR | os.O_CREAT, 0o644)
os.write(fd, b"jamsim run lingering.toml (PID 4242 on elsewhere, 2 ranks, started 2026-01-01T00:00:00Z)\n")
fcntl.lockf(fd, fcntl.LOCK_SH)
open(sys.argv[1] + ".held", "w").close()
time.sleep(30)
PY
holder=$!
for _ in $(seq 100); do [[ -e b.h5.lock.held ]] && break; sleep 0.1; done
rc=0; "$jamsim" run "$spec" -o b.h5 > held_run.log 2>&1 || rc=$?
[[ $rc -eq 2 ]] || { echo "FAIL: run on a held archive exited $rc"; cat held_run.log; exit 1; }
grep -q "is being written by jamsim run lingering.toml (PID 4242 on elsewhere" held_run.log
rc=0; "$jamsim" merge b.h5 ref.h5 > held_merge.log 2>&1 || rc=$?
[[ $rc -eq 2 ]] || { echo "FAIL: merge into a held archive exited $rc"; cat held_merge.log; exit 1; }
grep -q "is being written by jamsim run lingering.toml" held_merge.log
[[ "$(sha256sum b.h5)" == "$before" ]] || { echo "FAIL: the held archive changed"; exit 1; }
kill "$holder"; wait "$holder" 2>/dev/null || true
"$jamsim" run "$spec" -o b.h5 > free_run.log  # free again: complete already, nothing to do
test ! -e b.h5.lock  # a finished run removes its lock file

# 3. Kill mpirun, resume at once.
setsid timeout 300 "$mpirun" -n 2 "$jamsim" run "$spec" -o a.h5 --checkpoint-every 0 > killed.log 2>&1 & leader=$!
for _ in $(seq 100); do [[ -e a.h5.lock ]] && break; sleep 0.05; done
sleep 1
kill -KILL "$leader"
refusals=0
for attempt in $(seq 120); do
  rc=0; "$jamsim" run "$spec" -o a.h5 > resume.log 2>&1 || rc=$?
  [[ $rc -eq 0 ]] && break
  [[ $rc -eq 2 ]] && grep -q "'a.h5' is being written by jamsim run" resume.log ||
    { echo "FAIL: resume attempt $attempt exited $rc without naming the holder"; cat resume.log; exit 1; }
  refusals=$((refusals + 1))
  sleep 0.5
done
[[ $rc -eq 0 ]] || { echo "FAIL: never resumed"; exit 1; }
/usr/bin/python3 "$py/compare_archives.py" ref.h5 a.h5
echo "one writer: two runs at once -> one refused; held lock -> run and merge refused, archive unchanged; kill of mpirun -> $refusals refused resumes, then bitwise equal"
