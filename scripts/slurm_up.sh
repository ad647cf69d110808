#!/usr/bin/env bash
# Starts a two-node Slurm on this machine for the farm tests
# (docs/farm.md): Debian's slurm-wlm and munge, a munge key, munged, a
# slurm.conf naming two nodes, node1 and node2, on this host (each its
# own slurmd on its own port, `slurmd -N`, sharing the CPUs, half the
# memory each; a partition `debug` without a time limit and one
# `short` of 10 minutes), slurmctld and the two slurmd. Exits 0 once `sinfo` shows
# both nodes idle; 1 (saying why) when Slurm cannot start here. Needs
# root; installs the packages if missing.
set -euo pipefail
say() { echo "slurm_up: $*" >&2; }
if ! command -v slurmctld >/dev/null 2>&1 || ! command -v munged >/dev/null 2>&1; then
  (apt-get update && apt-get install -y --no-install-recommends slurm-wlm munge) >/dev/null 2>&1 \
    || { say "cannot install slurm-wlm and munge"; exit 1; }
fi
host=$(hostname -s)
cpus=$(nproc)
mem=$(( ($(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 - 512) / 2 ))
nodes=(node1 node2)
conf=/etc/slurm/slurm.conf
mkdir -p /etc/slurm /var/spool/slurmctld /var/spool/slurmd/node1 /var/spool/slurmd/node2 /var/log/slurm /run/munge /var/lib/munge /var/log/munge /etc/munge
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
SlurmdSpoolDir=/var/spool/slurmd/%n
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd-%n.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd-%n.log
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
NodeName=node1 NodeHostname=$host Port=17001 CPUs=$cpus RealMemory=$mem State=UNKNOWN
NodeName=node2 NodeHostname=$host Port=17002 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=node1,node2 Default=YES MaxTime=INFINITE State=UP
PartitionName=short Nodes=node1,node2 MaxTime=00:10:00 State=UP
CONF
pgrep -x slurmctld >/dev/null || slurmctld || { say "slurmctld does not start"; exit 1; }
for n in "${nodes[@]}"; do
  pgrep -f "slurmd -N $n\$" >/dev/null || slurmd -N "$n" || { say "slurmd of $n does not start"; exit 1; }
done
for _ in $(seq 1 30); do
  if [ "$(sinfo -h -N -o '%T' 2>/dev/null | grep -cx idle)" -eq ${#nodes[@]} ]; then
    say "nodes ${nodes[*]} idle on $host ($cpus CPUs, $mem MB each)"
    exit 0
  fi
  for n in "${nodes[@]}"; do
    scontrol update nodename="$n" state=resume >/dev/null 2>&1 || true
  done
  sleep 1
done
say "the node does not come up: $(sinfo 2>&1 | tail -1)"
exit 1
