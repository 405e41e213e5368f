#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for the tests of the cluster path (scripts/slurm/).
#
#   scripts/slurm/local-cluster.sh start   # install (Debian's Slurm 22.05 + munge) and start it
#   scripts/slurm/local-cluster.sh stop    # stop the daemons this script started, nothing else
#   scripts/slurm/local-cluster.sh conf    # print the SLURM_CONF path the clients need
#   scripts/slurm/local-cluster.sh status  # exit 0 when it is up (its controller and node answer)
#
# Everything lives in its own folder, $SPINE_SLURM_HOME (default /var/tmp/spine-slurm): its own
# slurm.conf (clients use it through SLURM_CONF), state, spool, logs and pid files, and its own
# ports (16817, 16818), so a machine's own Slurm, if it has one, is neither read nor touched.
# Idempotent: daemons already answering are left as they are. `start` needs root (or sudo) to
# install packages and run slurmd; it exits 77 with the reason where that is not possible, which
# the tests report as a skip. `stop` stops only the daemons whose pid this script recorded.
set -euo pipefail
home="${SPINE_SLURM_HOME:-/var/tmp/spine-slurm}"
conf="$home/slurm.conf"
started="$home/started" # one daemon name per line: what `stop` may stop

skip() {
  echo "local-cluster: cannot start a one-node Slurm here: $*" >&2
  exit 77
}

sudo_cmd() {
  if [ "$(id -u)" -eq 0 ]; then
    "$@"
  elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
    sudo -n "$@"
  else
    return 1
  fi
}

munge_answers() { munge -n 2>/dev/null | unmunge >/dev/null 2>&1; }
ctld_answers() { SLURM_CONF="$conf" timeout 5 scontrol ping 2>/dev/null | grep -q "is UP"; }
node_ready() {
  SLURM_CONF="$conf" timeout 5 sinfo -h -N -o "%T" 2>/dev/null | grep -qE "^(idle|mixed|allocated)"
}

start() {
  [ "$(id -u)" -eq 0 ] || skip "it must run as root (the daemons of a one-node cluster, and apt-get)"
  local pkgs=() p
  for p in slurmctld slurmd slurm-client munge; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || pkgs+=("$p")
  done
  if [ ${#pkgs[@]} -gt 0 ]; then
    echo "local-cluster: installing Debian packages: ${pkgs[*]}"
    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${pkgs[@]}" >/dev/null; } ||
      skip "apt-get could not install ${pkgs[*]}"
  fi
  mkdir -p "$home"/state "$home"/spool "$home"/log
  touch "$started"
  # Debian's Slurm packages start nothing where there is no systemd; their unit may have, where
  # there is: only our own ports and conf are used here, so the two do not meet.
  if ! munge_answers; then
    [ -s /etc/munge/munge.key ] || { mungekey --create --keyfile=/etc/munge/munge.key && chown munge:munge /etc/munge/munge.key; }
    mkdir -p /run/munge && chown munge:munge /run/munge
    runuser -u munge -- /usr/sbin/munged --pid-file=/run/munge/munged.pid || skip "munged did not start"
    echo munged >>"$started"
    for _ in $(seq 50); do munge_answers && break; sleep 0.1; done
    munge_answers || skip "munged does not answer"
  fi
  local host cpus mem
  host="$(hostname -s)"
  cpus="$(nproc)"
  mem="$(slurmd -C | sed -n 's/.*RealMemory=\([0-9]*\).*/\1/p')"
  cat >"$conf.tmp" <<EOF
# A one-node cluster for the tests of the workspace's cluster path (scripts/slurm/local-cluster.sh).
ClusterName=spine-local
SlurmctldHost=$host
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
AuthType=auth/munge
StateSaveLocation=$home/state
SlurmdSpoolDir=$home/spool
SlurmctldPidFile=$home/slurmctld.pid
SlurmdPidFile=$home/slurmd.pid
SlurmctldLogFile=$home/log/slurmctld.log
SlurmdLogFile=$home/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
SchedulerParameters=sched_min_interval=0,bf_interval=1
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
MinJobAge=600
NodeName=$host CPUs=$cpus RealMemory=${mem:-1000} State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  mv "$conf.tmp" "$conf"
  if ! ctld_answers; then
    slurmctld -f "$conf" || skip "slurmctld did not start (see $home/log/slurmctld.log)"
    echo slurmctld >>"$started"
    for _ in $(seq 100); do ctld_answers && break; sleep 0.1; done
    ctld_answers || skip "slurmctld does not answer (see $home/log/slurmctld.log)"
  fi
  if ! node_ready; then
    if ! pgrep -F "$home/slurmd.pid" slurmd >/dev/null 2>&1; then
      slurmd -f "$conf" || skip "slurmd did not start (see $home/log/slurmd.log)"
      echo slurmd >>"$started"
    fi
    for _ in $(seq 300); do node_ready && break; sleep 0.2; done
    node_ready || skip "the node did not come up (see $home/log/slurmd.log)"
  fi
  echo "local-cluster: one-node Slurm up on $host ($cpus CPUs); clients: export SLURM_CONF=$conf"
}

stop() {
  [ -f "$started" ] || return 0
  local name pidfile
  # Last started, first stopped.
  for name in $(tac "$started" | awk '!seen[$0]++'); do
    case "$name" in
      slurmd) pidfile="$home/slurmd.pid" ;;
      slurmctld) pidfile="$home/slurmctld.pid" ;;
      munged) pidfile=/run/munge/munged.pid ;;
      *) continue ;;
    esac
    if [ -s "$pidfile" ] && pgrep -F "$pidfile" "$name" >/dev/null 2>&1; then
      kill "$(cat "$pidfile")" 2>/dev/null || true
      for _ in $(seq 50); do pgrep -F "$pidfile" "$name" >/dev/null 2>&1 || break; sleep 0.1; done
    fi
  done
  : >"$started"
  echo "local-cluster: stopped what it had started"
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  conf) echo "$conf" ;;
  status) [ -f "$conf" ] && ctld_answers && node_ready ;;
  *)
    echo "usage: $0 start|stop|conf|status" >&2
    exit 2
    ;;
esac
