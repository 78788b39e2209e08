#!/usr/bin/env bash
# usage: kill_loop.sh JAMSIM CAMPAIGN.toml WORKDIR PYTHON_DIR [KILLS]
# Runs the campaign undisturbed on 2 ranks; then runs it again and SIGKILLs every rank at a
# random moment, KILLS times in a row (default 12), resuming each time; checkpoints are saved
# at every checkpoint step (--checkpoint-every 0), so some kills land in the middle of a
# checkpoint write. The finished archive must equal the undisturbed one bitwise, and only
# the final checkpoints of finished replicas may be left behind. Prints the kills, the kills during a checkpoint write (a
# .tmp file present after the kill) and the resumes that continued from a checkpoint.
set -euo pipefail
jamsim=$1 spec=$2 work=$3 py=$4 kills=${5:-12}
mpirun=${MPIEXEC:-mpiexec}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$work"
rm -rf "$work"/ref.h5 "$work"/ref.h5.checkpoints "$work"/loop.h5 "$work"/loop.h5.checkpoints
timeout 300 "$mpirun" -n 2 "$jamsim" run "$spec" -o "$work/ref.h5" > "$work/ref.log"
RANDOM=7  # reproducible kill moments
during_write=0 from_checkpoint=0 done_kills=0
for k in $(seq "$kills"); do
  if [[ -d "$work/loop.h5.checkpoints" ]] && ls "$work/loop.h5.checkpoints"/replica_*.h5 >/dev/null 2>&1; then
    from_checkpoint=$((from_checkpoint + 1))
  fi
  touch "$work/attempt_start"
  setsid timeout 300 "$mpirun" -n 2 "$jamsim" run "$spec" -o "$work/loop.h5" --checkpoint-every 0 \
    > "$work/loop_$k.log" 2>&1 &
  leader=$!
  # The kill moment counts from the ranks' start, not mpiexec's (which took seconds on a
  # loaded machine: every kill then hit mpiexec before any checkpoint).
  started=0
  "$here/../wait_for_ranks.sh" "$leader" 2 "^$jamsim run $spec -o $work/loop.h5" || started=$?
  [[ $started -eq 1 ]] && { echo "FAIL: the ranks did not start"; exit 1; }
  sleep "0.$((3 + RANDOM % 7))"
  if ! kill -0 "$leader" 2>/dev/null; then wait "$leader" || true; break; fi  # finished already
  pkill -KILL -f -- "-o $work/loop.h5" || true
  wait "$leader" 2>/dev/null || true
  for _ in $(seq 50); do pgrep -f -- "-o $work/loop.h5" >/dev/null || break; sleep 0.1; done
  done_kills=$((done_kills + 1))
  # A .tmp written during this attempt and not renamed: the kill hit a checkpoint write.
  if [[ -n $(find "$work/loop.h5.checkpoints" -name '*.tmp' -newer "$work/attempt_start" 2>/dev/null) ]]; then
    during_write=$((during_write + 1))
  fi
  # The killed archive stays readable and its finished replicas valid; a kill before or during
  # its creation leaves none, or a half-made one with its creation marker (made anew next time).
  if ! "$jamsim" status "$work/loop.h5" > "$work/status_$k.txt" 2>&1; then
    grep -Eq "does not exist|being created, or a kill interrupted its creation" "$work/status_$k.txt" ||
      { cat "$work/status_$k.txt"; echo "FAIL: the killed archive cannot be read"; exit 1; }
  fi
done
timeout 300 "$mpirun" -n 2 "$jamsim" run "$spec" -o "$work/loop.h5" > "$work/final.log"
/usr/bin/python3 "$py/compare_archives.py" "$work/ref.h5" "$work/loop.h5"
/usr/bin/python3 "$py/check_checkpoints_final.py" "$work/loop.h5"
echo "kills: $done_kills, during a checkpoint write: $during_write, resumes from a checkpoint: $from_checkpoint"
[[ $done_kills -ge 10 ]] || { echo "FAIL: only $done_kills kills before the campaign finished"; exit 1; }
[[ $from_checkpoint -ge 1 ]] || { echo "FAIL: no resume continued from a checkpoint"; exit 1; }
