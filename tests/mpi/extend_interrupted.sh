#!/usr/bin/env bash
# usage: extend_interrupted.sh JAMSIM CAMPAIGNS_DIR WORKDIR PYTHON_DIR
# A campaign stopped by SIGUSR1 (exit 75, its replicas running with checkpoints) and then
# extended to a longer strain finishes bitwise equal to the longer campaign run in one go:
# the replicas that were running keep their rows and frames in the extended archive and go
# on from their checkpoints (the extension used to drop them, so the frames before a
# checkpoint were never written again and a done replica had frames of NaN strain).
set -euo pipefail
jamsim=$1 campaigns=$2 work=$3 py=$4
mpirun=${MPIEXEC:-mpiexec}
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*"; exit 1; }
short=$campaigns/frames_interrupted_short.toml long=$campaigns/frames_interrupted_long.toml
timeout 300 "$mpirun" -n 2 "$jamsim" run "$long" -o ref.h5 > ref.log 2>&1 || { cat ref.log; fail "reference run"; }
timeout 300 "$mpirun" -n 2 "$jamsim" run "$short" -o x.h5 --checkpoint-every 0 > short.log 2>&1 &
leader=$!
for _ in $(seq 1200); do compgen -G "x.h5.checkpoints/replica_*.h5" > /dev/null && break; sleep 0.02; done
pkill -USR1 -f -- "^$jamsim run $short" || fail "no rank to signal"
rc=0; wait "$leader" || rc=$?
[[ $rc -eq 75 ]] || { cat short.log; fail "the stopped run exited $rc, not 75 (did it finish before the signal?)"; }
grep -q "interrupted" short.log || { cat short.log; fail "no interrupted replica"; }
timeout 300 "$mpirun" -n 2 "$jamsim" run "$long" -o x.h5 > long.log 2>&1 || { cat long.log; fail "the extension"; }
grep -q "extending x.h5" long.log || { cat long.log; fail "not an extension"; }
"$jamsim" status x.h5 | grep -q "2/2 done" || fail "not every replica is done"
/usr/bin/python3 "$py/compare_archives.py" ref.h5 x.h5 || fail "the extended archive differs from the run in one go"
/usr/bin/python3 "$py/check_frames.py" x.h5 || fail "frames"
echo ok
