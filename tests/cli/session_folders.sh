#!/usr/bin/env bash
# usage: session_folders.sh JAMSIM (in a scratch folder)
# Each jamsim started without mpirun keeps Open MPI's session files in a jamsim-mpi.XXXXXX
# folder of its own under TMPDIR. A killed one (SIGKILL) leaves its folder; the next jamsim
# removes it, and never a live one's, nor a folder that is not a session folder.
set -euo pipefail
jamsim=$1
rm -rf session_work && mkdir -p session_work/tmp && cd session_work
export TMPDIR=$PWD/tmp
fail() { echo "FAIL: $*" >&2; ls -la tmp >&2; exit 1; }
folders() { find tmp -maxdepth 1 -name 'jamsim-mpi.*' -type d | sort; }
wait_for_folder() {  # wait until a session folder other than those in $1 has its lock
  for _ in $(seq 1 200); do
    for f in $(folders); do
      [[ " $1 " == *" $f "* ]] || { [[ -e $f/owner.lock ]] && { echo "$f"; return; }; }
    done
    sleep 0.05
  done
  return 1
}
printf '[campaign]\nname = "long"\noutput = "long.h5"\n[run]\nstrain = 100000\nsample_interval = 100\n[sweep]\nN = [1024]\nphi = [0.84]\nrate = [1e-2]\nseeds = 1\n' > long.toml
printf '[campaign]\nname = "short"\noutput = "short.h5"\n[run]\nstrain = 0.05\nsample_interval = 0.01\n[sweep]\nN = [16]\nphi = [0.84]\nrate = [1e-2]\nseeds = 1\n' > short.toml

# 1. A killed singleton's folder stays until the next jamsim, which removes it.
"$jamsim" run long.toml > killed.txt 2>&1 &
killed=$!
dead=$(wait_for_folder "") || { cat killed.txt; fail "the first run made no session folder"; }
kill -KILL "$killed"; wait "$killed" || true
[[ -d $dead ]] || fail "the killed run's folder was gone before the next run"

# 2. A live singleton's folder is kept while the next one sweeps.
"$jamsim" run long.toml -o live.h5 > live.txt 2>&1 &
live=$!
alive=$(wait_for_folder "$dead") || { cat live.txt; fail "the second run made no session folder"; }
# 3. Folders that are not a dead session's: young and without a lock (one being made),
#    a name of another length, a plain file,
#    and an old one whose filesystem refused the lock (its owner.new stays).
mkdir tmp/jamsim-mpi.young1 tmp/jamsim-mpi.toolong1 tmp/jamsim-mpi.old111 tmp/jamsim-mpi.nolck1
touch tmp/jamsim-mpi.nolck1/owner.new
touch -d '-1 hour' tmp/jamsim-mpi.old111 tmp/jamsim-mpi.nolck1
touch tmp/jamsim-mpi.file11
"$jamsim" run short.toml > short.txt 2>&1 || { cat short.txt; fail "the short run"; }
[[ ! -e $dead ]] || fail "the killed run's folder $dead was not removed"
[[ -d $alive && -e $alive/owner.lock ]] || fail "the live run's folder $alive was removed"
[[ ! -e tmp/jamsim-mpi.old111 ]] || fail "an old folder without a lock was kept"
for kept in jamsim-mpi.young1 jamsim-mpi.toolong1 jamsim-mpi.file11 jamsim-mpi.nolck1; do
  [[ -e tmp/$kept ]] || fail "tmp/$kept was removed"
done
kill -USR1 "$live"
status=0; wait "$live" || status=$?
[[ $status == 75 ]] || { cat live.txt; fail "the live run ended with $status, not 75 (stopped and resumable)"; }
[[ ! -e $alive ]] || fail "the live run left its folder $alive"
[[ -z $(find tmp -maxdepth 1 -name 'jamsim-mpi.??????' -newer long.toml -type d ! -name 'jamsim-mpi.young1' ! -name 'jamsim-mpi.nolck1') ]] ||
  fail "a session folder was left"
echo ok
