#!/usr/bin/env bash
# usage: threads_bitwise.sh JAMSIM WORKDIR dynamics|protocols
# One replica of every dynamical model (N = 10000: three blocks of the force loop and of the
# blocked sums, the last one short) on 1 thread and on 2, 3 and 4; or of every minimisation
# protocol (N = 4200: two blocks, the second of 104 disks) on 1 and 3. The files must hold the same bits (threads may outnumber
# the cores). JAMSIM_BITWISE_THREADS replaces the list of thread counts.
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
protocols=(
  "QS --strain 0.0004 --strain-step 1e-4 --sample-interval 0.0002 --phi 0.86"
  "RAND --phi 0.86"
  "COMPRESS --phi 0.8 --phi-tol 1e-3"
  "COOL --phi 0.86 --cooling-time 20"
  "COOL_COMPRESS --phi 0.8 --cooling-time 10 --phi-tol 1e-3"
  "SHEARED --phi 0.8 --strain 0.0002 --strain-step 1e-4 --phi-tol 1e-3"
)
if [[ $set == dynamics ]]; then models=("${dynamics[@]}") n=10000 threads="2 3 4"; else models=("${protocols[@]}") n=4200 threads=3; fi
# On a machine with more cores: JAMSIM_BITWISE_THREADS="8 16" (tests/bench/scaling.sh does this).
threads=${JAMSIM_BITWISE_THREADS:-$threads}
for m in "${models[@]}"; do
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
