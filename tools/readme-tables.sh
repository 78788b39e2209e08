#!/usr/bin/env bash
# The parameter table of campaigns/README.md ("Parameters") is printed by
# `jamsim parameters --markdown` (from the parameter table in the code). This script
# rewrites the block between the markers:
#   tools/readme-tables.sh [JAMSIM]            update campaigns/README.md
#   tools/readme-tables.sh --check [JAMSIM]    exit 1 (with a diff) if campaigns/README.md is stale
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then  # the header above, on stdout
  awk 'NR > 1 { if ($0 !~ /^#( |$)/) exit; sub(/^# ?/, ""); print }' "$0"
  exit 0
fi
cd "$(dirname "$0")/.."
check=0
if [[ "${1:-}" == "--check" ]]; then check=1; shift; fi
jamsim=${1:-build/release/jamsim}
doc=campaigns/README.md
table=$("$jamsim" parameters --markdown)
updated=$(/usr/bin/python3 - "$doc" "$table" <<'PY'
import sys
doc, table = sys.argv[1], sys.argv[2]
text = open(doc).read()
begin, end = "<!-- parameters:begin -->\n", "<!-- parameters:end -->"
i, j = text.index(begin) + len(begin), text.index(end)
sys.stdout.write(text[:i] + table + "\n" + text[j:])
PY
)
if [[ $check -eq 1 ]]; then
  if ! diff <(cat "$doc") <(printf '%s\n' "$updated"); then
    echo "$doc's parameter table is stale: run tools/readme-tables.sh" >&2
    exit 1
  fi
  echo "$doc parameter table current"
else
  printf '%s\n' "$updated" > "$doc"
fi
