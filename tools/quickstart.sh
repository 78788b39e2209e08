#!/usr/bin/env bash
# The main job: install what is missing, build, run the quick-start campaign
# (campaigns/quickstart.toml: RD0 across jamming, 56 replicas) on 2 MPI ranks into
# out/quickstart.h5, and draw its figures into out/quickstart/.
#   RANKS=4 tools/quickstart.sh     more ranks
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then  # the header above, on stdout
  awk 'NR > 1 { if ($0 !~ /^#( |$)/) exit; sub(/^# ?/, ""); print }' "$0"
  exit 0
fi
[[ $# -eq 0 ]] || { echo "quickstart.sh: argument '$1' is not allowed: it takes none (RANKS=4 for more ranks); --help says what it does" >&2; exit 2; }
cd "$(dirname "$0")/.."
tools/install-deps.sh
tools/build.sh
if [[ $(id -u) -eq 0 ]]; then  # Open MPI refuses root unless told
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
export OMPI_MCA_rmaps_base_oversubscribe=1  # RANKS may exceed the cores
mkdir -p out
# An archive of an older jamsim (or an edited quickstart.toml) cannot be resumed: keep it aside.
if [[ -e out/quickstart.h5 ]] &&
   ! build/${JAMSIM_PRESET:-release}/jamsim run --dry-run --no-calibrate campaigns/quickstart.toml \
       -o out/quickstart.h5 > /dev/null 2>&1; then
  old=out/quickstart.h5.$(date +%Y%m%dT%H%M%S)
  echo "quickstart: out/quickstart.h5 holds another campaign or jamsim version; moved to $old"
  mv out/quickstart.h5 "$old"
  if [[ -d out/quickstart.h5.checkpoints ]]; then mv out/quickstart.h5.checkpoints "$old.checkpoints"; fi
fi
if [[ ! -e out/quickstart.h5 && -d out/quickstart.h5.checkpoints ]]; then
  # the archive was removed by hand: its (final) checkpoints would be refused without it
  old=out/quickstart.h5.checkpoints.$(date +%Y%m%dT%H%M%S)
  echo "quickstart: out/quickstart.h5 is gone; its checkpoint folder moved to $old"
  mv out/quickstart.h5.checkpoints "$old"
fi
mpirun -n "${RANKS:-2}" build/${JAMSIM_PRESET:-release}/jamsim run campaigns/quickstart.toml \
    -o out/quickstart.h5
build/${JAMSIM_PRESET:-release}/jamsim status out/quickstart.h5
/usr/bin/python3 tools/plot_campaign.py out/quickstart.h5 out/quickstart
echo "archive: out/quickstart.h5   figures: out/quickstart/"
