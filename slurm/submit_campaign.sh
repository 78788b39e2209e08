#!/usr/bin/env bash
# Run a campaign as a Slurm array job, one shard per task, and merge the shards afterwards.
#
#   slurm/submit_campaign.sh [--wait] [--throttle K] [--threads T] [--retry-failed] CAMPAIGN.toml MERGED.h5 SHARDS [sbatch options]
#
#   CAMPAIGN.toml   the campaign file (checked here, before anything is queued)
#   MERGED.h5       the one archive of the campaign; shards go to MERGED.shards/shard_K.h5
#   SHARDS          number of array tasks; task K runs the replicas with id % SHARDS == K
#   --throttle K    at most K tasks at once (sbatch --array=0-(SHARDS-1)%K)
#   --threads T     threads of each rank's replica (default 1): the tasks ask for
#                   --cpus-per-task=T and run `jamsim run --threads T` with OpenMP placed
#                   on cores (OMP_PROC_BIND=close, OMP_PLACES=cores)
#   --retry-failed  the tasks run their failed replicas again (jamsim run --retry-failed)
#   --wait          return when the merge job has finished: 0 if every replica is finished
#                   (done or failed), 3 if some are still pending (submit again)
#   sbatch options  passed to the array job, e.g. --ntasks=4 --time=04:00:00 --partition=short;
#                   --account, --partition, --qos, --reservation and --clusters also go to
#                   the merge job
#
# Submitting the same command again after a time limit, a node failure or a cancelled task
# resumes: each task skips the replicas its shard already holds, and the merge completes the
# existing archive. Refused before anything is queued: a campaign file with an error, an
# existing archive (merged or shard 0) of another campaign or jamsim version, another SHARDS
# than the shards were made with, and an array of this campaign still in the queue.
# JAMSIM (default: the installed jamsim for an installed copy of this script, else
# build/release/jamsim of this checkout, else `jamsim` on PATH) is the executable every job runs. Time limits: the tasks ask for a warning JAMSIM_SIGNAL_LEAD
# seconds (default 300) before their limit (--signal=B:USR1@lead), save their replicas'
# state and requeue themselves (--requeue), at most JAMSIM_MAX_REQUEUES times (default 20).
# Choose the lead longer than one checkpoint interval of the slowest replica plus 60 s
# (Slurm may signal up to a minute early), and the time limit well above the lead.
set -euo pipefail
usage() { sed -n '4,18p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
if [[ "${1:-}" == "--help" || "${1:-}" == "-h" ]]; then  # the header above, on stdout
  sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'
  exit 0
fi
here=$(cd "$(dirname "$0")" && pwd)
wait_flag=() throttle="" threads=1 run_args=""
while [[ $# -gt 0 && $1 == --* ]]; do
  case $1 in
    --wait) wait_flag=(--wait); shift ;;
    --retry-failed) run_args="--retry-failed"; shift ;;
    --throttle) [[ $# -ge 2 ]] || usage; throttle=$2; shift 2 ;;
    --throttle=*) throttle=${1#--throttle=}; shift ;;
    --threads) [[ $# -ge 2 ]] || usage; threads=$2; shift 2 ;;
    --threads=*) threads=${1#--threads=}; shift ;;
    *) echo "submit_campaign.sh: unknown option '$1' (allowed: --wait, --throttle K, --threads T, --retry-failed)" >&2; exit 2 ;;
  esac
done
[[ $# -ge 3 ]] || usage
campaign=$1 merged=$2 shards=$3
shift 3
# This script's options after the positionals would go to sbatch (--threads 4 there left the
# tasks on one CPU each, running one thread).
for option in "$@"; do
  case $option in
    --wait | --retry-failed | --throttle | --throttle=* | --threads | --threads=*)
      echo "submit_campaign.sh: option '$option' after CAMPAIGN.toml MERGED.h5 SHARDS is not allowed: the options after them go to sbatch; give --wait, --throttle K, --threads T and --retry-failed before CAMPAIGN.toml" >&2
      exit 2 ;;
  esac
done
if ! [[ $shards =~ ^[1-9][0-9]*$ ]]; then
  echo "submit_campaign.sh: SHARDS = '$shards' is not allowed: a positive integer" >&2
  exit 2
fi
if [[ -n $throttle && ! $throttle =~ ^[1-9][0-9]{0,6}$ ]]; then
  echo "submit_campaign.sh: --throttle = '$throttle' is not allowed: a whole number of tasks from 1 to 9999999" >&2
  exit 2
fi
if ! [[ $threads =~ ^[1-9][0-9]*$ ]] || [[ ${#threads} -gt 4 ]] || [[ $threads -gt 4096 ]]; then
  echo "submit_campaign.sh: --threads = '$threads' is not allowed: a whole number of threads from 1 to 4096 (threads of each rank's replica)" >&2
  exit 2
fi
# --cpus-per-task among the sbatch options must agree with --threads.
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
  cpus=""
  case ${args[i]} in
    --cpus-per-task=*) cpus=${args[i]#--cpus-per-task=} ;;
    --cpus-per-task | -c) cpus=${args[i + 1]:-} ;;
    -c*) cpus=${args[i]#-c} ;;
  esac
  if [[ -n $cpus && $cpus != "$threads" ]]; then
    echo "submit_campaign.sh: sbatch option --cpus-per-task = '$cpus' is not allowed with --threads $threads: give the threads per task once, as --threads T (it sets --cpus-per-task=T)" >&2
    exit 2
  fi
done
if [[ -d $campaign ]]; then
  echo "submit_campaign.sh: campaign file '$campaign' is not allowed: a campaign file, not a folder" >&2
  exit 2
fi
[[ -f $campaign ]] || { echo "submit_campaign.sh: campaign file '$campaign' does not exist" >&2; exit 2; }
# The variables the tasks read, checked before anything is made or queued (a task would fail
# at its start, or at its first requeue hours in).
lead=${JAMSIM_SIGNAL_LEAD:-300}
if [[ ! $lead =~ ^[1-9][0-9]{0,4}$ ]] || (( lead > 65535 )); then
  echo "submit_campaign.sh: JAMSIM_SIGNAL_LEAD = '$lead' is not allowed: seconds, a whole number from 1 to 65535 (sbatch --signal)" >&2
  exit 2
fi
# sbatch options that would undo what the array job needs: its tasks (--array), the warning
# that lets a task save and requeue (--signal, --requeue), or a limit no task can work in.
slurm_seconds() {  # Slurm's time formats: M, M:S, H:M:S, D-H, D-H:M, D-H:M:S; "" when not one
  local t=$1 days=0 h=0 m=0 sec=0
  if [[ $t =~ ^([0-9]+)-([0-9]+)(:([0-9]+)(:([0-9]+))?)?$ ]]; then
    days=${BASH_REMATCH[1]} h=${BASH_REMATCH[2]} m=${BASH_REMATCH[4]:-0} sec=${BASH_REMATCH[6]:-0}
  elif [[ $t =~ ^([0-9]+):([0-9]+):([0-9]+)$ ]]; then
    h=${BASH_REMATCH[1]} m=${BASH_REMATCH[2]} sec=${BASH_REMATCH[3]}
  elif [[ $t =~ ^([0-9]+)(:([0-9]+))?$ ]]; then
    m=${BASH_REMATCH[1]} sec=${BASH_REMATCH[3]:-0}
  else
    return 0
  fi
  echo $(( ((10#$days * 24 + 10#$h) * 60 + 10#$m) * 60 + 10#$sec ))
}
for ((i = 0; i < ${#args[@]}; i++)); do
  option=${args[i]}
  value=""
  case $option in
    --array | --array=* | -a | -a*)
      echo "submit_campaign.sh: sbatch option '$option' is not allowed: the script makes the array itself (--array=0-(SHARDS-1), with --throttle K as %K); give the task count as SHARDS" >&2
      exit 2 ;;
    --signal | --signal=* | --no-requeue)
      echo "submit_campaign.sh: sbatch option '$option' is not allowed: the tasks need the script's --signal=B:USR1@LEAD and --requeue to save their replicas and continue after a time limit (JAMSIM_SIGNAL_LEAD sets LEAD)" >&2
      exit 2 ;;
    --cpus-per-task | -c)
      [[ $((i + 1)) -lt ${#args[@]} ]] || { echo "submit_campaign.sh: sbatch option '$option' is not allowed without a value: give the threads per task as --threads T" >&2; exit 2; } ;;
    --time=*) value=${option#--time=} ;;
    --time | -t) value=${args[i + 1]:-} ;;
    -t*) value=${option#-t} ;;
  esac
  if [[ ($option == --time || $option == --time=* || $option == -t*) && ! $value =~ ^(UNLIMITED|unlimited|INFINITE|infinite)$ ]]; then
    seconds=$(slurm_seconds "$value")
    if [[ -z $seconds ]] || (( seconds <= ${JAMSIM_SIGNAL_LEAD:-300} )); then
      echo "submit_campaign.sh: sbatch option --time = '$value' is not allowed: a time limit longer than the ${JAMSIM_SIGNAL_LEAD:-300} s before it at which a task saves its replicas (JAMSIM_SIGNAL_LEAD), in Slurm's form (minutes, H:M:S, D-H:M:S)" >&2
      exit 2
    fi
  fi
done
case ${JAMSIM_LAUNCHER:-mpirun} in
  mpirun | srun) ;;
  *) echo "submit_campaign.sh: JAMSIM_LAUNCHER = '$JAMSIM_LAUNCHER' is not allowed: mpirun or srun" >&2; exit 2 ;;
esac
if [[ ! ${JAMSIM_MAX_REQUEUES:-20} =~ ^(0|[1-9][0-9]{0,3})$ ]]; then
  echo "submit_campaign.sh: JAMSIM_MAX_REQUEUES = '$JAMSIM_MAX_REQUEUES' is not allowed: a whole number of requeues from 0 to 9999" >&2
  exit 2
fi
installed_jamsim=""  # an installed copy of this script names its jamsim here (cmake --install)
jamsim=${JAMSIM:-}
if [[ -z $jamsim ]]; then
  if [[ -n $installed_jamsim ]]; then jamsim=$installed_jamsim
  elif [[ -x $here/../build/release/jamsim ]]; then jamsim=$here/../build/release/jamsim
  else jamsim=$(command -v jamsim || true); fi
fi
[[ -n $jamsim && -f $jamsim && -x $jamsim ]] || { echo "submit_campaign.sh: no jamsim executable (set JAMSIM or build first)" >&2; exit 2; }
# JAMSIM=/bin/false ended the script with status 2 and no word.
[[ $("$jamsim" --version 2>/dev/null) == "jamsim "* ]] ||
  { echo "submit_campaign.sh: JAMSIM = '$jamsim' is not allowed: a jamsim executable ('$jamsim --version' does not say jamsim)" >&2; exit 2; }
jamsim=$(cd "$(dirname "$jamsim")" && pwd)/$(basename "$jamsim")
# Jobs may start in another directory: hand them absolute paths.
# (MERGED's folder may not exist yet: it is made once every check has passed.)
# An empty or folder-like MERGED is refused as jamsim refuses it (realpath made '' an error of
# its own and dropped a trailing slash).
if [[ -z $merged || $merged == */ || $merged == . || $merged == .. || $merged == */. || $merged == */.. ]]; then
  echo "submit_campaign.sh: MERGED.h5 = '$merged' is not allowed: the path of the campaign's archive file (not empty, not a folder)" >&2
  exit 2
fi
abs() { realpath -ms -- "$1"; }
campaign=$(abs "$campaign") merged=$(abs "$merged")
shard_dir=${merged%.h5}.shards
# Check the campaign (every key, every value) and the archives already there before queueing
# anything; a dry run checks an existing output against the campaign.
if [[ $(id -u) -eq 0 ]]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
plan=$("$jamsim" run "$campaign" --dry-run -o "$merged" --threads "$threads") || exit 2
if [[ -e $shard_dir/shard_0.h5 ]]; then
  "$jamsim" run "$campaign" --dry-run -o "$shard_dir/shard_0.h5" >/dev/null || exit 2
fi
record=$shard_dir/submission  # "shards S array_job A" of the last submission
if [[ -f $record ]]; then
  read -r _ old_shards _ old_array < "$record" || true
  if [[ -n ${old_shards:-} && $old_shards != "$shards" ]]; then
    echo "submit_campaign.sh: SHARDS = $shards is not allowed for $merged: its shards in $shard_dir were made with $old_shards (use $old_shards, or another MERGED path)" >&2
    exit 2
  fi
  if [[ -n ${old_array:-} ]] && [[ -n $(squeue -h -j "$old_array" -o %i 2>/dev/null) ]]; then
    echo "submit_campaign.sh: array job $old_array of this campaign is still queued or running; wait for it or scancel $old_array" >&2
    exit 2
  fi
fi
replicas=$(sed -n 's/^campaign .*: \([0-9]*\) replicas\{0,1\} .*/\1/p' <<<"$plan" | head -1)
if [[ -z $replicas ]]; then
  echo "submit_campaign.sh: the dry run of $campaign did not say how many replicas it has; nothing was queued" >&2
  exit 2
fi
# Shards are dealt chains (a rate ladder's replicas stay together; a chain without a ladder
# is one replica), and a shard past the chains holds none: a task for nothing (shards made so
# earlier go on).
chains=$(sed -n 's/^at once: at most \([0-9]*\) replicas\{0,1\} run together.*/\1/p' <<<"$plan" | head -1)
chains=${chains:-$replicas}
if (( chains < replicas )); then
  most="$chains rate-ladder chains (of $replicas replicas; task K runs the chains k with k % SHARDS == K, each chain whole)"
else
  most="$replicas replica$([[ $replicas == 1 ]] || echo s) (task K runs the replicas with id % SHARDS == K; a rate ladder's chain stays in one task)"
fi
if [[ ${old_shards:-} != "$shards" ]] && (( ${#shards} > 9 || shards > chains )); then
  echo "submit_campaign.sh: SHARDS = $shards is not allowed for $campaign: at most its $most" >&2
  exit 2
fi
mkdir -p "$(dirname "$merged")" "$shard_dir"
range=0-$((shards - 1))${throttle:+%$throttle}
array=$(sbatch --parsable --array="$range" --signal=B:USR1@"$lead" --requeue --open-mode=append --cpus-per-task="$threads" \
          --export=ALL,JAMSIM="$jamsim",JAMSIM_RUN_ARGS="$run_args" "$@" \
          "$here/campaign_array.sbatch" "$campaign" "$shard_dir" "$shards")
array=${array%%;*}
echo "shards $shards array_job $array" > "$record"
echo "array job $array: $shards tasks of $threads thread(s) per rank -> $shard_dir/shard_K.h5"
merge_output=$(dirname "$merged")/jamsim-merge_%j.out
# Where the cluster needs them, the merge gets the array's account, partition, QOS, ...
site=()
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
  case ${args[i]} in
    --account=* | --partition=* | --qos=* | --reservation=* | --clusters=*) site+=("${args[i]}") ;;
    --account | --partition | --qos | --reservation | --clusters | -A | -p | -q | -M)
      site+=("${args[i]}" "${args[i + 1]:-}")
      i=$((i + 1)) ;;
  esac
done
merge=$(sbatch --parsable --dependency=afterany:"$array" --export=ALL,JAMSIM="$jamsim" \
          "${site[@]}" --output="$merge_output" "$here/merge.sbatch" "$merged" "$shard_dir")
merge=${merge%%;*}
echo "merge job $merge after $array -> $merged"
if [[ ${#wait_flag[@]} -eq 0 ]]; then
  echo "follow: squeue -j $array,$merge; $jamsim status $shard_dir/shard_0.h5"
  exit 0
fi
# --wait: poll the merge job's state (every 2 s; `sbatch --wait` backs off to 30 s). A job
# record can vanish (MinJobAge) or the controller be unreachable: after 60 s without a state
# the archive itself decides.
unknown=0
state=""
while :; do
  info=$(scontrol -o show job "$merge" 2>/dev/null || true)
  state=$(sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' <<<"$info")
  case $state in
    PENDING | RUNNING | CONFIGURING | COMPLETING | SUSPENDED | REQUEUED | RESIZING)
      unknown=0
      # A task Slurm could not launch is requeued held and would keep the merge pending
      # forever: report it instead of waiting.
      held=$(scontrol -o show job "$array" 2>/dev/null | grep -o "JobId=[0-9]* .*Reason=launch_failed_requeued_held" | head -1 || true)
      if [[ -n $held ]]; then
        echo "submit_campaign.sh: a task of array job $array failed to launch and is held (${held%% *}); see scontrol show job $array and the slurmd log" >&2
        exit 1
      fi ;;
    "") unknown=$((unknown + 1)); [[ $unknown -lt 30 ]] || break ;;
    *) break ;;
  esac
  sleep 2
done
echo "merge job $merge: ${state:-state unknown}"
[[ -z $state || $state == COMPLETED ]] || { echo "submit_campaign.sh: the merge job ended $state; see $merge_output" >&2; exit 1; }
status=$("$jamsim" status "$merged") || exit 1
echo "$status"
left=$(sed -n 's/.* done, \([0-9]*\) running, [0-9]* failed, \([0-9]*\) pending.*/\1 \2/p' <<<"$status" | head -1)
if [[ -z $left || $left != "0 0" ]]; then
  echo "submit_campaign.sh: the campaign is not finished (running, pending: ${left:-?}); submit the same command again" >&2
  exit 3
fi
