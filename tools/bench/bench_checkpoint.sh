#!/usr/bin/env bash
# Checkpoint overhead: one RD0 replica (phi = 0.84, rate 1e-4, dt 0.2) run three ways on one
# rank, and the particle-steps per second of each:
#   none     no checkpoint steps before the end (checkpoint_steps = the run's steps)
#   default  checkpoint steps every 10000 steps (the default), saves at most every 300 s
#   every    checkpoint steps every 10000 steps, a save at each (--checkpoint-every 0)
# "vs none" is the wall-time difference (run-to-run noise on a shared VM is a few per cent);
# "writes (io)" is the time the rank spent in archive and checkpoint writes, measured inside
# jamsim, the overhead of saving itself.
#   tools/bench/bench_checkpoint.sh [N STEPS ...]     default: 1024 1000000 65536 30000
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then  # the header above, on stdout
  awk 'NR > 1 { if ($0 !~ /^#( |$)/) exit; sub(/^# ?/, ""); print }' "$0"
  exit 0
fi
cd "$(dirname "$0")/../.."
jamsim=${JAMSIM:-build/release/jamsim}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
[[ $# -gt 0 ]] || set -- 1024 1000000 65536 30000
printf "%7s %9s %-8s %10s %14s %9s %12s\n" N steps variant seconds particle-steps/s "vs none" "writes (io)"
while [[ $# -ge 2 ]]; do
  n=$1 steps=$2
  shift 2
  strain=$(awk -v s="$steps" 'BEGIN { printf "%.10g", s * 0.2 * 1e-4 }')
  base=""
  for variant in none default every; do
    every=10000 save=300
    [[ $variant == none ]] && every=$steps  # the only checkpoint step is the last
    [[ $variant == every ]] && save=0
    cat > "$work/c.toml" <<TOML
[campaign]
name = "bench-checkpoint"
output = "$work/c.h5"
[run]
strain = $strain
sample_interval = $(awk -v s="$strain" 'BEGIN { printf "%.10g", s / 10 }')
checkpoint_steps = $every
[sweep]
N = [$n]
phi = [0.84]
rate = [1e-4]
TOML
    rm -rf "$work/c.h5" "$work/c.h5.checkpoints"
    out=$("$jamsim" run "$work/c.toml" --checkpoint-every "$save" --progress lines)
    t=$(sed -n 's/.* finished in \([0-9.]*\) s.*/\1/p' <<<"$out")
    io=$(sed -n 's/.*archive writes took \([0-9.]*\)%.*/\1/p' <<<"$out")
    rate=$(awk -v n="$n" -v s="$steps" -v t="$t" 'BEGIN { printf "%.3g", n * s / t }')
    [[ -z $base ]] && base=$t
    printf "%7s %9s %-8s %10s %14s %8.2f%% %11s%%\n" "$n" "$steps" "$variant" "$t" "$rate" \
      "$(awk -v t="$t" -v b="$base" 'BEGIN { print 100 * (t / b - 1) }')" "$io"
  done
done
