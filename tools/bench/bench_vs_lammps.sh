#!/usr/bin/env bash
# Shear throughput of jamsim against Debian's LAMMPS on this machine, in one run.
#
# Same N, phi = 0.84, harmonic contacts, skin 0.3, shear rate 1e-4, one core. Prints
# particle-steps per second for both and the ratio jamsim/LAMMPS (median of REPEATS runs,
# default 3).
#   --model RD0 (default): jamsim RD0, forward Euler, dt 0.2, against LAMMPS fix nve +
#       fix viscous + fix deform remap v (the cheapest damped integrator it has); one force
#       evaluation per step on both sides.
#   --model RD: jamsim's massive RD (SLLOD, second-order splitting with the drag integrated
#       exactly, one force evaluation per step), dt 0.1,
#       m = 1, k_d = 1, against LAMMPS fix nve + fix langevin 0 0 1.0 with a temp/deform
#       bias (drag on the velocity relative to the shear profile), dt 0.1; per step.
#
#   tools/bench/bench_vs_lammps.sh [--model RD0|RD] [N ...]   default sizes: 1024 16384 65536
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then  # the header above, on stdout
  awk 'NR > 1 { if ($0 !~ /^#( |$)/) exit; sub(/^# ?/, ""); print }' "$0"
  exit 0
fi
cd "$(dirname "$0")/../.."
tools/install-deps.sh --bench >/dev/null
tools/build.sh >/dev/null
model=RD0
if [[ ${1:-} == --model ]]; then
  model=${2:?--model needs RD0 or RD}
  shift 2
fi
case $model in
  RD0) filter_of() { echo "BM_Rd0/N:$1/heun:0/"; }; damping=viscous; dt=0.1 ;;
  RD) filter_of() { echo "BM_RdMassive/N:$1/"; }; damping=langevin; dt=0.1 ;;
  *) echo "bench_vs_lammps.sh: --model '$model' is not allowed (RD0 or RD)" >&2; exit 2 ;;
esac
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
          build/release/tests/bench/jamsim_bench --benchmark_filter="$(filter_of "$n")" \
            --benchmark_format=json 2>/dev/null |
            /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["benchmarks"][0]["items_per_second"])'
        done | median)
  steps=$(( n <= 4096 ? 10000 : (n <= 16384 ? 4000 : 1000) ))
  lmp_rate=$(for r in $(seq "$repeats"); do
          log=$work/shear_${model}_N${n}_r$r.log
          lmp -in tools/lammps/in.shear -var N "$n" -var nsteps "$steps" -var table "$work/harmonic.table" \
              -var damping "$damping" -var dt "$dt" \
              -log "$log" -screen none -nocite
          t=$(grep "^Loop time" "$log" | tail -1 | awk '{print $4}')
          /usr/bin/python3 -c "print($n*$steps/$t)"
        done | median)
  printf "%-7s %-16.4g %-16.4g %.2f\n" "$n" "$jam" "$lmp_rate" \
    "$(/usr/bin/python3 -c "print($jam/$lmp_rate)")"
done
