#!/usr/bin/env bash
# Configure and build jamsim with a CMake preset (default: release; JAMSIM_PRESET overrides).
#   tools/build.sh            -> build/release/jamsim
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${JAMSIM_PRESET:-release}
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
