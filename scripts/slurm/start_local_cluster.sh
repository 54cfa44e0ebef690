#!/usr/bin/env bash
# Configures and starts a single-node Slurm cluster on this machine (munged, slurmctld, slurmd),
# for tests of `runner submit --slurm`. Installs nothing: slurm-wlm and munge come from
# scripts/install_deps.sh --with-slurm. Run as root. Idempotent: an already running cluster is left alone.
#   scripts/slurm/start_local_cluster.sh          # start (about 20 s)
#   scripts/slurm/start_local_cluster.sh --stop   # stop the daemons (slurmd, slurmctld, munged)
set -euo pipefail

if [[ $(id -u) -ne 0 ]]; then
  echo "start_local_cluster.sh: must run as root" >&2
  exit 1
fi
for b in munged slurmctld slurmd sinfo; do
  command -v "$b" >/dev/null || { echo "start_local_cluster.sh: $b not found (apt-get install slurm-wlm munge)" >&2; exit 1; }
done

if [[ "${1:-}" == "--stop" ]]; then
  pids=()
  for f in /run/slurmd.pid /run/slurmctld.pid /run/munge/munged.pid; do
    if [[ -f $f ]] && p=$(cat "$f") && kill "$p" 2>/dev/null; then pids+=("$p"); fi
  done
  # Wait (up to 10 s) until they are gone, so that the caller's next step sees no daemon.
  for _ in $(seq 100); do
    alive=0
    for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null && alive=1; done
    [[ $alive == 0 ]] && break
    sleep 0.1
  done
  exit 0
fi

HOST=$(hostname -s)
CPUS=$(nproc)
MEM_MB=$(awk '/MemTotal/ { printf "%d", $2 / 1024 * 0.8 }' /proc/meminfo)

# munge: a key, its directories, the daemon.
mkdir -p /etc/munge /var/lib/munge /var/log/munge /run/munge
if [[ ! -s /etc/munge/munge.key ]]; then
  if command -v mungekey >/dev/null; then mungekey --create --keyfile=/etc/munge/munge.key --force
  else dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key status=none; fi
fi
chown -R munge:munge /etc/munge /var/lib/munge /var/log/munge /run/munge
chmod 0700 /etc/munge /var/lib/munge /var/log/munge
chmod 0755 /run/munge
chmod 0400 /etc/munge/munge.key
if ! munge -n </dev/null 2>/dev/null | unmunge >/dev/null 2>&1; then
  runuser -u munge -- /usr/sbin/munged
  for _ in $(seq 50); do munge -n </dev/null 2>/dev/null | unmunge >/dev/null 2>&1 && break; sleep 0.1; done
fi

# Slurm configuration: one node (this host), one partition.
mkdir -p /etc/slurm /var/spool/slurmctld /var/spool/slurmd /var/log/slurm
cat > /etc/slurm/slurm.conf <<CONF
# Single-node test cluster written by scripts/slurm/start_local_cluster.sh
ClusterName=sphlocal
SlurmctldHost=${HOST}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MaxArraySize=100001
MinJobAge=300
SchedulerParameters=defer_batch
NodeName=${HOST} CPUs=${CPUS} RealMemory=${MEM_MB} State=UNKNOWN
PartitionName=debug Nodes=${HOST} Default=YES MaxTime=INFINITE State=UP OverSubscribe=YES
CONF
# cgroup.conf keeps slurmd from probing cgroups it does not need with these plugins.
cat > /etc/slurm/cgroup.conf <<CONF
CgroupPlugin=autodetect
IgnoreSystemd=yes
CONF

if ! scontrol ping 2>/dev/null | grep -q "UP"; then
  slurmctld
fi
if ! { [[ -f /run/slurmd.pid ]] && kill -0 "$(cat /run/slurmd.pid)" 2>/dev/null; }; then
  slurmd
fi

# Wait until the node accepts work.
for _ in $(seq 120); do
  state=$(sinfo -h -n "$HOST" -o %T 2>/dev/null | head -1 || true)
  case "$state" in
    idle*|mixed*|allocated*) echo "Slurm up: node $HOST ($CPUS CPUs) $state"; exit 0 ;;
    down*|drain*) scontrol update nodename="$HOST" state=resume 2>/dev/null || true ;;
  esac
  sleep 0.5
done
echo "start_local_cluster.sh: the node did not become idle; see /var/log/slurm/" >&2
sinfo >&2 || true
tail -20 /var/log/slurm/slurmctld.log /var/log/slurm/slurmd.log >&2 || true
exit 1
