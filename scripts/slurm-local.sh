#!/usr/bin/env bash
# A real single-node Slurm on this machine, for the `slurm` tests and for trying
# `mopad suite slurm` locally (docs/suites.md, "Slurm"). No systemd, nothing in /etc changed:
# munged, slurmctld and slurmd run as root (munged as user munge) from a configuration generated in
# a folder of their own, and are stopped by the PIDs in their pid files.
#
#   scripts/slurm-local.sh start [DIR]   generate DIR (default: a new temporary folder), start the
#                                        three daemons, wait until the node is idle, print
#                                        `export SLURM_CONF=DIR/slurm.conf` (the clients'
#                                        configuration) on stdout
#   scripts/slurm-local.sh stop [DIR]    stop the daemons of DIR (default: the last started
#                                        without DIR)
#   scripts/slurm-local.sh status [DIR]  the daemons' PIDs and `sinfo`; exit 0 when all three run
#
# Needs root and Debian 12's `slurm-wlm slurmctld slurmd slurm-client munge`
# (scripts/install-deps.sh --test). Exit codes: 0 done, 1 a daemon failed (its log is printed),
# 2 usage, 4 Slurm or munge not installed or not root (callers such as the `slurm` test skip on 4).
set -euo pipefail

readonly kLast="${TMPDIR:-/tmp}/mopad-slurm-local.last"  # the last `start` without DIR
readonly kIdleTimeout=60  # s: how long `start` waits for the node to report idle

die() { echo "slurm-local: error: $*" >&2; exit "${2:-1}"; }
usage() { sed -n '7,14p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }

cmd="${1:-}"
[[ "$cmd" == start || "$cmd" == stop || "$cmd" == status ]] || usage
dir="${2:-}"

# The folder a command acts on: the one given, else the last one started.
resolve_dir() {
  if [[ -z "$dir" ]]; then
    [[ -f "$kLast" ]] || die "no folder given and no local Slurm started (no $kLast)" 2
    dir="$(cat "$kLast")"
  fi
  [[ -f "$dir/slurm.conf" ]] || die "$dir/slurm.conf: no local Slurm configuration there" 2
}

# PID from a pid file when that process is alive, else nothing.
live_pid() {
  local f="$1" pid
  [[ -s "$f" ]] || return 0
  pid="$(tr -dc '0-9' < "$f")"
  [[ -n "$pid" ]] && kill -0 "$pid" 2>/dev/null && echo "$pid"
  return 0
}

pid_files() { echo "$dir/slurmd.pid $dir/slurmctld.pid $dir/munge/munged.pid"; }

stop_daemons() {
  local f pid i
  for f in $(pid_files); do
    pid="$(live_pid "$f")"
    [[ -n "$pid" ]] || continue
    kill "$pid" 2>/dev/null || true
    for ((i = 0; i < 50; ++i)); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -0 "$pid" 2>/dev/null && kill -9 "$pid" 2>/dev/null || true
  done
  return 0
}

# True when something listens on TCP port $1 of localhost.
port_busy() { (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }

write_conf() {
  local host cpus port
  host="$(hostname -s)"
  cpus="$(nproc)"
  # Slurm's ports (6817 slurmctld, 6818 slurmd) unless taken, e.g. by another local Slurm.
  for ((port = 6817; port < 7817; port += 10)); do
    port_busy "$port" || port_busy "$((port + 1))" || break
  done
  # The configuration seen working on Debian 12 (../shared/PITFALLS.md, "Other"), with munge's
  # socket in DIR (AuthInfo) so that a system munged, if any, is neither used nor disturbed.
  cat > "$dir/slurm.conf" <<EOF
ClusterName=mopadlocal
SlurmctldHost=${host}(127.0.0.1)
SlurmctldPort=${port}
SlurmdPort=$((port + 1))
SlurmUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=${dir}/munge/munge.socket.2
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=${dir}/jobcomp.log
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
MailProg=/bin/true
StateSaveLocation=${dir}/state
SlurmdSpoolDir=${dir}/spool
SlurmctldPidFile=${dir}/slurmctld.pid
SlurmdPidFile=${dir}/slurmd.pid
SlurmctldLogFile=${dir}/slurmctld.log
SlurmdLogFile=${dir}/slurmd.log
NodeName=${host} NodeAddr=127.0.0.1 CPUs=${cpus} RealMemory=1000 State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
}

start() {
  [[ $(id -u) -eq 0 ]] || die "needs root (slurmd runs jobs as their user)" 4
  local b
  for b in /usr/sbin/munged /usr/sbin/slurmctld /usr/sbin/slurmd sinfo sbatch; do
    command -v "$b" >/dev/null || die "$b not installed (scripts/install-deps.sh --test)" 4
  done
  [[ -r /etc/munge/munge.key ]] || die "/etc/munge/munge.key missing (reinstall munge)" 4
  if [[ -z "$dir" ]]; then
    dir="$(mktemp -d "${TMPDIR:-/tmp}/mopad-slurm.XXXXXX")"
    echo "$dir" > "$kLast"
  else
    mkdir -p "$dir"
    dir="$(cd "$dir" && pwd)"
    [[ -z "$(live_pid "$dir/slurmctld.pid")" ]] || die "a local Slurm already runs in $dir" 1
  fi
  chmod 755 "$dir"  # munged (user munge) must reach its socket folder
  mkdir -p "$dir/state" "$dir/spool"
  install -d -o munge -g munge -m 755 "$dir/munge"
  runuser -u munge -- test -w "$dir/munge" ||
    die "$dir/munge: user munge cannot reach it (a parent folder closed to others?)"
  write_conf
  export SLURM_CONF="$dir/slurm.conf"

  trap 'stop_daemons' ERR
  runuser -u munge -- /usr/sbin/munged --socket="$dir/munge/munge.socket.2" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" \
    --seed-file="$dir/munge/munged.seed" ||
    { cat "$dir/munge/munged.log" >&2 2>/dev/null; stop_daemons; die "munged did not start"; }
  /usr/sbin/slurmctld || { tail -20 "$dir/slurmctld.log" >&2; stop_daemons; die "slurmctld did not start"; }
  /usr/sbin/slurmd || { tail -20 "$dir/slurmd.log" >&2; stop_daemons; die "slurmd did not start"; }

  local i state=""
  for ((i = 0; i < kIdleTimeout * 5; ++i)); do
    state="$(sinfo -h -o %t 2>/dev/null || true)"
    [[ "$state" == idle ]] && break
    sleep 0.2
  done
  if [[ "$state" != idle ]]; then
    tail -20 "$dir/slurmctld.log" "$dir/slurmd.log" >&2 || true
    stop_daemons
    die "the node did not become idle within ${kIdleTimeout} s (state '${state}')"
  fi
  trap - ERR
  echo "slurm-local: running in $dir (stop with: $0 stop $dir)" >&2
  echo "export SLURM_CONF=$dir/slurm.conf"
}

status() {
  local f pid up=0
  for f in $(pid_files); do
    pid="$(live_pid "$f")"
    echo "$(basename "$f" .pid): ${pid:-not running}"
    [[ -n "$pid" ]] && up=$((up + 1))
  done
  if ((up == 3)); then
    SLURM_CONF="$dir/slurm.conf" sinfo
    return 0
  fi
  return 1
}

case "$cmd" in
  start) start ;;
  stop) resolve_dir; stop_daemons; echo "slurm-local: stopped $dir" >&2 ;;
  status) resolve_dir; status ;;
esac
