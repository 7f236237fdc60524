#!/usr/bin/env bash
# A one-node Slurm on this machine, for the tests and for trying the batch scripts: munged,
# slurmctld and slurmd from Debian's slurm-wlm (22.05) and munge, with a generated minimal
# configuration in STATE (no systemd, no cgroups: proctrack/linuxproc, task/none), as root.
#
#   scripts/slurm/local-cluster.sh start STATE   # prints the line to source: export SLURM_CONF=...
#   scripts/slurm/local-cluster.sh stop STATE    # stops the daemons and removes STATE
#
# Clients (sbatch, squeue, scontrol, scancel) find this cluster through SLURM_CONF. The ports
# (BT_SLURM_PORT, default 16817, and the next one) stay off Slurm's defaults, so a real
# slurmd on the machine is not disturbed.
set -euo pipefail

command=${1:?usage: local-cluster.sh start|stop STATE}
state=${2:?usage: local-cluster.sh start|stop STATE}
port=${BT_SLURM_PORT:-16817}

stop_daemon() { # pid file; the daemon gets 10 s to leave after SIGTERM
  [[ -f "$1" ]] || return 0
  local pid
  pid=$(cat "$1")
  kill "$pid" 2>/dev/null || return 0
  for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || return 0; sleep 0.1; done
  kill -9 "$pid" 2>/dev/null || true
}

if [[ "$command" == stop ]]; then
  stop_daemon "$state/slurmd.pid"
  stop_daemon "$state/slurmctld.pid"
  stop_daemon "$state/munge/munged.pid"
  rm -rf "$state"
  exit 0
fi
[[ "$command" == start ]] || { echo "local-cluster.sh: unknown command '$command' (start|stop)" >&2; exit 2; }

for tool in munged slurmctld slurmd sbatch; do
  command -v "$tool" >/dev/null || [[ -x /usr/sbin/$tool ]] ||
    { echo "local-cluster.sh: $tool not found (apt-get install slurm-wlm munge)" >&2; exit 3; }
done
[[ $(id -u) -eq 0 ]] || { echo "local-cluster.sh: run as root (slurmd starts jobs as their users)" >&2; exit 3; }
PATH=/usr/sbin:$PATH

mkdir -p "$state/munge" "$state/ctld" "$state/spool"
state=$(cd "$state" && pwd)
chmod 700 "$state/munge"
dd if=/dev/urandom of="$state/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$state/munge/munge.key"
timeout 30 munged --key-file="$state/munge/munge.key" --socket="$state/munge/munge.socket" --pid-file="$state/munge/munged.pid" \
  --log-file="$state/munge/munged.log" --seed-file="$state/munge/munged.seed" --force

host=$(hostname -s)
cpus=$(nproc)
memory=$(awk '/MemTotal/ { print int($2 / 1024 / 2) }' /proc/meminfo) # half: the node is shared
cat > "$state/slurm.conf" <<CONF
ClusterName=brushtrace-test
SlurmctldHost=$host
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$state/munge/munge.socket
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/spool
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
SlurmctldLogFile=$state/slurmctld.log
SlurmdLogFile=$state/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
JobRequeue=1
SchedulerParameters=defer_batch
MinJobAge=600
KillWait=5
NodeName=$host CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=batch Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$state/slurm.conf
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"

# Ready when the node takes jobs.
for _ in $(seq 150); do
  if sinfo -h -o %t 2>/dev/null | grep -qE '^(idle|mix|alloc)'; then
    echo "export SLURM_CONF=$SLURM_CONF"
    exit 0
  fi
  sleep 0.2
done
echo "local-cluster.sh: the node did not come up; see $state/slurmctld.log and $state/slurmd.log" >&2
sinfo >&2 || true
exit 1
