#!/usr/bin/env bash
# A real single-node Slurm for tests and trials, started without systemd (root only):
#   SLURM_LOCAL_DIR=DIR tools/slurm-local.sh start   # state, logs and slurm.conf in DIR
#   export SLURM_CONF=DIR/slurm.conf                  # then sbatch, squeue, scontrol work
#   SLURM_LOCAL_DIR=DIR tools/slurm-local.sh stop    # stops exactly the daemons it started
# One node (localhost) with this machine's CPUs, partition `debug`, no accounting
# (finished jobs are listed in DIR/log/jobcomp.txt). Ports are picked free, so it does not
# collide with another Slurm on the machine; munged is reused when one already runs.
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then  # the header above, on stdout
  awk 'NR > 1 { if ($0 !~ /^#( |$)/) exit; sub(/^# ?/, ""); print }' "$0"
  exit 0
fi
dir=${SLURM_LOCAL_DIR:?set SLURM_LOCAL_DIR to a directory for the state and logs}

start() {
  [[ $(id -u) -eq 0 ]] || { echo "slurm-local: must run as root (slurmd)" >&2; exit 77; }
  command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v sbatch >/dev/null &&
    command -v munged >/dev/null || {
      echo "slurm-local: installing slurmctld slurmd slurm-client munge" >&2
      DEBIAN_FRONTEND=noninteractive apt-get update -qq
      DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        slurmctld slurmd slurm-client munge >/dev/null; }
  mkdir -p "$dir"/state "$dir"/log
  # slurmd puts Unix sockets in its spool folder, and a socket path must stay under 108
  # bytes: a deep DIR (a build tree inside a temporary clone) would make batch launches
  # fail, so the spool lives in a short folder of its own, removed by stop.
  spool=$(mktemp -d /tmp/slurmd.XXXXXX)
  echo "$spool" > "$dir"/spool-dir
  # munge: one daemon per machine, shared; start it only if none answers.
  if ! (munge -n | unmunge) >/dev/null 2>&1; then
    install -d -o munge -g munge -m 0755 /run/munge
    if [[ ! -s /etc/munge/munge.key ]]; then
      /usr/sbin/mungekey --create --force 2>/dev/null ||
        dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 2>/dev/null
      chown munge:munge /etc/munge/munge.key
      chmod 400 /etc/munge/munge.key
    fi
    runuser -u munge -- /usr/sbin/munged
    cp /run/munge/munged.pid "$dir"/munged.pid
  fi
  # Two free TCP ports for slurmctld and slurmd.
  read -r ctld_port slurmd_port < <(/usr/bin/python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
  cat > "$dir"/slurm.conf <<CONF
ClusterName=jamsim-local
SlurmctldHost=localhost
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=cred_expire=10
StateSaveLocation=$dir/state
SlurmdSpoolDir=$spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd-%n.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd-%n.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$dir/log/jobcomp.txt
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=pmix
ReturnToService=2
MailProg=/bin/true
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF=$dir/slurm.conf
  /usr/sbin/slurmctld -f "$dir"/slurm.conf -c
  /usr/sbin/slurmd -f "$dir"/slurm.conf -N localhost
  for _ in $(seq 1 60); do
    sinfo -h -o %T 2>/dev/null | grep -qx idle && break
    sleep 0.5
  done
  sinfo -h -o %T | grep -qx idle || { echo "slurm-local: the node did not come up" >&2; tail -20 "$dir"/log/*.log >&2; stop; exit 1; }
  echo "slurm-local: up (SLURM_CONF=$dir/slurm.conf)"
}

stop() {
  for f in slurmd-localhost.pid slurmctld.pid munged.pid; do
    [[ -s $dir/$f ]] || continue
    pid=$(cat "$dir/$f")
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 1 40); do kill -0 "$pid" 2>/dev/null || break; sleep 0.25; done
    rm -f "$dir/$f"
  done
  if [[ -s $dir/spool-dir ]]; then
    rm -rf -- "$(cat "$dir"/spool-dir)"
    rm -f "$dir"/spool-dir
  fi
}

case ${1:-} in
  start) start ;;
  stop) stop ;;
  *) echo "usage: SLURM_LOCAL_DIR=DIR $0 start|stop" >&2; exit 2 ;;
esac
