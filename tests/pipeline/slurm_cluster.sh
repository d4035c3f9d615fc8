# A private single-node Slurm cluster on localhost for tests, sourced by slurm_test.sh:
# its own munge key and munged, a slurm.conf with state, spool, logs and sockets in one folder,
# slurmctld and slurmd on free ports, all run as root in the foreground of this shell's children
# so that they are stopped by their process ids. No cgroups, systemd or system service is used
# (proctrack/linuxproc, task/none), so it runs in a container.
#   slurm_cluster_missing                 prints what this machine lacks for it (nothing: ready)
#   slurm_cluster_start DIR               starts it; exports SLURM_CONF for sbatch & co. Every folder
#                                         above DIR must be traversable by all (munged checks)
#   slurm_cluster_stop                    cancels its jobs and stops the daemons (idempotent)
#   slurm_cluster_leftovers DIR           prints the daemons of DIR still running (none: stopped)

slurm_cluster_pids=()
slurm_cluster_dir=""
# Each daemon runs under `timeout`, so that one whose test was killed outright (no trap runs on
# SIGKILL) still ends; TERM to the timeout process reaches the daemon.
# (A prefix, not a function: `function &` would fork a subshell and $! would not be the daemon's.)
SLURM_CLUSTER_LIFETIME_S=${SLURM_CLUSTER_LIFETIME_S:-1200}
_slurm_bounded=(timeout --kill-after=10 "$SLURM_CLUSTER_LIFETIME_S")

slurm_cluster_missing() {
  local tool
  for tool in munged munge slurmctld slurmd sbatch scontrol sinfo squeue scancel; do
    command -v "$tool" > /dev/null || { echo "$tool not found (Debian packages slurm-wlm and munge, scripts/debian-packages.txt)"; return; }
  done
  [[ "$(id -u)" == 0 ]] || echo "not root: slurmd must be root to start jobs as their owner"
}

# Waits up to $2 seconds for the command $3... to succeed; says what it waited for ($1) otherwise.
_slurm_cluster_wait() {
  local what=$1 seconds=$2 deadline
  shift 2
  deadline=$((SECONDS + seconds))
  until "$@" > /dev/null 2>&1; do
    if ((SECONDS >= deadline)); then
      echo "slurm_cluster: $what not ready after ${seconds} s" >&2
      return 1
    fi
    sleep 0.5
  done
}

_slurm_node_idle() { [[ "$(sinfo -h -n flnode -o %t 2> /dev/null)" == idle ]]; }
_slurm_ctld_up() { scontrol ping 2> /dev/null | grep -q UP; }

# Two ports nobody listens on (the daemons fail to start if one is taken in between; the start
# is then retried with other ports).
_slurm_free_ports() {
  local base
  for _ in $(seq 50); do
    base=$((20000 + RANDOM % 30000))
    # Without ss (iproute2) the ports are taken unchecked.
    if ! command -v ss > /dev/null || ! ss -Htln | awk '{print $4}' | grep -qE ":($base|$((base + 1)))\$"; then
      echo "$base $((base + 1))"
      return 0
    fi
  done
  return 1
}

_slurm_write_conf() {
  local dir=$1 ctld_port=$2 slurmd_port=$3 cpus mem_mib
  cpus=$(nproc)
  # Half the machine's memory: slurmd refuses a node whose configured memory exceeds what it finds.
  mem_mib=$(($(awk '/^MemTotal:/ {print $2}' /proc/meminfo) / 1024 / 2))
  cat > "$dir/slurm.conf" <<EOF
ClusterName=firelooktest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/run/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
NodeName=flnode NodeHostname=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mib State=UNKNOWN
PartitionName=firelook Nodes=flnode Default=YES MaxTime=INFINITE State=UP
EOF
}

_slurm_cluster_try_start() {
  local dir=$1 ports
  ports=$(_slurm_free_ports) || { echo "slurm_cluster: no free port pair found" >&2; return 1; }
  rm -rf "$dir/state" "$dir/spool" "$dir/log"
  mkdir -p "$dir/state" "$dir/spool" "$dir/log"
  # shellcheck disable=SC2086
  _slurm_write_conf "$dir" $ports
  export SLURM_CONF="$dir/slurm.conf"
  "${_slurm_bounded[@]}" slurmctld -D -f "$SLURM_CONF" > "$dir/log/slurmctld.out" 2>&1 &
  slurm_cluster_pids+=($!)
  _slurm_cluster_wait "slurmctld (ports $ports, log $dir/log/slurmctld.log)" 60 _slurm_ctld_up || return 1
  "${_slurm_bounded[@]}" slurmd -D -f "$SLURM_CONF" -N flnode > "$dir/log/slurmd.out" 2>&1 &
  slurm_cluster_pids+=($!)
  _slurm_cluster_wait "slurmd's node flnode (log $dir/log/slurmd.log)" 60 _slurm_node_idle || return 1
}

slurm_cluster_start() {
  local dir=$1 attempt
  slurm_cluster_dir=$dir
  mkdir -p "$dir/munge" "$dir/run"
  # munged insists on a private key and a socket folder everyone can traverse.
  chmod 755 "$dir" "$dir/run"
  chmod 700 "$dir/munge"
  head -c 1024 /dev/urandom > "$dir/munge/munge.key"
  chmod 400 "$dir/munge/munge.key"
  "${_slurm_bounded[@]}" munged -F --key-file="$dir/munge/munge.key" --socket="$dir/run/munge.socket" --pid-file="$dir/run/munged.pid" \
    --seed-file="$dir/munge/seed" --log-file="$dir/munge/munged.log" > "$dir/munge/munged.out" 2>&1 &
  slurm_cluster_pids+=($!)
  _slurm_cluster_wait "munged" 30 munge -S "$dir/run/munge.socket" -n ||
    { tail -n 3 "$dir/munge/munged.out" >&2; return 1; }
  for attempt in 1 2 3; do
    if _slurm_cluster_try_start "$dir"; then return 0; fi
    echo "slurm_cluster: start attempt $attempt failed; last log lines:" >&2
    tail -n 5 "$dir/log/slurmctld.log" "$dir/log/slurmd.log" "$dir/log/slurmctld.out" "$dir/log/slurmd.out" >&2 2> /dev/null || true
    _slurm_cluster_stop_daemons 1
  done
  return 1
}

# Stops the daemons started by this shell, all but the first $1 (munged) or all of them.
_slurm_cluster_stop_daemons() {
  local keep=${1:-0} i pid deadline
  for ((i = ${#slurm_cluster_pids[@]} - 1; i >= keep; --i)); do
    pid=${slurm_cluster_pids[i]}
    kill -TERM "$pid" 2> /dev/null || true
    deadline=$((SECONDS + 15))
    while kill -0 "$pid" 2> /dev/null && ((SECONDS < deadline)); do sleep 0.2; done
    kill -KILL "$pid" 2> /dev/null || true
    wait "$pid" 2> /dev/null || true
  done
  slurm_cluster_pids=("${slurm_cluster_pids[@]:0:keep}")
}

slurm_cluster_stop() {
  [[ -n "$slurm_cluster_dir" ]] || return 0
  if ((${#slurm_cluster_pids[@]} > 1)); then
    # Jobs first, so that no bake still writes into the folder when it is removed.
    timeout 15 scancel --full --user=root > /dev/null 2>&1 || true
    _slurm_cluster_wait "the cancelled jobs to end" 20 bash -c '[[ -z "$(squeue -h 2> /dev/null)" ]]' || true
  fi
  _slurm_cluster_stop_daemons 0
  slurm_cluster_dir=""
}

# The daemons' own pid files name any of them still running (none after slurm_cluster_stop).
slurm_cluster_leftovers() {
  local dir=$1 file pid
  for file in "$dir"/run/munged.pid "$dir"/run/slurmctld.pid "$dir"/run/slurmd.pid; do
    [[ -f "$file" ]] || continue
    pid=$(cat "$file")
    if [[ -n "$pid" ]] && kill -0 "$pid" 2> /dev/null; then echo "$(basename "$file" .pid) (pid $pid)"; fi
  done
}
