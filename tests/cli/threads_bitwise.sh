#!/usr/bin/env bash
# usage: threads_bitwise.sh JAMSIM WORKDIR dynamics|protocols
# One replica of every dynamical model (N = 10000: three blocks of the force loop and of the
# blocked sums, the last one short) on 1 thread and on 2, 3 and 4; or of every minimisation
# protocol (N = 4200: two blocks, the second of 104 disks) on 1 and 2, and the three quick ones
# (QS, RAND, COOL) on 3 too, where a thread has no block. The files must hold the same bits
# (threads may outnumber the cores). JAMSIM_BITWISE_THREADS replaces the lists of thread counts.
# Why not every protocol on 3 threads: a minimiser meets a barrier every few microseconds at
# N = 4200, and 3 threads on 2 cores wait a time slice at each, so COMPRESS took 105 s on
# 3 threads against 16 s on 1 and 20 s on 2 (all protocols on 3: about 320 s of CI).
set -euo pipefail
jamsim=$1 work=$2 set=$3
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$work" && cd "$work"
dynamics=(
  "RD0 --rate 1e-3 --strain 0.02 --sample-interval 0.005 --integrator heun"
  "CD0 --rate 1e-3 --strain 0.004 --sample-interval 0.002"
  "RD --rate 1e-3 --strain 0.01 --sample-interval 0.005"
  "CD --rate 1e-3 --strain 0.01 --sample-interval 0.005"
  "CDn --rate 1e-3 --strain 0.01 --sample-interval 0.005"
  "CDt --rate 1e-3 --strain 0.01 --sample-interval 0.005"
  "RD0T --rate 1e-3 --strain 0.01 --sample-interval 0.005"
)
# A protocol's line starts with the thread counts it is compared on (besides 1).
protocols=(
  "2,3 QS --strain 0.0004 --strain-step 1e-4 --sample-interval 0.0002 --phi 0.86"
  "2,3 RAND --phi 0.86"
  "2 COMPRESS --phi 0.8 --phi-tol 1e-3"
  "2,3 COOL --phi 0.86 --cooling-time 20"
  "2 COOL_COMPRESS --phi 0.8 --cooling-time 10 --phi-tol 1e-3"
  "2 SHEARED --phi 0.8 --strain 0.0002 --strain-step 1e-4 --phi-tol 1e-3"
)
if [[ $set == dynamics ]]; then
  models=() n=10000
  for m in "${dynamics[@]}"; do models+=("2,3,4 $m"); done
else
  models=("${protocols[@]}") n=4200
fi
for line in "${models[@]}"; do
  threads=${line%% *} m=${line#* }
  threads=${threads//,/ }
  # On a machine with more cores: JAMSIM_BITWISE_THREADS="8 16" (tests/bench/scaling.sh does this).
  threads=${JAMSIM_BITWISE_THREADS:-$threads}
  name=${m%% *}
  # shellcheck disable=SC2086
  "$jamsim" replica --model $m --N $n --threads 1 -o "$name.1.h5" > /dev/null 2> "$name.1.err"
  for t in $threads; do
    # shellcheck disable=SC2086
    "$jamsim" replica --model $m --N $n --threads $t -o "$name.$t.h5" > /dev/null 2> "$name.$t.err"
    "${PYTHON:-/usr/bin/python3}" "$here/compare_replica_files.py" "$name.1.h5" "$name.$t.h5" > /dev/null ||
      { echo "FAIL: $name on $t threads differs from 1 thread"; exit 1; }
  done
  echo "ok: $name the same on 1 and $threads threads"
done
