#!/usr/bin/env bash
# usage: lend_cores.sh JAMSIM WORKDIR COMPARE_PY DATA_DIR
# Ranks without work park and lend their cores (campaign/core_lending.hpp):
#  1. one replica on 2 ranks: the rank without work waits without spinning (its CPU time is
#     well under its wall time; a rank spinning in an MPI wait would use all of it);
#     while it runs, `jamsim status` says the run is live (the archive's lock);
#  2. a rate ladder of N = 8192 on 2 unbound ranks x 1 thread: while one rank runs the ladder
#     the other lends its core (the log says so), and the archive holds the same bits as on
#     1 rank x 1 thread, and /replicas/threads records the lent core (time-weighted).
set -uo pipefail
jamsim=$1 work=$2 compare=$3 data=$4
mpirun=${MPIEXEC:-mpiexec}
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1

# 1. Each rank's CPU seconds (user + system) over its wall seconds.
cat > timed.sh <<'SH'
#!/usr/bin/env bash
start=$(date +%s.%N); "$@" > "rank$OMPI_COMM_WORLD_RANK.log" 2>&1; rc=$?; end=$(date +%s.%N)
times > "times$OMPI_COMM_WORLD_RANK.txt"  # (in this shell: its children's times on the last line)
read -r cu cs < <(tail -1 "times$OMPI_COMM_WORLD_RANK.txt" | sed 's/\([0-9]*\)m\([0-9.]*\)s/\1 \2/g' | awk '{print $1 * 60 + $2, $3 * 60 + $4}')
echo "$OMPI_COMM_WORLD_RANK $cu $cs $start $end" > "cpu$OMPI_COMM_WORLD_RANK.txt"
exit $rc
SH
chmod +x timed.sh
timeout 300 "$mpirun" -n 2 ./timed.sh "$jamsim" run "$data/park.toml" -o park.h5 --threads 1 || { cat rank*.log; exit 1; }
cat cpu0.txt cpu1.txt | awk '
  { ratio = ($2 + $3) / ($5 - $4); printf "rank %d: %.2f CPU s in %.2f s\n", $1, $2 + $3, $5 - $4
    if (min == "" || ratio < min) min = ratio }
  END { if (min >= 0.5) { print "FAIL: no rank waited without spinning (least CPU / wall " min ")"; exit 1 }
        print "ok: the rank without work parked (CPU / wall " min ")" }' || exit 1

# 1b. While a run holds the archive, `jamsim status` says it is running now (the park
# campaign runs for about a second and a half; status is asked until it ends).
rm -rf park.h5 park.h5.checkpoints
"$mpirun" -n 2 "$jamsim" run "$data/park.toml" -o park.h5 --threads 1 > park_live.log 2>&1 &
pid=$!
seen=0
while kill -0 "$pid" 2> /dev/null; do
  "$jamsim" status park.h5 2> /dev/null | grep -q "running now: a live run holds the archive's lock" && seen=1
  sleep 0.05
done
wait "$pid" || { cat park_live.log; exit 1; }
[[ $seen -eq 1 ]] || { echo "FAIL: status never said 'running now' during the run"; exit 1; }
"$jamsim" status park.h5 | grep -q "complete: every replica is finished" || { echo "FAIL: status after the run"; exit 1; }
echo "ok: status told the live run"

# 2. Lent cores, the same bits.
timeout 300 "$mpirun" -n 1 "$jamsim" run "$data/lend_ladder.toml" -o ref.h5 --threads 1 > ref.log 2>&1 || { cat ref.log; exit 1; }
timeout 300 "$mpirun" -n 2 --bind-to none "$jamsim" run "$data/lend_ladder.toml" -o lend.h5 --threads 1 > lend.log 2>&1 ||
  { cat lend.log; exit 1; }
grep -q "now on 2 threads, 1 lent by idle ranks of its node" lend.log || { cat lend.log; echo "FAIL: no core lent"; exit 1; }
/usr/bin/python3 "$compare" ref.h5 lend.h5 || exit 1
# The threads each replica ran on, weighted by time: one on 1 rank x 1 thread; between 1 and 2
# with a lent core, and above 1 for the replicas that had it.
/usr/bin/python3 - ref.h5 lend.h5 <<'PY'
import sys
import h5py
ref, lend = (h5py.File(p, "r")["replicas/threads"][...] for p in sys.argv[1:3])
assert (ref == 1).all(), f"1 rank x 1 thread: /replicas/threads = {ref}"
assert ((lend >= 1) & (lend <= 2)).all() and lend.max() > 1, f"with a lent core: /replicas/threads = {lend}"
print(f"ok: threads {ref.tolist()} on 1 x 1, {[round(t, 3) for t in lend]} with a lent core")
PY
