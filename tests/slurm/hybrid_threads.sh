#!/usr/bin/env bash
# Hybrid MPI x threads through a real (local, single-node) Slurm: slurm/submit_campaign.sh
# --threads 2 queues an array of 2 shard tasks of 1 rank x 2 CPUs (--cpus-per-task=2), launched
# with mpirun (--map-by slot:PE=2) and then with srun (--cpus-per-task=2). Each task's log must
# show 2 threads and no oversubscription warning (the rank has its 2 cores), and the merged
# archive must be complete and bitwise identical to a run on 1 rank x 1 thread. Bad thread
# counts are refused before anything is queued.
#   hybrid_threads.sh JAMSIM REPO_ROOT        (root; exit 77 = skipped when not root)
set -euo pipefail
jamsim=$1 root=$2
[[ $(nproc) -ge 2 ]] || { echo "skipped: fewer than 2 cores"; exit 77; }
source "$(dirname "$0")/local_slurm.sh" slurm-hybrid
campaign=$root/tests/data/campaigns/small.toml
fail() { echo "FAIL: $*"; exit 1; }

"$MPIEXEC" -n 1 "$jamsim" run "$campaign" -o "$work/whole.h5" --threads 1 >/dev/null

for launcher in mpirun srun; do
  JAMSIM_LAUNCHER=$launcher "$root/slurm/submit_campaign.sh" --wait --threads 2 "$campaign" \
    "$work/$launcher.h5" 2 --ntasks=1 --output="$work/${launcher}_%A_%a.out" | tee "$work/submit_$launcher.txt"
  grep -q "2 tasks of 2 thread(s) per rank" "$work/submit_$launcher.txt" || fail "submit did not take --threads 2"
  array=$(sed -n 's/^array job \([0-9]*\):.*/\1/p' "$work/submit_$launcher.txt")
  for task in 0 1; do
    log=$work/${launcher}_${array}_$task.out
    cat "$log"
    grep -q "on 1 ranks x 2 threads" "$log" || fail "$launcher task $task: the script does not say 2 threads"
    grep -q "replicas on 1 rank x 2 threads" "$log" || fail "$launcher task $task: jamsim run did not run 2 threads"
    ! grep -q "threads will share cores" "$log" || fail "$launcher task $task: the rank did not get 2 cores"
  done
  "$jamsim" status "$work/$launcher.h5" | grep -q "18/18 done" || fail "$launcher: the archive is not complete"
  /usr/bin/python3 "$root/tests/mpi/compare_archives.py" "$work/whole.h5" "$work/$launcher.h5"
done

# Bad thread counts: refused with a message, nothing queued.
queued=$(squeue -h | wc -l)
refused() {  # refused PATTERN ARGS...
  local pattern=$1
  shift
  if "$root/slurm/submit_campaign.sh" "$@" 2> "$work/refused.txt"; then fail "submit_campaign.sh $* was accepted"; fi
  grep -q -- "$pattern" "$work/refused.txt" || { cat "$work/refused.txt"; fail "no message /$pattern/"; }
}
refused "--threads = '0' is not allowed: a whole number of threads from 1 to 4096" --threads 0 "$campaign" "$work/bad.h5" 2
refused "--threads = 'two' is not allowed" --threads=two "$campaign" "$work/bad.h5" 2
refused "--cpus-per-task = '3' is not allowed with --threads 2" --threads 2 "$campaign" "$work/bad.h5" 2 --cpus-per-task=3
refused "--cpus-per-task = '4' is not allowed with --threads 1" "$campaign" "$work/bad.h5" 2 -c 4
test ! -e "$work/bad.shards" || fail "a shard folder was made"
[[ $(squeue -h | wc -l) -eq $queued ]] || fail "something was queued"
echo "slurm hybrid threads: ok"
