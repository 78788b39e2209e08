#!/usr/bin/env bash
# The dry run's cost estimate against the measured cost, per model and protocol: for each
# benchmark campaign (tests/bench/campaigns/cost_*.toml, a few seconds of work each) the
# estimate of `jamsim run --dry-run` (throughput calibrated on this machine), then the campaign
# run on one rank; measured = the sum of its replicas' wall times (core-seconds). Prints a
# Markdown table. Not a test: timings depend on the machine and its load.
#   tools/bench/cost_accuracy.sh [JAMSIM] [CAMPAIGN.toml ...]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
if [[ ${1:-} == -h || ${1:-} == --help ]]; then
  sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'
  exit 0
fi
jamsim=${1:-$root/build/release/jamsim}
[[ $# -gt 0 ]] && shift
[[ -x $jamsim ]] || { echo "cost_accuracy.sh: JAMSIM = '$jamsim' is not allowed: an executable jamsim (build it: tools/build.sh)" >&2; exit 2; }
campaigns=("$@")
[[ ${#campaigns[@]} -gt 0 ]] || campaigns=("$root"/tests/bench/campaigns/cost_*.toml)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| campaign | model | replicas | estimated core-s | measured core-s | estimated / measured |"
echo "|---|---|---:|---:|---:|---:|"
for spec in "${campaigns[@]}"; do
  name=$(basename "$spec" .toml)
  out="$work/$name.h5"
  estimate=$("$jamsim" run --dry-run "$spec" -o "$out" 2>/dev/null | sed -n 's/^total: .* core-hours, \([0-9.e+-]*\) core-seconds.*/\1/p')
  "$jamsim" run "$spec" -o "$out" --progress lines > "$work/$name.log" 2>&1 || { cat "$work/$name.log" >&2; exit 1; }
  /usr/bin/python3 - "$out" "$name" "$estimate" <<'PY'
import sys
import h5py
path, name, estimate = sys.argv[1], sys.argv[2], float(sys.argv[3])
with h5py.File(path, "r") as f:
    measured = float(f["replicas/wall_seconds"][...].sum())
    model = f.attrs["model"] if "model" in f.attrs else "?"
    n = len(f["replicas/status"])
print(f"| {name} | {model} | {n} | {estimate:.3g} | {measured:.3g} | {estimate / measured:.2f} |")
PY
done
