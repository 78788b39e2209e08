#!/usr/bin/env bash
# usage: ladder_merge.sh JAMSIM CAMPAIGNS_DIR WORKDIR PYTHON_DIR
# A rate ladder's successor whose predecessor's end state the archive's checkpoint folder does
# not hold (a merge of archives that never had it, or a copy of the archive without its
# folder): its run runs the chain up to the predecessor again, checks that it ends on the
# predecessor's final configuration in the archive, and the campaign finishes bitwise equal to
# one run in one go. An end state that an input holds (its run was stopped before the
# successor finished) is copied by the merge instead, and one that is damaged is made again.
# A predecessor whose stored final configuration the run does not reproduce fails its
# successor, naming it.
set -euo pipefail
jamsim=$1 campaigns=$2 work=$3 py=$4
mpirun=${MPIEXEC:-mpiexec}
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*"; exit 1; }
run() {  # LOG ARGS...: jamsim run on 2 ranks
  local log=$1; shift
  timeout 300 "$mpirun" -n 2 "$jamsim" run "$@" > "$log" 2>&1 || { cat "$log"; fail "jamsim run $*"; }
}
compare="/usr/bin/python3 $py/compare_archives.py"
two=$campaigns/ladder_merge_two.toml three=$campaigns/ladder_merge_three.toml

# Rates 1e-2 and 3e-3 done in one archive; the three-rate campaign's archive all pending.
run ref.log "$three" -o ref.h5
run two.log "$two" -o two.h5
run three.log "$three" -o three.h5 --shard 1/2
"$jamsim" merge -o m.h5 two.h5 three.h5 > merge.log
grep -q "2/3 done, 0 running, 0 failed, 1 pending" merge.log || { cat merge.log; fail "merge"; }
grep -q "merged .*, not run since: jamsim run CAMPAIGN.toml -o m.h5 runs the rest" merge.log || { cat merge.log; fail "status after the merge"; }
! ls m.h5.checkpoints/end_* > /dev/null 2>&1 || fail "the merge made an end state that no input held"
cp m.h5 tampered.h5
run rest.log "$three" -o m.h5
grep -q "replica 2 starts from the end state of replica 1, which 'm.h5.checkpoints' no longer holds .*: replica 1 runs again to make it" rest.log || { cat rest.log; fail "no word of the end state made again"; }
grep -q "replica 1 starts from the end state of replica 0" rest.log || { cat rest.log; fail "the chain was not run from its start"; }
"$jamsim" status m.h5 | grep -q "3/3 done" || fail "not every replica is done"
$compare ref.h5 m.h5 || fail "the merged ladder finished otherwise than the ladder run in one go"
! ls m.h5.checkpoints/end_* > /dev/null 2>&1 || fail "end states were left behind: $(ls m.h5.checkpoints)"

# A stored final configuration that the run does not reproduce: the successor fails, naming why.
/usr/bin/python3 -c "
import h5py; f = h5py.File('tampered.h5', 'r+'); o = f['replicas/particle_offset'][1]; f['final/x'][o] += 1e-9"
run tampered.log "$three" -o tampered.h5
"$jamsim" status tampered.h5 > tampered_status.txt
grep -q "failed replica 2: replica 1, run again to make the end state that replica 2 starts from, did not end on its final configuration in the archive" tampered_status.txt || { cat tampered_status.txt; fail "the tampered final configuration was not noticed"; }

# An input stopped while its last rate runs holds the end state of rate 3e-3: the merge copies
# it, and the rest runs from it without running the chain again.
slow=$campaigns/ladder_merge_slow.toml
run slow_ref.log "$slow" -o slow_ref.h5
timeout 300 "$mpirun" -n 2 "$jamsim" run "$slow" -o slow.h5 > slow.log 2>&1 &
leader=$!
for _ in $(seq 600); do [[ -e slow.h5.checkpoints/end_1.h5 ]] && break; sleep 0.05; done
[[ -e slow.h5.checkpoints/end_1.h5 ]] || fail "the slow ladder never reached its last rate"
pkill -USR1 -f -- "^$jamsim run $slow -o slow.h5" || fail "no rank to signal"
rc=0; wait "$leader" || rc=$?
[[ $rc -eq 75 ]] || { cat slow.log; fail "the stopped run exited $rc, not 75"; }
"$jamsim" merge -o ms.h5 slow.h5 > merge_slow.log
[[ -e ms.h5.checkpoints/end_1.h5 ]] || { cat merge_slow.log; fail "the merge did not copy the end state"; }
run slow_rest.log "$slow" -o ms.h5
! grep -q "runs again to make it" slow_rest.log || { cat slow_rest.log; fail "the chain ran again though its end state was copied"; }
$compare slow_ref.h5 ms.h5 || fail "the merged stopped ladder finished otherwise than the ladder run in one go"
# A damaged end state (cut to a third) is made again, as a missing one (it failed the
# successor for good).
"$jamsim" merge -o md.h5 slow.h5 > merge_damaged.log
end=md.h5.checkpoints/end_1.h5
truncate -s $(($(stat -c %s "$end") / 3)) "$end"
run damaged.log "$slow" -o md.h5
grep -q "warning: checkpoint '$end' .*; it is made again" damaged.log || { cat damaged.log; fail "no warning of the damaged end state"; }
grep -q "replica 1 runs again to make it" damaged.log || { cat damaged.log; fail "the damaged end state was not made again"; }
$compare slow_ref.h5 md.h5 || fail "the ladder with a damaged end state finished otherwise than the ladder run in one go"
echo "ok"
