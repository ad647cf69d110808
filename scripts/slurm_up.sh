#!/usr/bin/env bash
# Starts a single-node Slurm on this machine for the farm tests
# (docs/farm.md): Debian's slurm-wlm and munge, a munge key, munged, a
# slurm.conf for this host with its CPUs and memory, slurmctld and slurmd.
# Exits 0 once `sinfo` shows the node idle; 1 (saying why) when Slurm
# cannot start here. Needs root; installs the packages if missing.
set -euo pipefail
say() { echo "slurm_up: $*" >&2; }
if ! command -v slurmctld >/dev/null 2>&1 || ! command -v munged >/dev/null 2>&1; then
  (apt-get update && apt-get install -y --no-install-recommends slurm-wlm munge) >/dev/null 2>&1 \
    || { say "cannot install slurm-wlm and munge"; exit 1; }
fi
host=$(hostname -s)
cpus=$(nproc)
mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 - 512 ))
conf=/etc/slurm/slurm.conf
mkdir -p /etc/slurm /var/spool/slurmctld /var/spool/slurmd /var/log/slurm /run/munge /var/lib/munge /var/log/munge /etc/munge
if [ ! -s /etc/munge/munge.key ]; then
  dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 2>/dev/null
fi
chown -R munge:munge /etc/munge /var/lib/munge /var/log/munge /run/munge 2>/dev/null || true
chmod 0700 /etc/munge /var/lib/munge /var/log/munge
chmod 0400 /etc/munge/munge.key
chmod 0755 /run/munge
pgrep -x munged >/dev/null || runuser -u munge -- munged --force || munged --force \
  || { say "munged does not start"; exit 1; }
cat > "$conf" <<CONF
ClusterName=lmfilm
SlurmctldHost=$host
AuthType=auth/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
pgrep -x slurmctld >/dev/null || slurmctld || { say "slurmctld does not start"; exit 1; }
pgrep -x slurmd >/dev/null || slurmd || { say "slurmd does not start"; exit 1; }
for _ in $(seq 1 30); do
  if sinfo -h -o '%T' 2>/dev/null | grep -qx idle; then
    say "node $host idle ($cpus CPUs, $mem MB)"
    exit 0
  fi
  scontrol update nodename="$host" state=resume >/dev/null 2>&1 || true
  sleep 1
done
say "the node does not come up: $(sinfo 2>&1 | tail -1)"
exit 1
