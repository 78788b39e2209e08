#!/usr/bin/env bash
# Thread scaling of one replica on a node of 16 or more cores:
#   1. the bits: every dynamical model on 1 thread and on 8 and 16 (tests/cli/threads_bitwise.sh);
#   2. the kernel benchmarks on 1, 2, 4, 8 and 16 threads: RD0 and CG (jamsim_bench) and CD0
#      (jamsim_bench_cd0), with the serial-fraction counters.
# usage: tests/bench/scaling.sh BUILD_DIR OUT_DIR          (the binaries of a build, e.g. build/release)
#        tests/bench/scaling.sh --bundle DIR OUT_DIR       (binaries packed by a bundle's run.sh)
# Writes OUT_DIR/bitwise.log and OUT_DIR/{rd0,cg,cd0_16384,cd0_65536}.json and prints a table of particle-steps per second,
# speed-up against 1 thread and serial fraction. SCALING_BITWISE_THREADS ("8 16") and
# SCALING_THREADS ("1|2|4|8|16") choose the thread counts, SCALING_KERNELS the kernels (below).
# Threads are placed one per core, close together.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
if [[ ${1:-} == --bundle ]]; then
  bundle=$(cd "$2" && pwd); out=$3
  export OMPI_MCA_ess_singleton_isolated=1  # a singleton without orted (a bundle packs none)
  run() { bash "$bundle/run.sh" "$@"; }
else
  build=$(cd "${1:?usage: scaling.sh BUILD_DIR OUT_DIR}" && pwd); out=${2:?usage: scaling.sh BUILD_DIR OUT_DIR}
  run() { local p=$1; shift; case $p in jamsim) "$build/jamsim" "$@" ;; *) "$build/tests/bench/$p" "$@" ;; esac; }
fi
mkdir -p "$out"; out=$(cd "$out" && pwd)
export OMP_PROC_BIND=close OMP_PLACES=cores
cores=$(nproc)
echo "cores: $cores; $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
(( cores >= 16 )) || echo "note: fewer than 16 cores; the rows above $cores threads are oversubscribed"

# 1. The bits on 8 and 16 threads against 1 (the script wants a program path: wrap `run`).
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
wrapper=$work/jamsim
declare -f run > "$wrapper.fn"
{ echo '#!/usr/bin/env bash'; [[ -n ${bundle:-} ]] && echo "bundle='$bundle'"; [[ -n ${build:-} ]] && echo "build='$build'"
  cat "$wrapper.fn"; echo 'run jamsim "$@"'; } > "$wrapper"
rm -f "$wrapper.fn"; chmod +x "$wrapper"
JAMSIM_BITWISE_THREADS=${SCALING_BITWISE_THREADS:-8 16} "$here/../cli/threads_bitwise.sh" "$wrapper" "$work/bitwise" dynamics | tee "$out/bitwise.log"

# 2. The kernels (SCALING_THREADS, e.g. "1|2", keeps only those rows).
only=${SCALING_THREADS:-1|2|4|8|16}
# One JSON file per kernel and size, so that a run cut short keeps what it finished.
bench() {  # bench NAME PROGRAM FILTER
  run "$2" --benchmark_filter="$3/.*threads:($only)/" \
    --benchmark_out="$out/$1.json" --benchmark_out_format=json > "$work/$1.txt"
}
# SCALING_KERNELS ("rd0 cg cd0_16384 cd0_65536") chooses the kernels; JAMSIM_BENCH_CD0_STATES
# (a folder of CD0's sheared start states, made by an earlier run) spares CD0's shearing.
kernels=" ${SCALING_KERNELS:-rd0 cg cd0_16384 cd0_65536} "
[[ $kernels == *" rd0 "* ]] && bench rd0 jamsim_bench 'BM_Rd0Threads'
[[ $kernels == *" cg "* ]] && bench cg jamsim_bench 'BM_CgThreads'
[[ $kernels == *" cd0_16384 "* ]] && bench cd0_16384 jamsim_bench_cd0 'BM_Cd0Threads/N:16384'
[[ $kernels == *" cd0_65536 "* ]] && bench cd0_65536 jamsim_bench_cd0 'BM_Cd0Threads/N:65536'
/usr/bin/env python3 "$here/scaling_table.py" "$out"/*.json
