#!/usr/bin/env bash
# A campaign longer than its time limit through a real local Slurm: one array task with
# --time=2 (minutes) and the warning 30 s before (Slurm checks limits once a minute, so the
# warning comes 30-90 s into the task) runs replicas of about 100 s of work on one rank. It
# is warned, its replicas save their state at their next checkpoint step, jamsim exits with
# 75, the task requeues itself, continues from the checkpoints, and the merged archive
# equals an uninterrupted mpirun run bitwise.
#   requeue.sh JAMSIM REPO_ROOT        (root; exit 77 = skipped when not root)
set -euo pipefail
jamsim=$1 root=$2
source "$(dirname "$0")/local_slurm.sh" slurm-requeue
campaign=$root/tests/slurm/requeue_campaign.toml
start=$(date +%s)
"$MPIEXEC" -n 2 "$jamsim" run "$campaign" -o "$work/whole.h5" >/dev/null &
reference=$!
JAMSIM_SIGNAL_LEAD=30 "$root/slurm/submit_campaign.sh" --wait "$campaign" "$work/merged.h5" 1 \
  --ntasks=1 --time=2 --output="$work/task_%A_%a.out" | tee "$work/submit.txt"
wait "$reference"
cat "$work"/task_*.out
grep -q "time-limit warning, saving state" "$work"/task_*.out
grep -q "requeueing (restart 1 of at most" "$work"/task_*.out
grep -q "interrupted after" "$work"/task_*.out
"$jamsim" status "$work/merged.h5" | grep -q "2/2 done"
/usr/bin/python3 "$root/tests/mpi/compare_archives.py" "$work/whole.h5" "$work/merged.h5"
echo "requeue test: $(grep -c 'requeueing' "$work"/task_*.out) requeues, $(( $(date +%s) - start )) s wall"
