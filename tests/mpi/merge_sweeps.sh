#!/usr/bin/env bash
# usage: merge_sweeps.sh JAMSIM CAMPAIGNS_DIR WORKDIR PYTHON_DIR
# jamsim merge of campaigns that differ only in their sweeps: seeds 1, 2 and seeds 3, 2 merged
# equal the campaign with seeds 1..3 (bitwise, replicas matched by parameters; seed 2 is in
# both and the same); the merged archive is a campaign that status and a later run accept.
# Refused, writing nothing: another potential (naming the key), and a replica in both inputs
# whose data differ (naming the replica).
set -euo pipefail
jamsim=$1 campaigns=$2 work=$3 py=$4
mpirun=${MPIEXEC:-mpiexec}
mkdir -p "$work"
cd "$work"
rm -rf merge-*.h5* merged.h5* bad*.h5* tampered.h5
fail() { echo "FAIL: $*"; exit 1; }
for c in a b all hertzian; do
  timeout 300 "$mpirun" -n 2 "$jamsim" run "$campaigns/merge_seeds_$c.toml" > "run_$c.log" 2>&1 || { cat "run_$c.log"; fail "run $c"; }
done
"$jamsim" merge -o merged.h5 merge-a.h5 merge-b.h5 | tee merge.log
grep -q "^merged 6 replicas from 2 archives into merged.h5 (a campaign of 6 replicas: the union of their sweeps)" merge.log || fail "merge line"
grep -q "6/6 done" merge.log || fail "merged status"
/usr/bin/python3 "$py/compare_replica_sets.py" merge-all.h5 merged.h5
# The merged campaign runs on: the campaign with all seeds finds every replica in it (in
# another order) and runs none.
timeout 300 "$mpirun" -n 2 "$jamsim" run "$campaigns/merge_seeds_all.toml" -o merged.h5 > rerun.log 2>&1 || { cat rerun.log; fail "run on the merged archive"; }
grep -q "^0 replicas ran in this run, 6 finished before were kept" rerun.log || { cat rerun.log; fail "the merged archive was not taken as the campaign"; }
/usr/bin/python3 "$py/compare_archives.py" merge-all.h5 merged.h5

# Another potential: refused naming the key.
if "$jamsim" merge -o bad.h5 merge-a.h5 merge-hertzian.h5 2> bad.txt; then fail "merged another potential"; fi
cat bad.txt
grep -q "'merge-hertzian.h5' belongs to a different campaign than 'merge-a.h5': \[potential\] alpha: 'merge-a.h5' 2, 'merge-hertzian.h5' 2.5" bad.txt || fail "message"
[[ ! -e bad.h5 ]] || fail "bad.h5 written"
# The same replica with other data in two inputs: refused naming it.
cp merge-b.h5 tampered.h5
/usr/bin/python3 - <<'PY'
import h5py
with h5py.File("tampered.h5", "r+") as f:
    r = f["replicas"]
    k = [i for i in range(len(r["seed"])) if r["seed"][i] == 2 and r["phi"][i] == 0.84][0]
    name = sorted(f["timeseries"])[0]
    f["timeseries"][name][k, 1] += 1e-9
PY
if "$jamsim" merge -o bad2.h5 merge-a.h5 tampered.h5 2> bad2.txt; then fail "merged a replica that differs"; fi
cat bad2.txt
grep -q "the replica N = 64, phi = 0.84, rate = 0.003, seed = 2 is in 'merge-a.h5' (replica 1) and 'tampered.h5' (replica 1) with different data (/timeseries/" bad2.txt || fail "message"
[[ ! -e bad2.h5 ]] || fail "bad2.h5 written"
echo "ok: campaigns of other sweeps merged, bitwise equal to the whole campaign"
