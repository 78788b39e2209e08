# Sourced by the Slurm tests: skip unless root, start a local Slurm in $PWD/$1 (stopped on
# exit), and export SLURM_CONF, JAMSIM and work (the test's folder).
#   source local_slurm.sh FOLDER        (with jamsim and root set by the caller)
[[ $(id -u) -eq 0 ]] || { echo "skipped: a local Slurm needs root"; exit 77; }
work=$PWD/$1
rm -rf "$work"
mkdir -p "$work"
export SLURM_LOCAL_DIR=$work/slurm
"$root/tools/slurm-local.sh" start
trap '"$root/tools/slurm-local.sh" stop' EXIT
export SLURM_CONF=$SLURM_LOCAL_DIR/slurm.conf JAMSIM=$jamsim
