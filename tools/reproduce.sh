#!/usr/bin/env bash
# Runs the reproduction campaigns of campaigns/papers/ at one size and writes each one's report.
#   tools/reproduce.sh [laptop|published] [NAME ...]     (default: laptop, every campaign)
#   RANKS=4 tools/reproduce.sh laptop collapse_rd0       more ranks, one campaign
# Archives go to out/papers/NAME.SIZE.h5 and reports to out/papers/NAME.SIZE.report/; a run
# that stopped resumes where it stopped. The published sizes take hundreds of core-hours: run
# them on a cluster (slurm/submit_campaign.sh) after `jamsim run --dry-run` shows their cost.
# RD0 against CD0 (rd0_cd0) is reported against the collapse_rd0 archive of the same size,
# the bidisperse crystallisation campaign against the monodisperse one. collapse_sizes (laptop
# only, about an hour) fits the same window at N = 256, 1024 and 4096: its report's section
# "Fitted values by system size" says whether the values move toward the published ones.
set -euo pipefail
cd "$(dirname "$0")/.."
usage() { sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; }
size=${1:-laptop}
case "$size" in
  -h|--help) usage; exit 0 ;;
  laptop|published) shift || true ;;
  *) echo "reproduce.sh: size '$size' is not allowed: laptop or published" >&2; exit 2 ;;
esac
names=("$@")
if [[ ${#names[@]} -eq 0 ]]; then  # every campaign of this size (collapse_sizes: laptop only)
  for name in collapse_rd0 rd0_cd0 bagnold_cdn jamming_fss sheared_fss crystallisation_mono crystallisation_bi \
    collapse_sizes; do
    [[ -f campaigns/papers/$name.$size.toml ]] && names+=("$name")
  done
fi
jamsim=build/${JAMSIM_PRESET:-release}/jamsim
[[ -x $jamsim ]] || { echo "reproduce.sh: $jamsim not built (run tools/build.sh)" >&2; exit 2; }
for name in "${names[@]}"; do
  [[ -f campaigns/papers/$name.$size.toml ]] ||
    { echo "reproduce.sh: no campaign campaigns/papers/$name.$size.toml" >&2; exit 2; }
done
# The collapse is fitted in the critical region (phi_J ~ 0.843 for this mixture; at N = 1024
# and rates >= 1e-5 the points far from it are outside the scaling region).
report_options() {
  case $1 in
    collapse_rd0|rd0_cd0|collapse_sizes) echo "--phi-min 0.83 --phi-max 0.86 --rate-max 2e-4 --degree 4" ;;
  esac
}
if [[ $(id -u) -eq 0 ]]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
export OMPI_MCA_rmaps_base_oversubscribe=1
mkdir -p out/papers
for name in "${names[@]}"; do
  spec=campaigns/papers/$name.$size.toml archive=out/papers/$name.$size.h5
  echo "== $name ($size)"
  mpirun -n "${RANKS:-2}" "$jamsim" run "$spec" -o "$archive"
  inputs=("$archive")
  if [[ $name == rd0_cd0 && -e out/papers/collapse_rd0.$size.h5 ]]; then
    inputs=(out/papers/collapse_rd0.$size.h5 "$archive")
  fi
  if [[ $name == crystallisation_bi && -e out/papers/crystallisation_mono.$size.h5 ]]; then
    inputs=(out/papers/crystallisation_mono.$size.h5 "$archive")
  fi
  # shellcheck disable=SC2046  # the options are words
  /usr/bin/python3 tools/jamsim_report.py $(report_options "$name") "${inputs[@]}" "out/papers/$name.$size.report"
done
