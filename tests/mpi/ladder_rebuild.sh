#!/usr/bin/env bash
# usage: ladder_rebuild.sh JAMSIM CAMPAIGNS_DIR WORKDIR PYTHON_DIR
# A rate ladder's end state made again (its archive copied without the checkpoint folder)
# saves checkpoints as any run does: stopped by SIGUSR1 while it runs, the run exits 75 with
# the rebuild's state saved, and the next run goes on from it (it ran the chain from its start
# again, so a rebuild longer than an allocation was never made), bitwise equal to the ladder
# run in one go.
set -euo pipefail
jamsim=$1 campaigns=$2 work=$3 py=$4
mpirun=${MPIEXEC:-mpiexec}
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*"; exit 1; }
campaign=$campaigns/ladder_rebuild.toml
compare="/usr/bin/python3 $py/compare_archives.py"
stop_when() {  # FILE LOG ARGS...: start jamsim run on 2 ranks, SIGUSR1 once FILE exists; exit 75
  local file=$1 log=$2; shift 2
  timeout 300 "$mpirun" -n 2 "$jamsim" run "$campaign" "$@" > "$log" 2>&1 &
  local leader=$!
  for _ in $(seq 1200); do [[ -e $file ]] && break; sleep 0.02; done
  [[ -e $file ]] || { wait "$leader" || true; cat "$log"; fail "no '$file' while the run ran"; }
  pkill -USR1 -f -- "^$jamsim run $campaign" || fail "no rank to signal"
  local rc=0; wait "$leader" || rc=$?
  [[ $rc -eq 75 ]] || { cat "$log"; fail "the stopped run exited $rc, not 75"; }
}

timeout 300 "$mpirun" -n 2 "$jamsim" run "$campaign" -o ref.h5 > ref.log 2>&1 || { cat ref.log; fail "reference run"; }
# Stopped while the last rate runs (its start, end_1, written), then the folder lost.
stop_when m.h5.checkpoints/end_1.h5 first.log -o m.h5
rm -rf m.h5.checkpoints
# The rebuild of replica 1 (about a second), stopped once it saved a checkpoint.
stop_when m.h5.checkpoints/rebuild_1.h5 second.log -o m.h5 --checkpoint-every 0
grep -q "replica 1 runs again to make it;" second.log || { cat second.log; fail "no rebuild of replica 1"; }
[[ -e m.h5.checkpoints/rebuild_1.h5 ]] || fail "the stopped rebuild kept no checkpoint"
timeout 300 "$mpirun" -n 2 "$jamsim" run "$campaign" -o m.h5 > third.log 2>&1 || { cat third.log; fail "third run"; }
grep -q "replica 1 runs again to make it, from its checkpoint 'm.h5.checkpoints/rebuild_1.h5'" third.log ||
  { cat third.log; fail "the rebuild did not go on from its checkpoint"; }
! grep -q "starts from the end state of replica 0" third.log || { cat third.log; fail "the chain ran from its start again"; }
"$jamsim" status m.h5 | grep -q "3/3 done" || fail "not every replica is done"
$compare ref.h5 m.h5 || fail "the ladder with a stopped rebuild finished otherwise than the ladder run in one go"
[[ -z $(ls m.h5.checkpoints | grep -E '^(end|rebuild)_' || true) ]] || fail "left behind: $(ls m.h5.checkpoints)"
echo "ok"
