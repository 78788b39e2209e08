#!/usr/bin/env bash
# A campaign through a real (local, single-node) Slurm: slurm/submit_campaign.sh queues an
# array of 3 shard tasks (2 MPI ranks each, mpirun inside the allocation) and the merge job.
# One task is cancelled before it starts, so the first merge leaves its replicas pending;
# submitting the same command again resumes (the other shards skip their finished replicas)
# and completes the archive, which must be bitwise identical to an unsharded run.
#   array_campaign.sh JAMSIM REPO_ROOT        (root; exit 77 = skipped when not root)
set -euo pipefail
jamsim=$1 root=$2
source "$(dirname "$0")/local_slurm.sh" slurm-array
campaign=$root/tests/data/campaigns/small.toml

"$MPIEXEC" -n 1 "$jamsim" run "$campaign" -o "$work/whole.h5" >/dev/null

# First submission, one task at a time (--throttle 1), so task 2 is still pending when it is
# cancelled.
"$root/slurm/submit_campaign.sh" --throttle 1 "$campaign" "$work/merged.h5" 3 --ntasks=2 \
  --output="$work/task_%A_%a.out" | tee "$work/submit1.txt"
array=$(sed -n 's/^array job \([0-9]*\):.*/\1/p' "$work/submit1.txt")
merge=$(sed -n 's/^merge job \([0-9]*\) after.*/\1/p' "$work/submit1.txt")
# A second submission while this array is queued is refused (two tasks must never write the
# same shard).
if "$root/slurm/submit_campaign.sh" "$campaign" "$work/merged.h5" 3 2> "$work/busy.txt"; then
  echo "FAIL: a second submission was queued while the first array ran"; exit 1
fi
grep -q "array job $array of this campaign is still queued or running" "$work/busy.txt"
scancel "${array}_2"
# One reading of the state per pass: two readings could straddle the job's completion.
while state=$(scontrol -o show job "$merge") && ! grep -q "JobState=COMPLETED" <<<"$state"; do
  grep -qE "JobState=(PENDING|RUNNING|CONFIGURING|COMPLETING)" <<<"$state" ||
    { echo "merge job $merge did not complete:"; echo "$state"; exit 1; }
  sleep 1
done
"$jamsim" status "$work/merged.h5" | tee "$work/status1.txt"
grep -q "12/18 done" "$work/status1.txt"  # replicas 2, 5, 8, ... (task 2) are missing
grep -q "JobState=COMPLETED.*ArrayTaskId=0 " "$SLURM_LOCAL_DIR/log/jobcomp.txt"

# The same command again, waiting for the merge: the campaign completes. This time the tasks
# launch with srun (PMIx) instead of mpirun, and pass --retry-failed on to jamsim run.
JAMSIM_LAUNCHER=srun "$root/slurm/submit_campaign.sh" --wait --retry-failed "$campaign" \
  "$work/merged.h5" 3 --ntasks=2 --output="$work/task_%A_%a.out" | tee "$work/submit2.txt"
array2=$(sed -n 's/^array job \([0-9]*\):.*/\1/p' "$work/submit2.txt")
grep -q "failed ones run again" "$work/task_${array2}_0.out"
grep -q "on 2 ranks" "$work/task_${array2}_2.out"
"$jamsim" status "$work/merged.h5" | grep -q "18/18 done"
# Shards 0 and 1 were finished: their second runs skipped every replica.
grep -q "resuming" "$work"/task_*_0.out
/usr/bin/python3 "$root/tests/mpi/compare_archives.py" "$work/whole.h5" "$work/merged.h5"

# Bad input is refused before anything is queued.
refused() {  # refused PATTERN ARGS...: submit_campaign.sh must fail naming the problem
  local pattern=$1
  shift
  if "$root/slurm/submit_campaign.sh" "$@" 2> "$work/refused.txt"; then
    echo "FAIL: submit_campaign.sh $* was accepted"; exit 1
  fi
  grep -q -- "$pattern" "$work/refused.txt" || { cat "$work/refused.txt"; exit 1; }
}
queued=$(squeue -h | wc -l)
refused "unknown_key.toml" "$root/tests/data/campaigns/unknown_key.toml" "$work/bad.h5" 2
refused "SHARDS = '0' is not allowed" "$campaign" "$work/bad.h5" 0
refused "made with 3" "$campaign" "$work/merged.h5" 2
refused "different campaign" "$root/tests/data/campaigns/other_campaign.toml" "$work/merged.h5" 3
test ! -e "$work/bad.shards"
[[ $(squeue -h | wc -l) -eq $queued ]]
echo "slurm array campaign: ok"
