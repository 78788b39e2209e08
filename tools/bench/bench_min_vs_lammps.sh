#!/usr/bin/env bash
# Minimisation of RAND configurations (phi = 0.85, harmonic, above phi_J) by jamsim's CG
# (cg: hybrid HS/DY beta; cg-pr: Polak-Ribiere) and FIRE and by Debian's LAMMPS (min_style cg and fire) on the very same configurations: jamsim
# writes each random start as a LAMMPS data file, both codes minimise it until the largest
# force component is below 1e-12 (LAMMPS: min_modify norm max; jamsim: --force-tol 0
# --force-tol-abs 1e-12). One core each, one after the other on this machine.
# Prints per configuration: iterations, force evaluations, force floor reached and time, then
# per N the ratio of total times LAMMPS best / jamsim best.
#
#   tools/bench/bench_min_vs_lammps.sh [N ...]       default: 1024 16384; SEEDS (default "1 2 3")
# FIRE runs only for N <= ${FIRE_MAX_N:-4096} in both codes: at N = 16384 it needs minutes per
# configuration (seed 1: jamsim 227 s, LAMMPS 757 s, both ~6.8e5 iterations); set
# FIRE_MAX_N=16384 to run it.
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then  # the header above, on stdout
  awk 'NR > 1 { if ($0 !~ /^#( |$)/) exit; sub(/^# ?/, ""); print }' "$0"
  exit 0
fi
cd "$(dirname "$0")/../.."
tools/install-deps.sh --bench >/dev/null
tools/build.sh >/dev/null
sizes=("$@")
[[ ${#sizes[@]} -gt 0 ]] || sizes=(1024 16384)
seeds=(${SEEDS:-1 2 3})
fire_max=${FIRE_MAX_N:-4096}
work=build/lammps-bench
mkdir -p "$work"
[[ -s $work/harmonic.table ]] || /usr/bin/python3 tools/lammps/make_table.py "$work/harmonic.table"

field() { sed -n "s|.* $1=\([^ ]*\).*|\1|p"; }
printf "%-6s %-5s %-12s %-10s %-8s %-10s %-9s %s\n" N seed code iterations evals fmax E/N seconds
for n in "${sizes[@]}"; do
  declare -A total=() skip=()
  for s in "${seeds[@]}"; do
    data=$work/min_N${n}_s${s}.data
    declare -A jt=()
    for m in cg cg-pr fire; do
      [[ $m == fire && $n -gt $fire_max ]] && continue
      line=$(build/release/jamsim minimize --N "$n" --phi 0.85 --seed "$s" --minimizer "$m" \
               --force-tol 0 --force-tol-abs 1e-12 --lammps-data "$data" | grep '^RESULT' || true)
      [[ $(field outcome <<<"$line") == force_balanced ]] || echo "note: jamsim-$m did not reach the tolerance: $line"
      t=$(field seconds <<<"$line")
      jt[$m]=$t
      printf "%-6s %-5s %-12s %-10s %-8s %-10s %-9s %s\n" "$n" "$s" "jamsim-$m" "$(field iterations <<<"$line")" \
        "$(field force_evaluations <<<"$line")" "$(field fmax <<<"$line")" "$(field E/N <<<"$line")" "$t"
    done
    declare -A lt=()
    for m in cg fire; do
      [[ $m == fire && $n -gt $fire_max ]] && continue
      log=$work/min_${m}_N${n}_s${s}.log
      if ! lmp -in tools/lammps/in.minimize -var data "$data" -var style "$m" -var table "$work/harmonic.table" \
          -log "$log" -screen none -nocite >/dev/null 2>&1; then
        # e.g. "Pair distance < table inner cutoff": two random disks almost on top of each
        # other, which LAMMPS's tabulated pair style cannot start from.
        echo "note: lammps-$m failed on N=$n seed=$s: $(grep -m1 ERROR "$log" || echo '?'); seed left out of the totals"
        skip[$s]=1
        continue
      fi
      t=$(grep "^Loop time" "$log" | tail -1 | awk '{print $4}')
      res=$(grep '^RESULT' "$log" | tail -1)
      its=$(grep "Iterations, force evaluations" "$log" | tail -1 | awk '{print $5}')
      evals=$(grep "Iterations, force evaluations" "$log" | tail -1 | awk '{print $6}')
      lt[$m]=$t
      printf "%-6s %-5s %-12s %-10s %-8s %-10s %-9s %s\n" "$n" "$s" "lammps-$m" "$its" "$evals" \
        "$(field fmax <<<"$res")" "$(field E/N <<<"$res")" "$t"
      if /usr/bin/python3 -c "import sys; sys.exit(0 if float('$(field fmax <<<"$res")') > 1e-12 else 1)"; then
        # e.g. "linesearch alpha is zero": LAMMPS stopped early, so its time is if anything short
        echo "note: lammps-$m stopped above the tolerance on N=$n seed=$s: $(grep -m1 'Stopping criterion' "$log" | sed 's/^ *//'); its time is kept in the totals"
      fi
    done
    if [[ -z ${skip[$s]:-} ]]; then  # totals over the configurations every code finished
      for m in "${!jt[@]}"; do total[jamsim-$m]=$(/usr/bin/python3 -c "print(${total[jamsim-$m]:-0}+${jt[$m]})"); done
      for m in "${!lt[@]}"; do total[lammps-$m]=$(/usr/bin/python3 -c "print(${total[lammps-$m]:-0}+${lt[$m]})"); done
    fi
    unset jt lt
  done
  best_j=${total[jamsim-cg]}
  for m in cg-pr fire; do
    [[ -n ${total[jamsim-$m]:-} ]] && best_j=$(/usr/bin/python3 -c "print(min($best_j, ${total[jamsim-$m]}))")
  done
  best_l=${total[lammps-cg]}
  [[ -n ${total[lammps-fire]:-} ]] && best_l=$(/usr/bin/python3 -c "print(min($best_l, ${total[lammps-fire]}))")
  echo "N=$n total over the seeds every code finished: jamsim cg ${total[jamsim-cg]} s, jamsim cg-pr ${total[jamsim-cg-pr]} s${total[jamsim-fire]:+, jamsim fire ${total[jamsim-fire]} s}," \
       "lammps cg ${total[lammps-cg]} s${total[lammps-fire]:+, lammps fire ${total[lammps-fire]} s}" \
       "-> LAMMPS best / jamsim best = $(/usr/bin/python3 -c "print(round($best_l/$best_j, 2))")"
  unset total skip
done
