#!/usr/bin/env bash
# usage: submit_refusals.sh JAMSIM CAMPAIGN (in a scratch folder; no Slurm needed)
# slurm/submit_campaign.sh checks the variables its array tasks read before it makes a folder
# or queues a job: JAMSIM_LAUNCHER (a typo failed every task at its start), JAMSIM_MAX_REQUEUES
# (abc killed a task at its first requeue, 1.5 requeued for ever) and JAMSIM_SIGNAL_LEAD; a
# refused campaign leaves no folder either (the MERGED folder was made first).
set -uo pipefail
jamsim=$1 campaign=$2
submit=$(dirname "$0")/../../slurm/submit_campaign.sh
rm -rf sub_work && mkdir sub_work && cd sub_work || exit 1
printf '[campaign]\nname = "bad"\noutput = "bad.h5"\n[model]\nname = "RD0"\n[sweep]\nN = [16]\nphi = [2]\nrate = [1e-2]\n' > bad.toml
check() {  # REGEX VAR=VALUE... -- submit arguments
  local regex=$1
  shift
  msg=$(env JAMSIM="$jamsim" PATH=/usr/bin:/bin "$@" 2>&1)
  rc=$?
  echo "$msg"
  [[ $rc -eq 2 ]] || { echo "FAIL: exit $rc, not 2"; exit 1; }
  grep -Eq -- "$regex" <<<"$msg" || { echo "FAIL: no /$regex/"; exit 1; }
  [[ -z $(ls -A) || $(ls -A) == bad.toml ]] || { echo "FAIL: left behind: $(ls -A)"; exit 1; }
}
check "JAMSIM_LAUNCHER = 'srn' is not allowed: mpirun or srun" JAMSIM_LAUNCHER=srn bash "$submit" "$campaign" new/m.h5 2
for v in abc -1 1.5 "2 3"; do
  check "JAMSIM_MAX_REQUEUES = '$v' is not allowed: a whole number of requeues" JAMSIM_MAX_REQUEUES="$v" \
    bash "$submit" "$campaign" new/m.h5 2
done
check "JAMSIM_SIGNAL_LEAD = '0' is not allowed" JAMSIM_SIGNAL_LEAD=0 bash "$submit" "$campaign" new/m.h5 2
check "phi = 2 is not allowed" bash "$submit" bad.toml new/sub/m.h5 2
# An empty or folder-like MERGED (realpath failed on '' and dropped the slash of m.h5/), and a
# JAMSIM that is a folder or no jamsim (line 121: //tmp: Is a directory; /bin/false: no word).
for merged in '' new/m.h5/ new/.; do
  check "MERGED.h5 = '$merged' is not allowed: the path of the campaign's archive file" bash "$submit" "$campaign" "$merged" 1
done
msg=$(env JAMSIM=/tmp PATH=/usr/bin:/bin bash "$submit" "$campaign" new/m.h5 1 2>&1); rc=$?
[[ $rc -eq 2 ]] && grep -q "no jamsim executable" <<<"$msg" || { echo "$msg"; echo "FAIL: JAMSIM=/tmp (exit $rc)"; exit 1; }
msg=$(env JAMSIM=/bin/false PATH=/usr/bin:/bin bash "$submit" "$campaign" new/m.h5 1 2>&1); rc=$?
[[ $rc -eq 2 ]] && grep -q "JAMSIM = '/bin/false' is not allowed: a jamsim executable" <<<"$msg" ||
  { echo "$msg"; echo "FAIL: JAMSIM=/bin/false (exit $rc)"; exit 1; }
# The script's own options after the positionals went to sbatch (--threads 4 ran one thread);
# SHARDS beyond the replicas queued tasks for nothing (10^8 without a word for one replica).
for option in --threads=4 --wait --retry-failed; do
  check "option '$option' after CAMPAIGN.toml MERGED.h5 SHARDS is not allowed" bash "$submit" "$campaign" new/m.h5 1 "$option"
done
check "option '--throttle' after CAMPAIGN.toml MERGED.h5 SHARDS is not allowed" bash "$submit" "$campaign" new/m.h5 1 --throttle 2
for shards in 2 100000000; do
  check "SHARDS = $shards is not allowed for .*other_campaign.toml: at most its 1 replica \\(" bash "$submit" "$campaign" new/m.h5 $shards
done
# A rate ladder's chain stays in one task: 24 replicas in 8 chains make at most 8 shards.
check "SHARDS = 9 is not allowed for .*ladder.toml: at most its 8 rate-ladder chains \\(of 24 replicas" \
  bash "$submit" "$(dirname "$campaign")/ladder.toml" new/m.h5 9
# sbatch options that undo what the array job needs were passed on (no task could work in a
# limit shorter than the signal's lead; --array gave tasks shards beyond SHARDS; --signal
# stopped the requeue), and a throttle of 20 digits went to sbatch as it was.
for time in --time=00:05:00 --time=1 -t4 --time=abc; do
  check "sbatch option --time = '.*' is not allowed: a time limit longer than the 300 s before it" bash "$submit" "$campaign" new/m.h5 1 "$time"
done
check "sbatch option '--array=0-99' is not allowed: the script makes the array itself" bash "$submit" "$campaign" new/m.h5 1 --array=0-99
check "sbatch option '--signal=USR2@10' is not allowed: the tasks need the script's --signal=B:USR1@LEAD" \
  bash "$submit" "$campaign" new/m.h5 1 --signal=USR2@10
check "sbatch option '--no-requeue' is not allowed" bash "$submit" "$campaign" new/m.h5 1 --no-requeue
check "sbatch option '--cpus-per-task' is not allowed without a value" bash "$submit" "$campaign" new/m.h5 1 --cpus-per-task
check "--throttle = '99999999999999999999' is not allowed: a whole number of tasks" \
  bash "$submit" --throttle 99999999999999999999 "$campaign" new/m.h5 1
check "campaign file '.' is not allowed: a campaign file, not a folder" bash "$submit" . new/m.h5 1
# The array script itself, run by hand or with a bad count: one message, no shard folder (it
# made the folder, then ended in bash's "unbound variable").
sbatch_script=$(dirname "$submit")/campaign_array.sbatch
check "S = 'abc' is not allowed: the number of shards" bash "$sbatch_script" "$campaign" shards abc
check "SLURM_ARRAY_TASK_ID = '' is not allowed: a task of an array 0-1" env -u SLURM_ARRAY_TASK_ID bash "$sbatch_script" "$campaign" shards 2
check "SLURM_ARRAY_TASK_ID = '5' is not allowed: a task of an array 0-1" env SLURM_ARRAY_TASK_ID=5 bash "$sbatch_script" "$campaign" shards 2
echo "ok: refused before any folder or job"
