#!/usr/bin/env bash
# usage: probe_order.sh JAMSIM WORKDIR
# The dry run's estimate of a campaign does not depend on the order of its rate list. A
# group's (model, N, phi) first replica used to be its probe: with the fast rate first, a
# replica of a few steps ran whole, its set-up and samples counted as steps, and the estimate
# came out 8 times the measured cost, where the slow rate first gave 0.9 of it. The two
# estimates (each a timed probe, so with a machine's noise) must agree within a factor 2.
set -euo pipefail
jamsim=$1 work=$2
mkdir -p "$work" && cd "$work"
estimate() {  # RATES: the dry run's core-seconds for the campaign with that rate list
  printf '[campaign]\nname = "order"\noutput = "none.h5"\n[run]\ntransient = 0.05\nstrain = 0.5\nsample_interval = 0.02\n[sweep]\nN = [128]\nphi = [0.84]\nrate = [%s]\nseeds = 2\n' "$1" > order.toml
  "$jamsim" run order.toml --dry-run | awk '/^total:/ { for (k = 1; k < NF; ++k) if ($(k + 1) == "core-seconds") print $k }'
}
fast_first=$(estimate "0.1, 1e-4")
slow_first=$(estimate "1e-4, 0.1")
[[ ! -e none.h5 ]] || { echo "FAIL: the dry run wrote an archive"; exit 1; }
awk -v a="$fast_first" -v b="$slow_first" 'BEGIN {
  if (!(a > 0 && b > 0)) { print "FAIL: no estimate (" a ", " b ")"; exit 1 }
  r = a > b ? a / b : b / a
  printf "fast rate first: %g core-seconds, slow rate first: %g (ratio %.2f)\n", a, b, r
  if (r > 2) { print "FAIL: the estimate depends on the order of the rates"; exit 1 } }'
