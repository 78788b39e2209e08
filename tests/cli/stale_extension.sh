#!/usr/bin/env bash
# usage: stale_extension.sh JAMSIM (in a scratch folder)
# What an extension killed before its rename leaves beside the archive (ARCHIVE.extending and
# its creation marker) is removed, with a note, by the next run of the archive, extending or
# not; the archive keeps its replicas, and the extension then runs.
set -euo pipefail
jamsim=$1
rm -rf stale_work && mkdir stale_work && cd stale_work
fail() { echo "FAIL: $*"; exit 1; }
campaign() {  # NAME STRAIN
  printf '[campaign]\nname = "stale"\noutput = "s.h5"\n[run]\nstrain = %s\nsample_interval = 0.01\n[sweep]\nN = [16]\nphi = [0.84]\nrate = [1e-2]\nseeds = 1\n' \
    "$2" > "$1.toml"
}
campaign short 0.05
campaign long 0.1
"$jamsim" run short.toml > first.txt 2>&1 || { cat first.txt; fail "the first run"; }
head -c 4096 /dev/urandom > s.h5.extending  # as a kill leaves them: half-written
echo "jamsim: the archive beside this file is being created" > s.h5.extending.creating
"$jamsim" run short.toml > again.txt 2>&1 || { cat again.txt; fail "the run after the killed extension"; }
grep -q "removed 's.h5.extending', left by an extension that a kill interrupted before it replaced 's.h5' (which is whole)" again.txt ||
  { cat again.txt; fail "no note of the removal"; }
[[ ! -e s.h5.extending && ! -e s.h5.extending.creating ]] || fail "left: $(ls)"
grep -q "^0 replicas ran in this run, 1 finished before were kept" again.txt || { cat again.txt; fail "the archive was not kept"; }
touch s.h5.extending
"$jamsim" run long.toml > long.txt 2>&1 || { cat long.txt; fail "the extension"; }
grep -q "removed 's.h5.extending'" long.txt || { cat long.txt; fail "no note before the extension"; }
"$jamsim" status s.h5 | grep -q "1/1 done" || fail "the extension did not finish"
[[ ! -e s.h5.extending ]] || fail "the extension left s.h5.extending"
echo ok
