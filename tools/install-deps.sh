#!/usr/bin/env bash
# Install the Debian packages jamsim needs, and only those that are missing.
#
#   tools/install-deps.sh            build + run + test dependencies (lammps and MDAnalysis
#                                    read jamsim export's files back in the tests)
#   tools/install-deps.sh --bench    the same (lammps is also the benchmarks' reference)
#
# Idempotent: when everything is present it makes no apt call at all.
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then  # the header above, on stdout
  awk 'NR > 1 { if ($0 !~ /^#( |$)/) exit; sub(/^# ?/, ""); print }' "$0"
  exit 0
fi

packages=(
  g++ cmake make pkg-config git clang-format python3-setuptools
  libopenmpi-dev openmpi-bin
  libhdf5-openmpi-dev hdf5-tools
  libeigen3-dev petsc-dev libsuitesparse-dev
  libcli11-dev libtomlplusplus-dev
  libgtest-dev libbenchmark-dev
  python3-numpy python3-h5py python3-matplotlib python3-scipy python3-pandas python3-pytest
  python3-xarray python3-mdanalysis lammps tcl
)
if [[ "${1:-}" == "--bench" ]]; then
  :  # lammps is in the list above
elif [[ $# -gt 0 ]]; then
  echo "install-deps.sh: unknown argument '$1' (allowed: --bench)" >&2
  exit 2
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
