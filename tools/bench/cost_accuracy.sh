#!/usr/bin/env bash
# The dry run's cost estimate against the measured cost, per model and protocol: for each
# benchmark campaign (tests/bench/campaigns/cost_*.toml, a few seconds of work each) the
# estimate of `jamsim run --dry-run` (throughput calibrated on this machine, each replica's
# archive writes included), then the campaign run on one rank; measured = the campaign's wall
# time on that rank (core-seconds: its replicas' own wall times, plus what it spent besides
# them, mostly the archive's writes, shared out evenly over the replicas for the rows per N).
# Prints a Markdown table. Not a test: timings depend on the machine and its load.
# PROBE_SECONDS=S gives the dry run `--probe-seconds S`.
#   tools/bench/cost_accuracy.sh [JAMSIM] [CAMPAIGN.toml ...]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
if [[ ${1:-} == -h || ${1:-} == --help ]]; then
  awk 'NR > 1 { if ($0 !~ /^#( |$)/) exit; sub(/^# ?/, ""); print }' "$0"
  exit 0
fi
jamsim=${1:-$root/build/release/jamsim}
[[ $# -gt 0 ]] && shift
[[ -x $jamsim ]] || { echo "cost_accuracy.sh: JAMSIM = '$jamsim' is not allowed: an executable jamsim (build it: tools/build.sh)" >&2; exit 2; }
campaigns=("$@")
[[ ${#campaigns[@]} -gt 0 ]] || campaigns=("$root"/tests/bench/campaigns/cost_*.toml)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| campaign | model | N | replicas | estimated core-s | measured core-s | estimated / measured |"
echo "|---|---|---:|---:|---:|---:|---:|"
for spec in "${campaigns[@]}"; do
  name=$(basename "$spec" .toml)
  out="$work/$name.h5"
  "$jamsim" run --dry-run ${PROBE_SECONDS:+--probe-seconds "$PROBE_SECONDS"} "$spec" -o "$out" > "$work/$name.plan" 2>/dev/null
  "$jamsim" run "$spec" -o "$out" --progress lines > "$work/$name.log" 2>&1 || { cat "$work/$name.log" >&2; exit 1; }
  /usr/bin/python3 - "$out" "$name" "$work/$name.plan" "$work/$name.log" <<'PY'
import re
import sys
from collections import defaultdict

import h5py

path, name, plan, log = sys.argv[1:5]
campaign_wall = float(re.search(r"finished in ([0-9.]+) s", open(log).read()).group(1))
estimated = {}  # replica id -> estimated seconds (the dry run's listing: id N phi rate seed samples cost est.s ...)
for line in open(plan):
    fields = line.split()
    if len(fields) >= 8 and re.fullmatch(r"\d+", fields[0]) and re.fullmatch(r"\d+", fields[1]):
        estimated[int(fields[0])] = float(fields[7])
with h5py.File(path, "r") as f:
    wall = f["replicas/wall_seconds"][...]
    sizes = f["replicas/N"][...].astype(int)
    model = f.attrs["model"] if "model" in f.attrs else "?"
besides = max(0.0, campaign_wall - float(wall.sum())) / len(wall)  # per replica, outside its own run
rows = defaultdict(lambda: [0, 0.0, 0.0])
for r, (n, w) in enumerate(zip(sizes, wall + besides)):
    for key in (n, "all"):
        rows[key][0] += 1
        rows[key][1] += estimated[r]
        rows[key][2] += w
for key in sorted(rows, key=lambda k: (k == "all", k if k != "all" else 0)):
    count, est, meas = rows[key]
    print(f"| {name} | {model} | {key} | {count} | {est:.3g} | {meas:.3g} | {est / meas:.2f} |")
PY
done
