#!/usr/bin/env bash
# usage: dry_run_check.sh JAMSIM SPEC  — the dry run lists every replica with its cost and a
# total, and creates no archive.
set -euo pipefail
out=dry-run-out.h5
rm -rf "$out" "$out.checkpoints"
listing=$("$1" run --dry-run "$2" -o "$out")
echo "$listing"
[[ ! -e $out ]] || { echo "FAIL: dry run wrote $out"; exit 1; }
rows=$(grep -cE '^ +[0-9]+ +[0-9]+ ' <<<"$listing")
expected=$(grep -oE '[0-9]+ replicas' <<<"$listing" | head -1 | grep -oE '[0-9]+')
[[ $rows -eq $expected && $rows -gt 0 ]] || { echo "FAIL: $rows rows for $expected replicas"; exit 1; }
grep -q '^total: ' <<<"$listing"
echo "ok: $rows replicas listed"
