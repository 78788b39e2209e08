#!/usr/bin/env bash
# usage: threads_input.sh JAMSIM CAMPAIGN WORKDIR CASE
# Threads as the user gives them (--threads, OMP_NUM_THREADS), one CASE per CTest test:
#   refused cases: exit 2, one message naming the flag or variable, the value and what is
#     allowed (and no libgomp line: jamsim's message is the only one), nothing written; a bad
#     OMP_NUM_THREADS only where the kernel runs, and not with --threads;
#   flag_wins: --threads wins over a different OMP_NUM_THREADS, and the log says so;
#   oversubscribed / fits: more threads than the process's cores warn (and run), as many
#     do not (also with OMP_PROC_BIND set); mpi_oversubscribed / mpi_fits: the same for ranks sharing a node's cores
#     (MPIEXEC, 2 ranks, not bound).
set -uo pipefail
jamsim=$1 campaign=$2 work=$3 case=$4
mkdir -p "$work/$case" && cd "$work/$case" || exit 1
rm -rf out.h5 out.h5.tmp out.h5.checkpoints
unset OMP_NUM_THREADS
fail() { echo "$msg"; echo "FAIL ($case): $*"; exit 1; }
mpirun=${MPIEXEC:-mpiexec}

# refused STATUS REGEX [ENV=VALUE] -- jamsim ARGS...: exit STATUS, the one message, nothing written.
refused() {
  local regex=$1
  shift
  msg=$("$@" 2>&1)
  rc=$?
  echo "$msg"
  [[ $rc -eq 2 ]] || fail "exit $rc, expected 2"
  grep -Eq -- "$regex" <<<"$msg" || fail "message does not match /$regex/"
  ! grep -q "libgomp" <<<"$msg" || fail "libgomp's own message too: jamsim's must be the only one"
  ! grep -Eq "campaign .* replicas on|samples, " <<<"$msg" || fail "work started"
  [[ ! -e out.h5 && ! -e out.h5.tmp && ! -e out.h5.checkpoints ]] || fail "out.h5 was written"
  echo "ok ($case): refused, exit 2"
}
# ran REGEX [!REGEX] -- COMMAND...: exit 0, the output matches REGEX (and not !REGEX).
ran() {
  local want=$1 unwanted=$2
  shift 2
  msg=$("$@" 2>&1)
  rc=$?
  echo "$msg"
  [[ $rc -eq 0 ]] || fail "exit $rc, expected 0"
  grep -Eq -- "$want" <<<"$msg" || fail "output does not match /$want/"
  [[ -z $unwanted ]] || ! grep -Eq -- "$unwanted" <<<"$msg" || fail "output matches /$unwanted/"
  [[ -e out.h5 ]] || fail "no out.h5"
  echo "ok ($case): ran, exit 0"
}
allowed="is not allowed: a whole number of threads from 1 to 4096"
over="warning: 2 threads per replica \(--threads\) are more than the"
short=(--N 4096 --strain 0.0005 --sample-interval 0.00025)  # long enough loops for threads

case $case in
  flag_not_a_number) refused "^jamsim replica: --threads = abc $allowed" "$jamsim" replica --threads abc -o out.h5 ;;
  flag_zero) refused "^jamsim replica: --threads = 0 $allowed" "$jamsim" replica --threads 0 -o out.h5 ;;
  flag_negative) refused "^jamsim run: --threads = -3 $allowed" "$jamsim" run "$campaign" --threads -3 -o out.h5 ;;
  flag_fraction) refused "^jamsim run: --threads = 1.5 $allowed" "$jamsim" run "$campaign" --threads 1.5 -o out.h5 ;;
  env_zero) refused "^jamsim run: OMP_NUM_THREADS = \"0\" $allowed" env OMP_NUM_THREADS=0 "$jamsim" run "$campaign" -o out.h5 ;;
  env_negative) refused "^jamsim replica: OMP_NUM_THREADS = \"-1\" $allowed" env OMP_NUM_THREADS=-1 "$jamsim" replica -o out.h5 ;;
  env_not_a_number)
    # Refused by the commands that run the kernel, unless --threads gives the count (the flag
    # wins, and says so); the others (--help, status, models) do not need it.
    refused "^jamsim replica: OMP_NUM_THREADS = \"abc\" $allowed.*; --threads T sets the count instead" \
      env OMP_NUM_THREADS=abc "$jamsim" replica -o out.h5
    refused "^jamsim minimize: OMP_NUM_THREADS = \"abc\" $allowed" env OMP_NUM_THREADS=abc "$jamsim" minimize --N 16
    env OMP_NUM_THREADS=abc "$jamsim" --help > /dev/null || fail "--help refused a bad OMP_NUM_THREADS"
    env OMP_NUM_THREADS=abc "$jamsim" models > /dev/null || fail "models refused a bad OMP_NUM_THREADS"
    ran "jamsim replica: --threads 2 wins over OMP_NUM_THREADS=abc" "libgomp" \
      env OMP_NUM_THREADS=abc "$jamsim" replica "${short[@]}" --threads 2 -o out.h5 ;;
  env_list)  # a nested list counts by its first level, but every level must be a count
    refused "^jamsim replica: OMP_NUM_THREADS = \"2,\" $allowed" env OMP_NUM_THREADS=2, "$jamsim" replica -o out.h5
    refused "^jamsim run: OMP_NUM_THREADS = \"2,0\" $allowed" env OMP_NUM_THREADS=2,0 "$jamsim" run "$campaign" -o out.h5
    ran "on 2 threads," "libgomp" env OMP_NUM_THREADS=2,1 "$jamsim" replica "${short[@]}" -o out.h5 ;;
  env_empty)  # set but empty: as if unset (1 thread), and no libgomp complaint
    ran "on 1 thread," "libgomp" env OMP_NUM_THREADS= "$jamsim" replica "${short[@]}" -o out.h5 ;;
  flag_wins)
    ran "jamsim run: --threads 2 wins over OMP_NUM_THREADS=3" "" \
      env OMP_NUM_THREADS=3 "$jamsim" run "$campaign" --threads 2 -o out.h5
    grep -q "replicas on 1 rank x 2 threads" <<<"$msg" || fail "the log does not say 1 rank x 2 threads"
    rm -f out.h5
    ran "jamsim replica: --threads 1 wins over OMP_NUM_THREADS=2" "" \
      env OMP_NUM_THREADS=2 "$jamsim" replica "${short[@]}" --threads 1 -o out.h5
    grep -q "on 1 thread," <<<"$msg" || fail "the replica did not run on 1 thread"
    rm -f out.h5  # the same count: nothing to say
    ran "on 2 threads," "wins over" env OMP_NUM_THREADS=2 "$jamsim" replica "${short[@]}" --threads 2 -o out.h5 ;;
  oversubscribed)
    ran "jamsim replica: $over 1 core this process may use: threads will share cores" "" \
      taskset -c 0 "$jamsim" replica "${short[@]}" --threads 2 -o out.h5
    rm -f out.h5
    ran "jamsim replica: warning: 3 threads per replica \(OMP_NUM_THREADS\) are more than the 1 core" "" \
      env OMP_NUM_THREADS=3 taskset -c 0 "$jamsim" replica "${short[@]}" -o out.h5 ;;
  fits)
    [[ $(nproc) -ge 2 ]] || { echo "skipped: fewer than 2 cores"; exit 77; }
    ran "on 2 threads," "warning: .*threads per replica" taskset -c 0,1 "$jamsim" replica "${short[@]}" --threads 2 -o out.h5
    # OpenMP placement binds the initial thread to one core before main: the process's
    # cores are still 2.
    rm -f out.h5
    ran "on 2 threads," "warning: .*threads per replica" env OMP_PROC_BIND=close OMP_PLACES=cores \
      taskset -c 0,1 "$jamsim" replica "${short[@]}" --threads 2 -o out.h5 ;;
  mpi_oversubscribed)  # 2 ranks of 2 threads on the cores of 2 ranks of 1
    [[ $(nproc) -ge 2 ]] || { echo "skipped: fewer than 2 cores"; exit 77; }
    ran "jamsim run: $over 1 core of each rank \(2 ranks on this node\)" "" \
      taskset -c 0,1 "$mpirun" -n 2 --bind-to none "$jamsim" run "$campaign" --threads 2 -o out.h5
    [[ $(grep -c "warning: 2 threads per replica" <<<"$msg") -eq 1 ]] || fail "the warning is not printed once" ;;
  mpi_fits)
    [[ $(nproc) -ge 2 ]] || { echo "skipped: fewer than 2 cores"; exit 77; }
    ran "replicas on 2 ranks x 1 thread " "warning: .*threads per replica" \
      taskset -c 0,1 "$mpirun" -n 2 --bind-to none "$jamsim" run "$campaign" --threads 1 -o out.h5 ;;
  *) echo "threads_input.sh: CASE = '$case' is not allowed: see the header of $0"; exit 2 ;;
esac
