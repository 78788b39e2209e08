#!/usr/bin/env bash
# usage: fault_case.sh JAMSIM CASE RANKS WORKDIR
# One fault-injection case on RANKS MPI ranks, in WORKDIR (made afresh). Every jamsim run
# goes through a watchdog (FAULT_LIMIT seconds, default 120): a run still alive then is a
# hang and fails the case. A case passes when the run ends with the expected status and
# message, leaves finished data bitwise unchanged and, where it continues, finishes bitwise
# equal to an undisturbed run. The cases are listed in tests/README.md ("Fault injection").
set -uo pipefail
jamsim=$1 case=$2 ranks=$3 work=$4
here=$(cd "$(dirname "$0")" && pwd)
compare="/usr/bin/python3 $here/../mpi/compare_archives.py"
damage="/usr/bin/python3 $here/damage_checkpoint.py"
limit=${FAULT_LIMIT:-120}
mpirun=${MPIEXEC:-mpiexec}
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1

fail() { echo "FAIL ($case, $ranks ranks): $*"; exit 1; }
# run LOG ARGS...: jamsim on $ranks ranks under the watchdog; sets rc.
run() {
  local log=$1; shift
  timeout -k 10 "$limit" "$mpirun" -n "$ranks" "$jamsim" "$@" > "$log" 2>&1
  rc=$?
  if [[ $rc -eq 124 || $rc -eq 137 ]]; then cat "$log"; fail "jamsim $* did not end within ${limit} s (a hang)"; fi
}
expect_rc() { [[ $rc -eq $1 ]] || { cat "$2"; fail "exit status $rc, expected $1"; }; }
expect_in() { grep -Eq -- "$1" "$2" || { cat "$2"; fail "no /$1/ in $2"; }; }
no_crash() {
  ! grep -Eq -- "HDF5-DIAG|terminate called|Segmentation|buffer overflow|malloc\(\)" "$1" || { cat "$1"; fail "a crash in $1"; }
}

# Two fixtures, made once by their own cases (faults.reference.np2 and faults.interrupted.npN,
# CTest's FIXTURES_SETUP) beside this case's WORKDIR, and copied by the cases that use them;
# a case run without them makes its own.
shared=$(dirname "$work")
# ref.h5: the checkpointed campaign run without interruption (its bits do not depend on ranks).
reference() {
  if [[ -s $shared/reference.np2/ref.h5 ]]; then cp "$shared/reference.np2/ref.h5" ref.h5 || fail "copying the reference"
  else run ref.log run "$here/checkpointed.toml" -o ref.h5; expect_rc 0 ref.log; fi
}
# cp.h5 and its checkpoints: the checkpointed campaign interrupted by SIGUSR1 while replicas
# run, on $ranks ranks.
interrupt_campaign() {
  # SIGUSR1 (what a batch system's time-limit warning sends) to mpiexec 2 s after the ranks
  # started, while the long replicas run (about 5 s on 2 ranks). A signal before the ranks
  # start is lost (tests/wait_for_ranks.sh).
  timeout -k 10 "$limit" "$mpirun" -n "$ranks" "$jamsim" run "$here/checkpointed.toml" -o cp.h5 \
    --progress lines > cp.log 2>&1 &
  local leader=$!
  "$here/../wait_for_ranks.sh" "$leader" "$ranks" "^$jamsim run $here/checkpointed.toml -o cp.h5" &&
    sleep 2 && pkill -USR1 -P "$leader"  # mpiexec, the child of timeout
  rc=0; wait "$leader" || rc=$?
  expect_rc 75 cp.log
  # The last progress line counts the stopped replicas as interrupted, not as pending.
  expect_in '[1-9][0-9]* interrupted \(saved\)' cp.log
  ls cp.h5.checkpoints/replica_*.h5 > /dev/null 2>&1 || fail "the interrupted run left no checkpoint"
}
# Both of the above, for a case that damages or resumes the interrupted run.
interrupted_campaign() {
  reference
  local made=$shared/interrupted.np$ranks
  if [[ -s $made/cp.h5 ]]; then cp -a "$made/cp.h5" "$made/cp.h5.checkpoints" "$made/cp.log" . || fail "copying $made"
  else interrupt_campaign; fi
}

case $case in
reference)  # the fixture ref.h5 (above)
  run ref.log run "$here/checkpointed.toml" -o ref.h5; expect_rc 0 ref.log
  ;;
interrupted)  # the fixture cp.h5 with its checkpoints (above)
  interrupt_campaign
  ;;
initial_other_mixture)  # another size_ratio than the source's: refused before any work
  run src.log run "$here/source.toml"; expect_rc 0 src.log
  run dep.log run "$here/dependent_other_mixture.toml"; expect_rc 2 dep.log
  expect_in 'initial = "src.h5": replica 0 has size_ratio = 1.4, replica 0 here size_ratio = 1.3' dep.log
  [[ ! -e dep.h5 ]] || fail "an archive was written"
  ;;
initial_state_damaged)  # one source state unusable: its replicas fail with the reason, the rest run
  run src.log run "$here/source.toml"; expect_rc 0 src.log
  run ref.log run "$here/dependent.toml" -o ref.h5; expect_rc 0 ref.log
  cp src.h5 good-src.h5
  $damage src.h5 other_diameter > /dev/null || fail "could not damage the source"
  run dep.log run "$here/dependent.toml"; expect_rc 0 dep.log; no_crash dep.log
  "$jamsim" status dep.h5 > status.txt
  expect_in '6/8 done, 0 running, 2 failed' status.txt
  expect_in 'failed replica 0: \[run\] initial = "src.h5": replica 0 has disk 3 of diameter 1.2' status.txt
  expect_in 'failed replica 4: ' status.txt
  expect_in 'warning: 2 replicas of the archive failed \(jamsim status dep.h5 gives the reasons\); after a fix, --retry-failed' dep.log
  # A rerun without --retry-failed runs nothing, and still says so (it said "0 failed replicas").
  run again.log run "$here/dependent.toml"; expect_rc 0 again.log
  expect_in 'warning: 2 replicas of the archive failed' again.log
  cp good-src.h5 src.h5
  run retry.log run "$here/dependent.toml" --retry-failed; expect_rc 0 retry.log
  $compare ref.h5 dep.h5 || fail "the retried campaign differs from the undisturbed one"
  ;;
checkpoint_*)  # a damaged checkpoint: its replica starts again, with a warning; the rest continue
  kind=${case#checkpoint_}
  interrupted_campaign
  victim=$(ls cp.h5.checkpoints/replica_*.h5 | head -1)
  before=$(/usr/bin/python3 -c "import h5py,numpy; print((h5py.File('cp.h5','r',locking=False)['replicas/status'][...]==2).sum())")
  $damage "$victim" "$kind" > /dev/null || fail "could not damage $victim"
  run resume.log run "$here/checkpointed.toml" -o cp.h5; expect_rc 0 resume.log; no_crash resume.log
  expect_in "warning: checkpoint '$victim' .*; replica [0-9]+ starts again from its start" resume.log
  expect_in "\(0 failed replicas" resume.log
  [[ $before -ge 0 ]] || fail "no status"
  $compare ref.h5 cp.h5 || fail "the resumed campaign differs from the undisturbed one"
  ;;
ladder_extend)  # an extended rate ladder equals the longer ladder run in one go
  d=$here/../data/campaigns
  run ref.log run "$d/ladder_extend_long.toml" -o ref.h5; expect_rc 0 ref.log
  run short.log run "$d/ladder_extend_short.toml" -o ext.h5; expect_rc 0 short.log
  run long.log run "$d/ladder_extend_long.toml" -o ext.h5; expect_rc 0 long.log
  expect_in "a rate ladder's later replicas run again from their predecessors' new end states" long.log
  $compare ref.h5 ext.h5 || fail "the extended ladder differs from the one run in one go"
  ;;
initial_source_changed)  # the source extended between two runs of the dependent campaign
  run src.log run "$here/source.toml"; expect_rc 0 src.log
  run half.log run "$here/dependent.toml" --shard 0/2; expect_rc 0 half.log
  run longer.log run "$here/source_longer.toml" -o src.h5; expect_rc 0 longer.log
  sum=$(sha256sum dep.h5)
  run rest.log run "$here/dependent.toml"; expect_rc 2 rest.log
  expect_in 'initial = "src.h5" has changed since this archive.s replicas started from it: the state that started replicas 0, 2' rest.log
  [[ "$(sha256sum dep.h5)" == "$sum" ]] || fail "dep.h5 was modified"
  ;;
lock_symlink | lock_removed)  # a second writer through a symlink, or after the lock file is removed
  reference
  timeout -k 10 "$limit" "$mpirun" -n "$ranks" "$jamsim" run "$here/checkpointed.toml" -o cp.h5 > first.log 2>&1 &
  leader=$!
  for _ in $(seq 200); do [[ -e cp.h5 ]] && break; sleep 0.05; done
  sleep 1
  if [[ $case == lock_symlink ]]; then
    ln -s cp.h5 alias.h5
    run second.log run "$here/checkpointed.toml" -o alias.h5
    expect_in "is being written by jamsim run" second.log
  else
    rm -f cp.h5.lock
    run second.log run "$here/checkpointed.toml" -o cp.h5
    expect_in "'cp.h5' is open in another process" second.log
  fi
  expect_rc 2 second.log
  wait "$leader"; rc=$?; expect_rc 0 first.log
  $compare ref.h5 cp.h5 || fail "the first run's archive differs from an undisturbed one"
  ;;
long_path)  # an archive path longer than MPI-IO takes: shortened, or refused in words
  deep=$(printf 'd%.0s' $(seq 100))/$(printf 'e%.0s' $(seq 100))
  mkdir -p "$deep"
  run near.log run "$here/source.toml" -o "$PWD/$deep/src.h5"; expect_rc 0 near.log; no_crash near.log
  "$jamsim" status "$deep/src.h5" | grep -q '4/4 done' || fail "the long-path archive is not complete"
  mkdir -p "$deep/$deep"
  cd "$deep/$deep" && cd / || fail "cannot reach $deep/$deep"
  run far.log run "$here/source.toml" -o "$work/$deep/$deep/src.h5"; expect_rc 2 far.log
  expect_in 'is not allowed: an archive path of at most 234 characters' far.log
  # A path of the longest length taken (relative, as given): run, then extended (which
  # opens PATH.extending, 10 characters more, through MPI-IO).
  cd "$work" || fail "cannot return to $work"
  longest=$(printf 'g%.0s' $(seq 100))/
  mkdir -p "$longest"
  longest+=$(printf 'f%.0s' $(seq $((234 - ${#longest} - 3)))).h5
  [[ ${#longest} -eq 234 ]] || fail "the test's path has ${#longest} characters, not 234"
  run edge.log run "$here/source.toml" -o "$longest"; expect_rc 0 edge.log; no_crash edge.log
  run edge_longer.log run "$here/source_longer.toml" -o "$longest"; expect_rc 0 edge_longer.log
  no_crash edge_longer.log
  "$jamsim" status "$longest" | grep -q '4/4 done' || fail "the extended archive of 234 characters is not complete"
  # ... and one of 240 is refused before any work (its extension aborted in Open MPI).
  run edge240.log run "$here/source.toml" -o "${longest%.h5}ffffff.h5"; expect_rc 2 edge240.log
  expect_in 'is not allowed: an archive path of at most 234 characters' edge240.log
  ;;
signals)  # SIGHUP to a rank saves and exits 75; a closed pipe does not kill the run
  reference
  timeout -k 10 "$limit" "$mpirun" -n "$ranks" "$jamsim" run "$here/checkpointed.toml" -o hup.h5 > hup.log 2>&1 &
  leader=$!
  for _ in $(seq 200); do [[ -e hup.h5 ]] && break; sleep 0.05; done
  sleep 1
  pkill -HUP -f -- "^$jamsim run .*-o hup.h5" || fail "no rank to signal"  # the ranks, not mpirun
  wait "$leader"; rc=$?; expect_rc 75 hup.log
  expect_in 'run the same command again to continue' hup.log
  run again.log run "$here/checkpointed.toml" -o hup.h5; expect_rc 0 again.log
  $compare ref.h5 hup.h5 || fail "the run resumed after SIGHUP differs"
  # One process whose progress reader goes away at once (jamsim run ... | head): the run goes
  # on and finishes (mpirun itself is not jamsim's to protect: this runs without it).
  timeout -k 10 "$limit" "$jamsim" run "$here/checkpointed.toml" -o pipe.h5 --progress lines \
    --progress-interval 0.1 2> pipe.err | head -c 1 > /dev/null
  for _ in $(seq $((limit * 10))); do pgrep -f -- "-o pipe.h5" > /dev/null || break; sleep 0.1; done
  "$jamsim" status pipe.h5 | grep -q '6/6 done' || fail "the run whose reader went away did not finish"
  $compare ref.h5 pipe.h5 || fail "the run whose reader went away differs"
  ;;
disk_full)  # another program fills the filesystem mid-run: every rank stops with one message
  [[ $(id -u) -eq 0 ]] || { echo "skipped: mounting a tmpfs needs root"; exit 77; }
  run ref.log run "$here/filling.toml" -o ref.h5; expect_rc 0 ref.log
  mkdir -p small && mount -t tmpfs -o size=6M tmpfs small || fail "cannot mount a tmpfs"
  trap 'cd /; for _ in 1 2 3 4 5 6 7 8 9 10; do umount "$work/small" 2>/dev/null && break; sleep 0.5; done; mountpoint -q "$work/small" && umount -l "$work/small"' EXIT
  cd small || fail "no tmpfs"
  timeout -k 10 "$limit" "$mpirun" -n "$ranks" "$jamsim" run "$here/filling.toml" --progress lines \
    --progress-interval 0.1 > ../filled.log 2>&1 &
  leader=$!
  for _ in $(seq 300); do grep -Eq "\] [1-9][0-9]*/10 done" ../filled.log && break; sleep 0.05; done
  dd if=/dev/zero of=filler bs=64k 2> /dev/null
  wait "$leader"; rc=$?
  [[ $rc -ne 124 && $rc -ne 137 ]] || { cat ../filled.log; fail "the run did not end within ${limit} s (a hang)"; }
  [[ $rc -ne 0 ]] || { cat ../filled.log; fail "the run did not notice the full filesystem"; }
  expect_in "no space left on device: writing the archive 'big.h5' failed .*run the same command again to continue" ../filled.log
  rm filler
  run ../after.log run "$here/filling.toml"; expect_rc 0 ../after.log
  $compare ../ref.h5 big.h5 || fail "the campaign finished after the full disk differs"
  ;;
export_disk_full)  # jamsim export into a nearly full filesystem: one message, no crash, nothing left
  [[ $(id -u) -eq 0 ]] || { echo "skipped: mounting a tmpfs needs root"; exit 77; }
  run src.log run "$here/source.toml" -o src.h5; expect_rc 0 src.log
  mkdir -p small && mount -t tmpfs -o size=1M tmpfs small || fail "cannot mount a tmpfs"
  trap 'cd /; umount "$work/small" 2>/dev/null || umount -l "$work/small"' EXIT
  # Free space left for the export, in kB: below the file's size (about 30 kB for H5MD and
  # 6 kB for LAMMPS data at N = 64).
  for free in 0 4 8 16 24; do
    rm -f small/filler
    avail=$(df -k --output=avail small | tail -1)
    dd if=/dev/zero of=small/filler bs=1k count=$((avail - free)) 2> /dev/null
    names=e.h5md; [[ $free -eq 0 ]] && names="e.h5md e.data"
    for name in $names; do
      timeout -k 10 "$limit" "$jamsim" export src.h5 -r 0 -o "small/$name" > "export_$free.log" 2>&1
      rc=$?
      no_crash "export_$free.log"
      [[ $rc -eq 1 ]] || { cat "export_$free.log"; fail "export into $free kB free: exit status $rc, expected 1"; }
      expect_in "No space left on device" "export_$free.log"
      [[ $(ls small) == filler ]] || fail "export into $free kB free left $(ls small | tr '\n' ' ')"
    done
  done
  rm small/filler
  timeout -k 10 "$limit" "$jamsim" export src.h5 -r 0 -o small/e.h5md > export.log 2>&1
  rc=$?; expect_rc 0 export.log
  ;;
write_one_rank)  # one rank's share of a collective archive write fails (ENOSPC): no hang
  # Parallel HDF5 1.10 then leaves that rank in a broadcast and the others in a barrier, for
  # ever: the archive's creation, stamps and close run under a deadline (shortened here).
  [[ -n ${FAIL_WRITE_LIB:-} ]] || fail "FAIL_WRITE_LIB is not set"
  last=$((ranks - 1))
  for after in 0 3; do  # the creation's first write; a later one (the run's stamps)
    rm -rf w.h5 w.h5.*
    timeout -k 10 "$limit" "$mpirun" -n "$ranks" -x LD_PRELOAD="$FAIL_WRITE_LIB" -x FAIL_WRITE_SUFFIX=/w.h5 \
      -x FAIL_WRITE_RANK=$last -x FAIL_WRITE_AFTER=$after -x JAMSIM_WRITE_DEADLINE_SECONDS=3 \
      "$jamsim" run "$here/source.toml" -o w.h5 > write$after.log 2>&1
    rc=$?
    if [[ $rc -eq 124 || $rc -eq 137 ]]; then cat write$after.log; fail "a failed write on rank $last hung the run"; fi
    [[ $rc -ne 0 ]] || { cat write$after.log; fail "a failed write went unnoticed (exit 0)"; }
    expect_in "jamsim: writing 'w\.h5' \(its creation\) did not finish within 3 s on rank [0-9]+: a write failed on some rank" write$after.log
  done
  # With room again, the same command makes the archive anew and runs it.
  run again.log run "$here/source.toml" -o w.h5; expect_rc 0 again.log
  expect_in "removed 'w.h5', an archive whose creation was interrupted" again.log
  "$jamsim" status w.h5 | grep -q " 0 failed" || fail "replicas failed after the creation was made anew"
  ;;
write_refused)  # every write to the archive refused, with a quota's or a failing disk's errno: the
  # message names it (MPI-IO passes HDF5 no errno: "file write failed"), and no crash (HDF5
  # closed the half-written file again at MPI_Finalize: a segfault, exit 139)
  [[ -n ${FAIL_WRITE_LIB:-} ]] || fail "FAIL_WRITE_LIB is not set"
  run ref.log run "$here/source.toml" -o ref.h5; expect_rc 0 ref.log
  refused() {  # ERRNO AFTER LOG: the run with writes to w.h5 and its test writes (a nameless
    # file, which /proc names 'DIR/#INODE (deleted)', or a named one) refused
    timeout -k 10 "$limit" "$mpirun" -n "$ranks" -x LD_PRELOAD="$FAIL_WRITE_LIB" -x FAIL_WRITE_SUFFIX='/w.h5:.write-test:(deleted)' \
      -x FAIL_WRITE_RANK=any -x FAIL_WRITE_ERRNO="$1" -x FAIL_WRITE_AFTER="$2" -x JAMSIM_WRITE_DEADLINE_SECONDS=10 \
      "$jamsim" run "$here/source.toml" -o w.h5 > "$3" 2>&1
    rc=$?
    if [[ $rc -eq 124 || $rc -eq 137 ]]; then cat "$3"; fail "a refused write hung the run"; fi
    expect_rc 1 "$3"; no_crash "$3"
  }
  refused EDQUOT 0 create.log  # the archive's creation
  expect_in "creating the archive 'w\.h5' failed: disk quota exceeded; nothing was kept \(HDF5: .* failed \(file write failed\)\)" create.log
  [[ ! -e w.h5 ]] || fail "the failed creation left w.h5"
  refused EIO 300 run.log  # a replica's results, mid-run
  expect_in "input/output error: writing the archive 'w\.h5' failed \(HDF5: .*\); the replicas finished before are safe in it \(jamsim status w\.h5\): mend the filesystem and run the same command again to continue" run.log
  ls *.write-test > /dev/null 2>&1 && fail "a test write was left"
  run again.log run "$here/source.toml" -o w.h5; expect_rc 0 again.log
  $compare ref.h5 w.h5 || fail "the campaign finished after the refused writes differs"
  ;;
write_stalls_one_rank)  # one rank's write of a replica's data never returns (a filesystem that
  # stops answering one node): the write deadline ends the job (it held every rank for as long
  # as the write did: only the archive's creation, stamps and close had a deadline)
  # Every rank's 101st write stalls: how many writes each rank makes depends on which replicas
  # the farm gave it (with the last rank alone and 200 writes, a loaded machine left it short).
  [[ -n ${FAIL_WRITE_LIB:-} ]] || fail "FAIL_WRITE_LIB is not set"
  timeout -k 10 "$limit" "$mpirun" -n "$ranks" -x LD_PRELOAD="$FAIL_WRITE_LIB" -x FAIL_WRITE_SUFFIX=/s.h5 \
    -x FAIL_WRITE_RANK=any -x FAIL_WRITE_AFTER=100 -x FAIL_WRITE_HANG_SECONDS=1000 \
    -x JAMSIM_WRITE_DEADLINE_SECONDS=5 "$jamsim" run "$here/checkpointed.toml" -o s.h5 > stall.log 2>&1
  rc=$?
  if [[ $rc -eq 124 || $rc -eq 137 ]]; then cat stall.log; fail "a stalled write hung the run"; fi
  [[ $rc -ne 0 ]] || { cat stall.log; fail "exit 0 with a stalled write"; }
  expect_in "jamsim: writing 's\.h5' \(replica [0-9]+'s [a-z ]+\) did not finish within 5 s on rank [0-9]+" stall.log
  # The same command then finishes the campaign.
  run again.log run "$here/checkpointed.toml" -o s.h5; expect_rc 0 again.log
  "$jamsim" status s.h5 | grep -q "6/6 done" || fail "the campaign did not finish after the stall"
  ;;
resume_checkpoint_unopenable)  # an interrupted run resumed while the system cannot open one of its
  # checkpoints (no descriptors left): the run stops with the checkpoint kept, and the same
  # command then finishes bitwise equal (the checkpoint was taken for damaged and removed, and
  # its replica started again from its start)
  [[ -n ${FAIL_OPEN_LIB:-} ]] || fail "FAIL_OPEN_LIB is not set"
  interrupted_campaign
  # (an interrupted replica's: finished ones keep theirs for an extension, unread by a resume)
  kept=replica_$("$jamsim" status cp.h5 | sed -n 's/^interrupted replica \([0-9]*\):.*/\1/p' | head -1).h5
  [[ -f cp.h5.checkpoints/$kept ]] || fail "no checkpoint of an interrupted replica ($kept)"
  sum=$(sha256sum < "cp.h5.checkpoints/$kept")
  timeout -k 10 "$limit" "$mpirun" -n 1 -x LD_PRELOAD="$FAIL_OPEN_LIB" -x FAIL_OPEN_SUFFIX="/$kept" -x FAIL_OPEN_RANK=0 \
    -x FAIL_OPEN_ERRNO=24 "$jamsim" run "$here/checkpointed.toml" -o cp.h5 > unopenable.log 2>&1
  rc=$?
  [[ $rc -eq 1 ]] || { cat unopenable.log; fail "exit status $rc, expected 1"; }
  expect_in "the filesystem refused a checkpoint beside the archive \(filesystem error: cannot read the checkpoint: Too many open files" unopenable.log
  [[ "$(sha256sum < "cp.h5.checkpoints/$kept")" == "$sum" ]] || fail "the checkpoint $kept was removed or changed"
  run again.log run "$here/checkpointed.toml" -o cp.h5; expect_rc 0 again.log
  ! grep -q "starts again from its start" again.log || { cat again.log; fail "a checkpoint was taken for damaged"; }
  $compare ref.h5 cp.h5 || fail "the resumed archive differs from the undisturbed run"
  ;;
merge_write_fails)  # a merge whose writes fail (a full disk), or stopped by Ctrl-C: its message, no crash
  # (HDF5's own close of the failed output at MPI_Finalize segfaulted, exit 139), and the same
  # merge then completes, equal to a merge that did not fail
  [[ -n ${FAIL_WRITE_LIB:-} ]] || fail "FAIL_WRITE_LIB is not set"
  for k in 0 1; do run shard$k.log run "$here/checkpointed.toml" -o s$k.h5 --shard $k/2; expect_rc 0 shard$k.log; done
  "$jamsim" merge ref.h5 s0.h5 s1.h5 > ref.log 2>&1 || { cat ref.log; fail "the reference merge"; }
  failing_merge() {  # LOG OUTPUT AFTER INPUTS...
    local log=$1 output=$2 after=$3; shift 3
    timeout -k 10 "$limit" "$mpirun" -n 1 -x LD_PRELOAD="$FAIL_WRITE_LIB" -x FAIL_WRITE_SUFFIX="/$output" \
      -x FAIL_WRITE_RANK=0 -x FAIL_WRITE_AFTER="$after" "$jamsim" merge "$output" "$@" > "$log" 2>&1
    rc=$?
    expect_rc 1 "$log"; no_crash "$log"
    ! grep -q "signal 11" "$log" || { cat "$log"; fail "a crash in $log"; }
  }
  failing_merge new.log m.h5 20 s0.h5 s1.h5  # into a new output: it is removed
  expect_in "merging into 'm.h5' failed: .*; the new 'm.h5' was removed" new.log
  [[ ! -e m.h5 ]] || fail "the failed new output is left"
  "$jamsim" merge m.h5 s0.h5 > first.log 2>&1 || { cat first.log; fail "merge of the first shard"; }
  failing_merge existing.log m.h5 40 s1.h5  # into an existing output: it keeps what it held
  expect_in "merging into 'm.h5' failed: .*'m.h5' keeps what it held" existing.log
  "$jamsim" merge m.h5 s1.h5 > again.log 2>&1 || { cat again.log; fail "the merge run again"; }
  $compare ref.h5 m.h5 || fail "the merge completed after a failure differs from the reference merge"
  # Ctrl-C to a merge (held at a write 3 s, the signal sent at 1 s): it stops before its next
  # replica with exit 75, its new output removed, an existing one whole. It used to die at
  # once with 130 and no word, its new output left half made.
  interrupted_merge() {  # LOG OUTPUT AFTER INPUTS...
    local log=$1 output=$2 after=$3; shift 3
    LD_PRELOAD="$FAIL_WRITE_LIB" FAIL_WRITE_SUFFIX="/$output" FAIL_WRITE_RANK=any FAIL_WRITE_AFTER="$after" \
      FAIL_WRITE_HANG_SECONDS=3 timeout -k 10 "$limit" "$jamsim" merge "$output" "$@" > "$log" 2>&1 &
    local leader=$!
    sleep 1 && pkill -INT -P "$leader"
    rc=0; wait "$leader" || rc=$?
    expect_rc 75 "$log"; no_crash "$log"
  }
  interrupted_merge stop_new.log n.h5 20 s0.h5 s1.h5
  expect_in "^jamsim merge: merging into 'n\.h5' was stopped by a signal; the new 'n\.h5' was removed" stop_new.log
  [[ ! -e n.h5 ]] || fail "the interrupted merge left its new output"
  "$jamsim" merge n.h5 s0.h5 > n_first.log 2>&1 || { cat n_first.log; fail "merge of the first shard"; }
  interrupted_merge stop_existing.log n.h5 5 s1.h5
  expect_in "merging into 'n\.h5' was stopped by a signal; 'n\.h5' keeps what it held and the [0-9]+ replicas? this merge copied whole before it stopped: run the same merge again" stop_existing.log
  "$jamsim" merge n.h5 s1.h5 > n_again.log 2>&1 || { cat n_again.log; fail "the interrupted merge run again"; }
  $compare ref.h5 n.h5 || fail "the merge completed after an interruption differs from the reference merge"
  # A second stop signal (here SIGTERM after SIGINT) ends the merge at once, as by default; the
  # same merge then makes its output anew.
  LD_PRELOAD="$FAIL_WRITE_LIB" FAIL_WRITE_SUFFIX=/t.h5 FAIL_WRITE_RANK=any FAIL_WRITE_AFTER=20 \
    FAIL_WRITE_HANG_SECONDS=30 timeout -k 10 "$limit" "$jamsim" merge t.h5 s0.h5 s1.h5 > twice.log 2>&1 &
  leader=$!
  sleep 1 && pkill -INT -P "$leader" && sleep 0.5 && pkill -TERM -P "$leader"
  rc=0; wait "$leader" || rc=$?
  expect_rc 143 twice.log  # timeout passes on its child's death by SIGTERM as 128 + 15
  "$jamsim" merge t.h5 s0.h5 s1.h5 > t_again.log 2>&1 || { cat t_again.log; fail "the merge after a second signal"; }
  $compare ref.h5 t.h5 || fail "the merge made again after a second signal differs from the reference merge"
  ;;
archive_changed_before_lock)  # another campaign's archive made between a run's checks and its lock
  # The run's checks find no archive; before it takes the lock (held there by an LD_PRELOAD
  # wrapper), another campaign runs to the same path. The run used to open that archive and
  # write its own replicas into it; it checks again under the lock and stops, changing nothing.
  [[ -n ${FAIL_OPEN_LIB:-} ]] || fail "FAIL_OPEN_LIB is not set"
  rm -f race.h5 go go.waiting
  timeout -k 10 "$limit" "$mpirun" -n "$ranks" -x LD_PRELOAD="$FAIL_OPEN_LIB" -x HOLD_CREATE_SUFFIX=race.h5.lock \
    -x HOLD_CREATE_UNTIL="$PWD/go" "$jamsim" run "$here/checkpointed.toml" -o race.h5 > late.log 2>&1 &
  late=$!
  for _ in $(seq $((limit * 50))); do [[ -e go.waiting ]] && break; sleep 0.02; done
  [[ -e go.waiting ]] || { touch go; wait $late; cat late.log; fail "the run never reached its lock"; }
  run other.log run "$here/source.toml" -o race.h5; expect_rc 0 other.log
  sum=$(sha256sum < race.h5)
  touch go
  rc=0; wait $late || rc=$?
  expect_rc 2 late.log
  expect_in "checkpointed.toml: the archive '.*race.h5' changed while this run started \(another run made or changed it\): .*belongs to a different campaign.*; nothing was done" late.log
  [[ $(sha256sum < race.h5) == "$sum" ]] || fail "the other campaign's archive was changed"
  "$jamsim" status race.h5 | grep -q "fault-source (race.h5): 4/4 done" || fail "the other campaign's archive is not whole"
  ;;
open_one_rank)  # one rank cannot open the archive: every rank refuses together, nothing changes
  # (Open MPI's MPI_File_open waited forever when it failed on one rank only.)
  [[ -n ${FAIL_OPEN_LIB:-} ]] || fail "FAIL_OPEN_LIB is not set"
  last=$((ranks - 1))
  # failing_open LOG SUFFIX ERRNO ARGS...: jamsim run with open() of *SUFFIX failing on the last
  # rank (after FAIL_OPEN_AFTER opens that succeed, default 0).
  failing_open() {
    local log=$1 suffix=$2 code=$3; shift 3
    timeout -k 10 "$limit" "$mpirun" -n "$ranks" -x LD_PRELOAD="$FAIL_OPEN_LIB" -x FAIL_OPEN_SUFFIX="$suffix" \
      -x FAIL_OPEN_RANK=$last -x FAIL_OPEN_ERRNO="$code" -x FAIL_OPEN_AFTER="${FAIL_OPEN_AFTER:-0}" \
      "$jamsim" run "$@" > "$log" 2>&1
    rc=$?
    if [[ $rc -eq 124 || $rc -eq 137 ]]; then cat "$log"; fail "jamsim run $* did not end within ${limit} s (a hang)"; fi
    expect_rc 2 "$log"; no_crash "$log"
  }
  failing_open create.log src.h5 13 "$here/source.toml"  # EACCES
  expect_in "creating 'src.h5' failed on rank $last: Permission denied" create.log
  [[ -z $(ls) || $(ls) == create.log ]] || fail "the refused creation left $(ls | tr '\n' ' ')"
  run src.log run "$here/source.toml"; expect_rc 0 src.log
  sum=$(sha256sum src.h5)
  failing_open resume.log src.h5 24 "$here/source.toml"  # EMFILE
  expect_in "opening 'src.h5' failed on rank $last: Too many open files; nothing was changed" resume.log
  failing_open extend.log src.h5.extending 13 "$here/source_longer.toml" -o src.h5
  expect_in "creating 'src.h5.extending' failed on rank $last: Permission denied; nothing was changed" extend.log
  [[ "$(sha256sum src.h5)" == "$sum" ]] || fail "src.h5 was modified"
  ! ls src.h5.extending* > /dev/null 2>&1 || fail "the refused extension left $(ls src.h5.extending*)"
  # Later stages: the extension's archive made, then its reopen refused (it was left beside
  # the archive); the archive opened, then its reopen at the run's start refused (an MPI abort).
  FAIL_OPEN_AFTER=2 failing_open extend_late.log src.h5.extending 13 "$here/source_longer.toml" -o src.h5
  expect_in "opening 'src.h5.extending' failed on rank $last: Permission denied; nothing was changed" extend_late.log
  ! ls src.h5.extending* > /dev/null 2>&1 || fail "the refused extension left $(ls src.h5.extending*)"
  FAIL_OPEN_AFTER=2 failing_open start_late.log src.h5 13 "$here/source.toml"
  expect_in "opening 'src.h5' failed on rank $last: Permission denied; nothing has run" start_late.log
  ! grep -q MPI_ABORT start_late.log || fail "an MPI abort"
  run longer.log run "$here/source_longer.toml" -o src.h5; expect_rc 0 longer.log
  ;;
refusals)  # runs no job can finish, duplicates, misleading inputs: one clear message each
  run huge.log run "$here/huge_run.toml" --dry-run; expect_in 'would take about [0-9.e+]+ core-years' huge.log
  run dup.log run "$here/duplicate_seeds.toml"; expect_rc 2 dup.log
  expect_in 'twice \(replicas 0 and 2\), which is not allowed: each replica once' dup.log
  [[ ! -e dup.h5 ]] || fail "an archive was written"
  ;;
archive_replaced)  # the archive replaced by another campaign's while the run writes: the run
  # stops non-zero and writes nothing into the other archive (it used to exit 0 "finished",
  # its results lost in the unlinked file, and stamp the other campaign's archive)
  run src.log run "$here/source.toml"; expect_rc 0 src.log
  other=$(sha256sum < src.h5)
  timeout -k 10 "$limit" "$mpirun" -n "$ranks" "$jamsim" run "$here/checkpointed.toml" -o d.h5 > d.log 2>&1 &
  leader=$!
  "$here/../wait_for_ranks.sh" "$leader" "$ranks" "^$jamsim run $here/checkpointed.toml -o d.h5" &&
    sleep 1 && mv src.h5 d.h5
  rc=0; wait "$leader" || rc=$?
  [[ $rc -ne 0 && $rc -ne 124 && $rc -ne 137 ]] || { cat d.log; fail "exit status $rc after the archive was replaced"; }
  expect_in "'d.h5' is no longer the archive this run writes \(it was replaced, moved or removed while the run wrote it\)" d.log
  [[ "$(sha256sum < d.h5)" == "$other" ]] || fail "the other campaign's archive was changed"
  ;;
rename_fails_at_checkpoint)  # the filesystem refuses a checkpoint's rename: the run stops, keeps the
  # replica's last good checkpoint and fails no replica (it marked the replica failed for good
  # and removed that checkpoint); the same command then finishes bitwise equal
  [[ -n ${FAIL_OPEN_LIB:-} ]] || fail "FAIL_OPEN_LIB is not set"
  reference
  timeout -k 10 "$limit" "$mpirun" -n "$ranks" -x LD_PRELOAD="$FAIL_OPEN_LIB" -x FAIL_RENAME_SUFFIX=/replica_0.h5 \
    -x FAIL_RENAME_AFTER=2 "$jamsim" run "$here/checkpointed.toml" -o cp.h5 --checkpoint-every 0 > cp.log 2>&1
  rc=$?
  [[ $rc -eq 1 ]] || { cat cp.log; fail "exit status $rc, expected 1"; }
  expect_in "the filesystem refused a checkpoint beside the archive \(.*replica_0.h5" cp.log
  [[ -f cp.h5.checkpoints/replica_0.h5 ]] || fail "the last good checkpoint of replica 0 was removed"
  "$jamsim" status cp.h5 > status.log 2>&1
  expect_in ", 0 failed," status.log
  run again.log run "$here/checkpointed.toml" -o cp.h5; expect_rc 0 again.log
  expect_in "1 continued from checkpoints|[1-9][0-9]* continued from checkpoints" again.log
  $compare ref.h5 cp.h5 || fail "the resumed archive differs from the undisturbed run"
  ;;
*) fail "unknown case" ;;
esac
echo "ok: $case on $ranks ranks"
