#!/usr/bin/env bash
# jamsim status between checkpoints: a running replica's progress note is shown (a fraction
# above 0 while its last checkpoint is still at 0), an interrupted one says where it
# continues, and a finished run leaves no note behind.
# Usage: status_live.sh JAMSIM WORKDIR
set -u
jamsim=$1
dir=$2
rm -rf "$dir" && mkdir -p "$dir" && cd "$dir" || exit 1
cat > live.toml <<'TOML'
[campaign]
name = "live"
output = "live.h5"
[run]
transient = 0.2
strain = 40.0
sample_interval = 0.05
[sweep]
N = [4096]
phi = [0.84]
rate = [1e-3]
seeds = 1
TOML
"$jamsim" run live.toml > run.log 2>&1 &
pid=$!
seen=""
for _ in $(seq 1 120); do  # up to 60 s: a loaded machine starts the replica late
  sleep 0.5
  line=$("$jamsim" status live.h5 2>/dev/null | grep '^running replica 0:')
  if [[ $line =~ ^running\ replica\ 0:\ ([0-9.]+)%\ of\ its\ steps\ \([0-9]+\ s\ ago\),\ 0.0%\ at\ its\ last\ checkpoint$ ]] &&
     [[ ${BASH_REMATCH[1]} != 0.0 ]]; then
    seen=$line
    break
  fi
done
kill -TERM $pid
wait $pid
rc=$?
echo "seen: $seen"
[[ -n $seen ]] || { echo "FAIL: no progress between checkpoints in jamsim status"; cat run.log; exit 1; }
[[ $rc -eq 75 ]] || { echo "FAIL: exit $rc after SIGTERM, expected 75"; exit 1; }
"$jamsim" status live.h5 | tee status.txt
grep -q '^interrupted replica 0: .*at its last checkpoint.*where it continues$' status.txt ||
  { echo "FAIL: the interrupted replica's line"; exit 1; }
sed -i 's/strain = 40.0/strain = 0.4/' live.toml  # a shorter campaign in a new archive: finishes
rm -rf live.h5 live.h5.checkpoints
"$jamsim" run live.toml > /dev/null 2>&1 || { echo "FAIL: the short run"; exit 1; }
if ls live.h5.checkpoints/*.progress 2>/dev/null; then echo "FAIL: a progress note outlived its replica"; exit 1; fi
echo "PASS"
