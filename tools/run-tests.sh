#!/usr/bin/env bash
# The test command: install what is missing, build, run the CTest suite.
#   tools/run-tests.sh            the quick set: every test not labelled `heavy`, `slow`,
#                                 `faults` or `slurm` (unit, physics, 2-rank campaigns, the
#                                 command line's refusals, the Python tools; about 3
#                                 minutes on 2 cores after the build, tests/README.md)
#   tools/run-tests.sh --all      everything, including `heavy`, `slow`, `faults` and `slurm`
#   tools/run-tests.sh --rest     only what the quick set leaves out (CI runs it after the quick set)
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
left_out="heavy|slow|faults|slurm"  # the labels outside the quick set
args=(-LE "$left_out")
case "${1:-}" in
  --all) args=(); shift ;;
  --rest) args=(-L "$left_out"); shift ;;
esac
ctest --preset "$preset" "${args[@]}" "$@"
