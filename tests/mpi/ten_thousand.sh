#!/usr/bin/env bash
# usage: ten_thousand.sh JAMSIM CAMPAIGN.toml WORKDIR PYTHON_DIR
# 10^4 tiny replicas end to end: on 2 ranks; then on 64 oversubscribed ranks, interrupted
# (SIGUSR1) in the middle and finished on 2 ranks; the two archives must be bitwise equal.
set -euo pipefail
jamsim=$1 spec=$2 work=$3 py=$4
mpirun=${MPIEXEC:-mpiexec}
mkdir -p "$work"
cd "$work"
rm -rf two.h5* many.h5*
start=$(date +%s)
timeout 600 "$mpirun" -n 2 "$jamsim" run "$spec" -o two.h5 --progress lines > two.log
"$jamsim" status two.h5 | grep -q "10000/10000 done"
mid=$(date +%s)
"$mpirun" -n 64 "$jamsim" run "$spec" -o many.h5 --progress lines --progress-interval 1 > many.log 2>&1 &
leader=$!
# Interrupt once some replicas are done (the first progress line with a done count > 0).
for _ in $(seq 600); do grep -qE "\] [1-9][0-9]*/10000 done" many.log && break; sleep 0.1; done
kill -USR1 "$leader"
rc=0; wait "$leader" || rc=$?
[[ $rc -eq 75 ]] || { echo "FAIL: the interrupted 64-rank run exited $rc, not 75"; tail -5 many.log; exit 1; }
"$jamsim" status many.h5 | head -1
timeout 600 "$mpirun" -n 2 "$jamsim" run "$spec" -o many.h5 > resume.log
grep -q "resuming" resume.log
/usr/bin/python3 "$py/compare_archives.py" two.h5 many.h5
echo "10^4 replicas: 2 ranks $((mid - start)) s; 64 ranks interrupted and finished on 2 ranks $(( $(date +%s) - mid )) s; bitwise equal"
