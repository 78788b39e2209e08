#!/usr/bin/env bash
# The test command: install what is missing, build, run the CTest suite.
#   tools/run-tests.sh            all tests except those labelled `slow` or `faults`
#   tools/run-tests.sh --all      everything, including `slow` and `faults`
#   tools/run-tests.sh -L physics extra arguments go to ctest
# JAMSIM_PRESET picks the CMake preset (default release; CI uses `ci`: warnings are errors).
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then  # the header above, on stdout
  awk 'NR > 1 { if ($0 !~ /^#( |$)/) exit; sub(/^# ?/, ""); print }' "$0"
  exit 0
fi
cd "$(dirname "$0")/.."
tools/install-deps.sh
preset=${JAMSIM_PRESET:-release}
JAMSIM_PRESET=$preset tools/build.sh
args=(-LE "slow|faults")
if [[ "${1:-}" == "--all" ]]; then
  args=()
  shift
fi
ctest --preset "$preset" "${args[@]}" "$@"
