#!/usr/bin/env bash
# usage: grow_in_place.sh JAMSIM CAMPAIGNS_DIR WORKDIR PYTHON_DIR
# Grow in place on 2 ranks. (1) grow_step0.toml, then the same archive grown in three steps
# (more seeds, a new rate, a new phi): each step keeps every finished replica bitwise (its
# wall time and rank too: not computed again) and runs only the new ones, and the result
# equals grow_step3.toml run in one go, bitwise. (2) A replica interrupted at a checkpoint
# step keeps its checkpoint through a growth that moves it to another id, and the two states
# a kill during a growth can leave (before and after its rename) are recovered from: the
# result equals the grown campaign run in one go, bitwise.
set -euo pipefail
jamsim=$1 campaigns=$2 work=$3 py=$4
mpirun=${MPIEXEC:-mpiexec}
mkdir -p "$work"
cd "$work"
rm -rf grow*.h5* grow-ck* step*.h5 old*
fail() { echo "FAIL: $*"; exit 1; }
run() { timeout 300 "$mpirun" -n 2 "$jamsim" run "$@"; }
# Until FILE exists (a run's first checkpoint: its signal handler is in place), at most 60 s.
wait_for() { for _ in $(seq 1200); do [[ -e $1 ]] && return 0; sleep 0.05; done; fail "no $1 after 60 s"; }

# (1) Three steps against one run of the final campaign.
run "$campaigns/grow_step3.toml" -o grow_ref.h5 > ref.log 2>&1 || { cat ref.log; fail "reference run"; }
run "$campaigns/grow_step0.toml" > step0.log 2>&1 || { cat step0.log; fail "step 0"; }
grep -q "^2 replicas ran in this run, 0 finished before were kept" step0.log || { cat step0.log; fail "step 0 count"; }
previous=2
for step in 1 2 3; do
  cp grow.h5 "step$((step - 1)).h5"
  run "$campaigns/grow_step$step.toml" > "step$step.log" 2>&1 || { cat "step$step.log"; fail "step $step"; }
  cat "step$step.log" | grep -v '^\['
  total=$(/usr/bin/python3 -c "import h5py; print(len(h5py.File('grow.h5', 'r')['replicas/status']))")
  new=$((total - previous))
  grep -q "^growing archive grow.h5: $previous replicas kept, $new new$" "step$step.log" || fail "step $step: no growth line"
  grep -q "^$new replicas\? ran in this run, $previous finished before were kept$" "step$step.log" || fail "step $step: ran more than the new replicas"
  /usr/bin/python3 "$py/check_grown.py" "step$((step - 1)).h5" grow.h5 "$new"
  previous=$total
done
[[ $previous -eq 12 ]] || fail "12 replicas expected, $previous"
/usr/bin/python3 "$py/compare_archives.py" grow_ref.h5 grow.h5
"$jamsim" status grow.h5 | grep -q '12/12 done' || fail "status of the grown archive"
# Running the final campaign once more changes nothing.
sum=$(sha256sum < grow.h5)
run "$campaigns/grow_step3.toml" > again.log 2>&1 || { cat again.log; fail "run again"; }
grep -q "^0 replicas ran in this run, 12 finished before were kept" again.log || fail "the run again ran replicas"

# (2) Checkpoints follow their replicas; a kill during a growth loses nothing.
run "$campaigns/grow_checkpointed_more.toml" -o grow_ck_ref.h5 > ck_ref.log 2>&1 || { cat ck_ref.log; fail "reference run (checkpointed)"; }
# (mpiexec itself in the background, so that SIGUSR1 reaches it)
"$mpirun" -n 2 "$jamsim" run "$campaigns/grow_checkpointed.toml" --checkpoint-every 0 > ck0.log 2>&1 &
pid=$!
wait_for grow-ck.h5.checkpoints/replica_0.h5
kill -USR1 "$pid" 2>/dev/null || true
rc=0; wait "$pid" || rc=$?
[[ $rc -eq 75 ]] || { cat ck0.log; fail "the first run was not interrupted (exit $rc)"; }
ls grow-ck.h5.checkpoints/replica_0.h5 > /dev/null || fail "no checkpoint of the interrupted replica"
cp grow-ck.h5 old.h5
cp -r grow-ck.h5.checkpoints old.checkpoints
# A kill before the growth's rename leaves PATH.growing and its checkpoint folder: removed,
# the archive as it was, and the growth done again.
cp old.h5 grow-ck.h5.growing
mkdir grow-ck.h5.growing.checkpoints
cp old.checkpoints/replica_0.h5 grow-ck.h5.growing.checkpoints/replica_7.h5
"$mpirun" -n 2 "$jamsim" run "$campaigns/grow_checkpointed_more.toml" --checkpoint-every 0 > ck1.log 2>&1 &
pid=$!
wait_for grow-ck.h5.checkpoints/replica_1.h5  # seed 2's checkpoint under its new id: grown
kill -USR1 "$pid" 2>/dev/null || true
rc=0; wait "$pid" || rc=$?
cat ck1.log | grep -v '^\['
[[ $rc -eq 75 || $rc -eq 0 ]] || fail "growth run exit $rc"
grep -q "removed 'grow-ck.h5.growing', left by a growth that was interrupted" ck1.log || fail "leftovers of a growth not removed"
grep -q "^growing archive grow-ck.h5: 1 replicas kept, 1 new$" ck1.log || fail "no growth line"
[[ ! -e grow-ck.h5.growing && ! -e grow-ck.h5.growing.checkpoints ]] || fail "leftovers remain"
# A kill after the rename, before the checkpoint folders were swapped: the grown archive with
# the old folder (old ids) and the new one beside it. The next run completes the swap.
# (The growth's folder carries its marker until the swap; a folder without one is left alone.)
mv grow-ck.h5.checkpoints grow-ck.h5.growing.checkpoints
echo "jamsim: the checkpoints of the archive growing from 'grow-ck.h5'" > grow-ck.h5.growing.checkpoints/.growth
cp -r old.checkpoints grow-ck.h5.checkpoints
run "$campaigns/grow_checkpointed_more.toml" > ck2.log 2>&1 || { cat ck2.log; fail "the run after the growth"; }
cat ck2.log | grep -v '^\['
grep -q "completed the growth of 'grow-ck.h5'" ck2.log || fail "the growth was not completed"
[[ ! -e grow-ck.h5.growing.checkpoints ]] || fail "the new checkpoint folder was not moved in place"
/usr/bin/python3 "$py/compare_archives.py" grow_ck_ref.h5 grow-ck.h5
# An undisturbed growth: seed 2 continues from its checkpoint, now under its new id (seed 1,
# new, starts afresh): exactly one replica continued.
cp old.h5 grow-ck2.h5
cp -r old.checkpoints grow-ck2.h5.checkpoints
run "$campaigns/grow_checkpointed_more.toml" -o grow-ck2.h5 > ck3.log 2>&1 || { cat ck3.log; fail "the growth of a copy"; }
cat ck3.log | grep -v '^\['
grep -q "^growing archive grow-ck2.h5: 1 replicas kept, 1 new$" ck3.log || fail "no growth line"
grep -q "(0 failed replicas; 1 continued from checkpoints" ck3.log || fail "the interrupted replica did not continue from its checkpoint"
/usr/bin/python3 "$py/compare_archives.py" grow_ck_ref.h5 grow-ck2.h5
echo "ok: grown in three steps and after interruptions, bitwise equal to the campaigns run in one go"
