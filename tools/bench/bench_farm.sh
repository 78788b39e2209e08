#!/usr/bin/env bash
# Load balancing of the campaign farm (a benchmark, not a test).
#  (a) 16 equal RD0 replicas on 1 and 2 ranks: replica throughput ratio (target >= 1.8).
#  (b) 3 replicas of cost 10 and 20 of cost 1 on 2 ranks: makespan against the lower bound
#      max(total cost / P, largest replica), costs taken from the replicas' own wall times
#      in the archive (target: within 10%).
#   tools/bench/bench_farm.sh       no arguments; builds first (JAMSIM_PRESET picks the preset),
#                             works in build/bench-farm
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then  # the header above, on stdout
  awk 'NR > 1 { if ($0 !~ /^#( |$)/) exit; sub(/^# ?/, ""); print }' "$0"
  exit 0
fi
[[ $# -eq 0 ]] || { echo "bench_farm.sh: argument '$1' is not allowed: it takes none; --help says what it does" >&2; exit 2; }
cd "$(dirname "$0")/../.."
tools/build.sh >/dev/null
[[ $(id -u) -ne 0 ]] || export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
jamsim=build/${JAMSIM_PRESET:-release}/jamsim
work=build/bench-farm
mkdir -p "$work"
cat > "$work/equal.toml" <<TOML
[campaign]
name = "equal"
output = "equal.h5"
[run]
strain = 4.0
sample_interval = 0.05
[sweep]
N = [1024]
phi = [0.84]
rate = [1e-3]
seeds = 16
TOML
{
  printf '[campaign]\nname = "spread"\noutput = "spread.h5"\n[run]\nstrain = 4.0\nsample_interval = 0.05\n'
  printf '[sweep]\nN = [1024]\nphi = [0.83, 0.84, 0.85]\nrate = [1e-4]\npoints = [\n'
  for k in $(seq 0 19); do printf '  {N = 1024, phi = %s, rate = 1e-3},\n' "$(awk "BEGIN{print 0.80 + 0.003*$k}")"; done
  printf ']\n'
} > "$work/spread.toml"

makespan() { grep -oE 'finished in [0-9.]+' "$1" | awk '{print $3}'; }
for n in 1 2; do
  rm -f "$work/equal$n.h5"
  mpirun -n $n "$jamsim" run "$work/equal.toml" -o "$work/equal$n.h5" --progress lines > "$work/equal$n.log"
done
t1=$(makespan "$work/equal1.log"); t2=$(makespan "$work/equal2.log")
echo "(a) 16 equal replicas: 1 rank $t1 s, 2 ranks $t2 s -> throughput ratio $(awk "BEGIN{printf \"%.2f\", $t1/$t2}") (target >= 1.8)"

rm -f "$work/spread.h5"
mpirun -n 2 "$jamsim" run "$work/spread.toml" -o "$work/spread.h5" --progress lines > "$work/spread.log"
t=$(makespan "$work/spread.log")
/usr/bin/python3 - "$work/spread.h5" "$t" <<'PY'
import sys, h5py
f = h5py.File(sys.argv[1], "r")
wall = f["replicas/wall_seconds"][...]
makespan = float(sys.argv[2])
bound = max(wall.sum() / 2, wall.max())
print(f"(b) 10:1 cost spread, 23 replicas on 2 ranks: largest {wall.max():.2f} s, smallest "
      f"{wall.min():.2f} s, total {wall.sum():.2f} s; makespan {makespan:.2f} s vs bound "
      f"{bound:.2f} s -> {100 * (makespan / bound - 1):+.1f}% (target within 10%)")
PY
