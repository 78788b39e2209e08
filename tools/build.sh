#!/usr/bin/env bash
# Configure and build jamsim with a CMake preset (default: release; JAMSIM_PRESET overrides).
#   tools/build.sh            -> build/release/jamsim
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then  # the header above, on stdout
  awk 'NR > 1 { if ($0 !~ /^#( |$)/) exit; sub(/^# ?/, ""); print }' "$0"
  exit 0
fi
[[ $# -eq 0 ]] || { echo "build.sh: argument '$1' is not allowed: it takes none (JAMSIM_PRESET picks the preset); --help says what it does" >&2; exit 2; }
cd "$(dirname "$0")/.."
preset=${JAMSIM_PRESET:-release}
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
