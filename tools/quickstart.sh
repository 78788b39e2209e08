#!/usr/bin/env bash
# The main job: install what is missing, build, shear one replica (RD0, N = 1024, φ = 0.84,
# γ̇ = 1e-4, strain 2) into out/quickstart.h5, print ⟨p⟩ and ⟨σ⟩, and draw out/quickstart.png.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
tools/build.sh
mkdir -p out
build/${JAMSIM_PRESET:-release}/jamsim replica --model RD0 --N 1024 --phi 0.84 --rate 1e-4 \
    --strain 2 --transient 0.5 --seed 1 -o out/quickstart.h5
/usr/bin/python3 tools/plot_replica.py out/quickstart.h5 out/quickstart.png
