#!/usr/bin/env bash
# usage: threads_campaign.sh JAMSIM WORKDIR COMPARE_PY
# A campaign on 2 ranks x 2 threads, stopped by SIGUSR1 while replicas run and resumed on
# 2 ranks x 1 thread, against the same campaign on 1 rank x 1 thread: bitwise the same
# (its N = 2048 replicas take the threaded force loop).
set -uo pipefail
jamsim=$1 work=$2 compare=$3
mpirun=${MPIEXEC:-mpiexec}
here=$(cd "$(dirname "$0")" && pwd)
spec=$here/kill_loop_campaign.toml
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
timeout 300 "$mpirun" -n 1 "$jamsim" run "$spec" -o ref.h5 --threads 1 > ref.log 2>&1 || { cat ref.log; exit 1; }
# SIGUSR1 to mpiexec 2 s after the ranks started (a signal before is lost: wait_for_ranks.sh).
timeout 300 "$mpirun" -n 2 "$jamsim" run "$spec" -o thr.h5 --threads 2 > stop.log 2>&1 &
leader=$!
"$here/../wait_for_ranks.sh" "$leader" 2 "^$jamsim run $spec -o thr.h5" && sleep 2 &&
  pkill -USR1 -P "$leader"  # mpiexec, the child of timeout
rc=0; wait "$leader" || rc=$?
[[ $rc -eq 75 ]] || { cat stop.log; echo "FAIL: exit $rc after SIGUSR1, expected 75"; exit 1; }
ls thr.h5.checkpoints/replica_*.h5 > /dev/null 2>&1 || { echo "FAIL: no checkpoint saved"; exit 1; }
timeout 300 "$mpirun" -n 2 "$jamsim" run "$spec" -o thr.h5 --threads 1 > resume.log 2>&1 || { cat resume.log; exit 1; }
grep -q "continued from checkpoints" resume.log || { cat resume.log; exit 1; }
/usr/bin/python3 "$compare" ref.h5 thr.h5
