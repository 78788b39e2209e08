#!/usr/bin/env bash
# RD0 throughput of jamsim against Debian's LAMMPS on this machine, in one run.
#
# Same N, phi = 0.84, harmonic contacts, skin 0.3, shear rate 1e-4, one core, one force
# evaluation per step (jamsim: RD0 forward Euler; LAMMPS: fix nve + fix viscous + fix deform
# remap v, the cheapest damped integrator it has). Prints particle-steps per second for both
# and the ratio jamsim/LAMMPS per force evaluation (median of REPEATS runs, default 3).
#
#   tools/bench_vs_lammps.sh [N ...]      default sizes: 1024 16384 65536
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh --bench >/dev/null
tools/build.sh >/dev/null
sizes=("$@")
[[ ${#sizes[@]} -gt 0 ]] || sizes=(1024 16384 65536)
repeats=${REPEATS:-3}
work=build/lammps-bench
mkdir -p "$work"
[[ -s $work/harmonic.table ]] || /usr/bin/python3 tools/lammps/make_table.py "$work/harmonic.table"

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

printf "%-7s %-16s %-16s %s\n" N "jamsim p-steps/s" "LAMMPS p-steps/s" "ratio"
for n in "${sizes[@]}"; do
  jam=$(for r in $(seq "$repeats"); do
          build/release/tests/bench/jamsim_bench --benchmark_filter="BM_Rd0/N:$n/heun:0/" \
            --benchmark_format=json 2>/dev/null |
            /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["benchmarks"][0]["items_per_second"])'
        done | median)
  steps=$(( n <= 4096 ? 10000 : (n <= 16384 ? 4000 : 1000) ))
  lmp_rate=$(for r in $(seq "$repeats"); do
          log=$work/shear_N${n}_r$r.log
          lmp -in tools/lammps/in.shear -var N "$n" -var nsteps "$steps" -var table "$work/harmonic.table" \
              -log "$log" -screen none -nocite
          t=$(grep "^Loop time" "$log" | tail -1 | awk '{print $4}')
          /usr/bin/python3 -c "print($n*$steps/$t)"
        done | median)
  printf "%-7s %-16.4g %-16.4g %.2f\n" "$n" "$jam" "$lmp_rate" \
    "$(/usr/bin/python3 -c "print($jam/$lmp_rate)")"
done
