#!/usr/bin/env bash
# usage: wait_for_ranks.sh LEADER_PID COUNT PATTERN [SECONDS]
# Waits until COUNT processes whose command line matches PATTERN (pgrep -f; anchor it, as in
# "^/path/jamsim run CAMPAIGN -o OUT", so that it matches the ranks and not mpiexec or a
# shell) have jamsim's stop-signal handler installed (SIGUSR1 caught, /proc/PID/status).
#
# Why: mpiexec forwards a signal only to the ranks it has already started; one sent before
# is lost, and the run then finishes with status 0. Starting the ranks took more than 2 s on
# a loaded CI machine, so a test that signals "2 s after mpiexec started" must wait for this.
# Exit 0 once they are there; 3 when LEADER_PID ended first (the run finished); 1 after
# SECONDS (default 120) without them.
set -uo pipefail
leader=$1 count=$2 pattern=$3 seconds=${4:-120}
readonly usr1_bit=$((1 << (10 - 1)))  # SIGUSR1 = 10 in the SigCgt mask
deadline=$((SECONDS + seconds))
while ((SECONDS < deadline)); do
  ready=0
  for pid in $(pgrep -f -- "$pattern"); do
    mask=$(awk '/^SigCgt:/ { print $2 }' "/proc/$pid/status" 2>/dev/null) || continue
    [[ -n $mask ]] && (((0x$mask & usr1_bit) != 0)) && ready=$((ready + 1))
  done
  ((ready >= count)) && exit 0
  kill -0 "$leader" 2>/dev/null || exit 3
  sleep 0.02
done
echo "wait_for_ranks.sh: $count processes matching '$pattern' did not start within $seconds s" >&2
exit 1
