#!/usr/bin/env bash
# A one-node Slurm cluster for the batch tests: munged, slurmctld and slurmd on this machine,
# with the configuration, state, sockets and logs in one folder.
#   tests/batch/slurm_cluster.sh start DIR   configure and start; prints SLURM_CONF=DIR/slurm.conf once
#                                          the node is idle (exit 0), or why it cannot start (exit 1)
#   tests/batch/slurm_cluster.sh stop DIR    stop the daemons started in DIR
# Needs Debian's slurmctld, slurmd, slurm-client and munge, and root (slurmd starts the tasks
# as their user). Nothing outside DIR is written.
set -uo pipefail

cmd="${1:-}"
dir="${2:-}"
[ -n "$cmd" ] && [ -n "$dir" ] || { echo "usage: $0 start|stop DIR" >&2; exit 2; }

fail() { echo "slurm test cluster: $*" >&2; exit 1; }

stop() {
  [ -f "$dir/pids" ] || return 0
  while read -r pid name; do
    kill "$pid" 2>/dev/null
  done < "$dir/pids"
  for _ in $(seq 50); do
    alive=0
    while read -r pid name; do kill -0 "$pid" 2>/dev/null && alive=1; done < "$dir/pids"
    [ $alive -eq 0 ] && break
    sleep 0.1
  done
  while read -r pid name; do kill -9 "$pid" 2>/dev/null; done < "$dir/pids"
  rm -f "$dir/pids"
}

if [ "$cmd" = stop ]; then stop; exit 0; fi
[ "$cmd" = start ] || { echo "usage: $0 start|stop DIR" >&2; exit 2; }

for tool in munged mungekey slurmctld slurmd sbatch squeue sinfo scontrol; do
  command -v "$tool" >/dev/null 2>&1 || [ -x "/usr/sbin/$tool" ] ||
    fail "$tool is not installed (Debian: apt-get install slurmctld slurmd slurm-client munge)"
done
export PATH="$PATH:/usr/sbin"
[ "$(id -u)" -eq 0 ] || fail "needs root: slurmd starts each task as the user who submitted it"

mkdir -p "$dir" && dir="$(cd "$dir" && pwd)" || fail "cannot create $dir"
mkdir -p "$dir/munge" "$dir/state" "$dir/spool" "$dir/log"
chmod 700 "$dir" "$dir/munge"
: > "$dir/pids"

# munge: a key of its own, its socket in DIR.
mungekey --create --keyfile="$dir/munge/munge.key" --force 2>"$dir/log/mungekey.err" ||
  fail "mungekey cannot create a key: $(tail -n1 "$dir/log/mungekey.err")"
chmod 600 "$dir/munge/munge.key"
munged --foreground --force --socket="$dir/munge/munge.socket" --key-file="$dir/munge/munge.key" \
  --pid-file="$dir/munge/munged.pid" --log-file="$dir/log/munged.log" --seed-file="$dir/munge/munged.seed" \
  >"$dir/log/munged.out" 2>&1 &
echo "$! munged" >> "$dir/pids"
for _ in $(seq 50); do [ -S "$dir/munge/munge.socket" ] && break; sleep 0.1; done
[ -S "$dir/munge/munge.socket" ] || { stop; fail "munged did not start: $(tail -n2 "$dir/log/munged.log" "$dir/log/munged.out" 2>/dev/null | tr '\n' ' ')"; }

# Two free TCP ports, so that clusters of parallel test runs do not meet.
port_free() { ! grep -qi ":$(printf '%04X' "$1") " /proc/net/tcp /proc/net/tcp6 2>/dev/null; }
pick_port() {
  local p
  for _ in $(seq 100); do
    p=$((20000 + RANDOM % 20000))
    port_free "$p" && port_free "$((p + 1))" && { echo "$p"; return; }
  done
  echo 26817
}
port=$(pick_port)
host=$(hostname -s)
cpus=$(nproc)
mem=$(awk '/MemAvailable/ { printf "%d", $2 / 1024 / 2 }' /proc/meminfo)
[ "${mem:-0}" -gt 512 ] || mem=512

cat > "$dir/slurm.conf" <<EOF
# A one-node test cluster written by tests/batch/slurm_cluster.sh.
ClusterName=cmtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
SlurmdParameters=config_overrides
SchedulerParameters=sched_interval=1
MessageTimeout=20
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$dir/slurm.conf"

slurmctld -D -i -f "$SLURM_CONF" >"$dir/log/slurmctld.out" 2>&1 &
echo "$! slurmctld" >> "$dir/pids"
slurmd -D -f "$SLURM_CONF" -N "$host" >"$dir/log/slurmd.out" 2>&1 &
echo "$! slurmd" >> "$dir/pids"

for _ in $(seq 150); do
  state=$(sinfo --noheader --nodes="$host" --format=%T 2>/dev/null | head -n1)
  [ "$state" = idle ] && { echo "SLURM_CONF=$SLURM_CONF"; exit 0; }
  while read -r pid name; do
    kill -0 "$pid" 2>/dev/null || {
      why=$(tail -n3 "$dir/log/$name.log" "$dir/log/$name.out" 2>/dev/null | grep -v '^==>' | grep -v '^$' | tail -n2 | tr '\n' ' ')
      stop
      fail "$name exited: $why"
    }
  done < "$dir/pids"
  sleep 0.2
done
why=$(tail -n2 "$dir/log/slurmd.log" 2>/dev/null | tr '\n' ' ')
stop
fail "the node did not become idle within 30 s (state: ${state:-unknown}); slurmd says: $why"
