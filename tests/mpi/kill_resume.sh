#!/usr/bin/env bash
# usage: kill_resume.sh JAMSIM CAMPAIGN.toml WORKDIR PYTHON_DIR
# Runs the campaign uninterrupted on 2 ranks; runs it again, SIGKILLs every rank once some
# replicas are done and others are running, checks the killed archive is readable and shows
# the finished replicas, resumes it, and compares with the uninterrupted archive bitwise.
set -euo pipefail
jamsim=$1 spec=$2 work=$3 py=$4
mpirun=${MPIEXEC:-mpiexec}
mkdir -p "$work"
rm -rf "$work/ref.h5" "$work/ref.h5.checkpoints" "$work/killed.h5" "$work/killed.h5.checkpoints"
timeout 300 "$mpirun" -n 2 "$jamsim" run "$spec" -o "$work/ref.h5" > "$work/ref.log"

setsid timeout 300 "$mpirun" -n 2 "$jamsim" run "$spec" -o "$work/killed.h5" > "$work/killed.log" 2>&1 &
leader=$!
done_count=0
for _ in $(seq 600); do
  sleep 0.05
  if [[ -f "$work/killed.h5" ]]; then
    done_count=$(/usr/bin/python3 -c "
import h5py,sys
try:
    f=h5py.File('$work/killed.h5','r',locking=False); print(int((f['replicas/status'][...]==2).sum()))
except Exception: print(0)" 2>/dev/null || echo 0)
    [[ $done_count -ge 3 ]] && break
  fi
done
pkill -KILL -f -- "-o $work/killed.h5" || true
kill -KILL -- -"$leader" 2>/dev/null || true
wait "$leader" 2>/dev/null || true
echo "killed after $done_count replicas were done"
"$jamsim" status "$work/killed.h5" | tee "$work/status.txt"
total=$(/usr/bin/python3 -c "import h5py; print(len(h5py.File('$work/killed.h5','r')['replicas/status']))")
read -r killed_done <<<"$(grep -oE '[0-9]+/[0-9]+ done' "$work/status.txt" | head -1 | cut -d/ -f1)"
if [[ $killed_done -lt 3 || $killed_done -ge $total ]]; then
  echo "FAIL: the kill did not land mid-campaign ($killed_done of $total done)"; exit 1
fi
timeout 300 "$mpirun" -n 2 "$jamsim" run "$spec" -o "$work/killed.h5" | tee "$work/resume.log"
grep -q "resuming" "$work/resume.log"
/usr/bin/python3 "$py/compare_archives.py" "$work/ref.h5" "$work/killed.h5"
