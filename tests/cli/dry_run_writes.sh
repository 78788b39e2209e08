#!/usr/bin/env bash
# usage: dry_run_writes.sh JAMSIM SPEC — a calibrated dry run prices each replica's archive
# writes, measured through the archive's code on a scratch file beside the output: the total
# grows by at least that much per replica over the kernel-only estimate, the scratch file is
# gone after, and without probes (--probe-seconds 0) they are said to be unmeasured.
set -euo pipefail
jamsim=$1 spec=$2
dir=$(mktemp -d "$PWD/dry-writes.XXXXXX")
trap 'rm -rf "$dir"' EXIT
out=$("$jamsim" run --dry-run "$spec" -o "$dir/a.h5" --probe-seconds 2)
ms=$(grep -oE "each replica's archive writes [0-9.e+-]+ ms \(measured beside the output\)" <<<"$out" |
  grep -oE '[0-9.e+-]+ ms' | cut -d' ' -f1) || { echo "FAIL: no archive writes in: $(grep '^total' <<<"$out")"; exit 1; }
replicas=$(grep -oE '[0-9]+ replicas' <<<"$out" | head -1 | cut -d' ' -f1)
total=$(grep -oE '^total: [^,]*, [0-9.e+-]+ core-seconds' <<<"$out" | grep -oE '[0-9.e+-]+ core-seconds' | cut -d' ' -f1)
left=$(find "$dir" -mindepth 1 | wc -l)
[[ $left -eq 0 ]] || { echo "FAIL: the dry run left $(ls -A "$dir") beside the output"; exit 1; }
/usr/bin/python3 - "$ms" "$replicas" "$total" <<'PY'
import sys
ms, replicas, total = float(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
assert ms > 0, f"archive writes {ms} ms"
# Both printed to 3 digits: half a unit in the third digit each (the kernel's seconds come on top).
assert total >= 0.99 * replicas * ms / 1e3, f"total {total} s below {replicas} replicas x {ms} ms of writes"
print(f"ok: {ms} ms of writes per replica, {replicas} replicas, {total} core-seconds in all")
PY
out=$("$jamsim" run --dry-run "$spec" -o "$dir/a.h5" --probe-seconds 0)
grep -q "the archive's writes per replica not measured" <<<"$out" || { echo "FAIL: no word of unmeasured writes"; exit 1; }
[[ $(find "$dir" -mindepth 1 | wc -l) -eq 0 ]] || { echo "FAIL: --probe-seconds 0 wrote beside the output"; exit 1; }
echo "ok: unmeasured without probes"
