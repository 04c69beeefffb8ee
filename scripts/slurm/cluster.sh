#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, for flapwing's cluster test and for trying
# `flapwing submit` locally. Needs root (it installs packages and runs the daemons as root).
#
#   scripts/slurm/cluster.sh install   # apt-get install slurm-wlm munge, when missing
#   scripts/slurm/cluster.sh start     # munged, slurmctld, slurmd; waits until the node is idle
#   scripts/slurm/cluster.sh stop      # stops what `start` started, by PID
#   scripts/slurm/cluster.sh env       # prints `export SLURM_CONF=...` for sbatch, squeue, sinfo
#
# Everything lives under $FLAPWING_SLURM_DIR (default /tmp/flapwing-slurm): slurm.conf, the
# controller's state, slurmd's spool, logs and PID files. The client commands find the cluster
# through SLURM_CONF, so nothing is written to /etc/slurm. Settings that matter on a VM or
# container without systemd: ProctrackType=proctrack/linuxproc and TaskPlugin=task/none (with
# cgroup tracking a job here "completes" without having run), ReturnToService=2, no accounting
# database (sacct then reports that accounting is disabled, and `flapwing status` says so).
set -euo pipefail

dir="${FLAPWING_SLURM_DIR:-/tmp/flapwing-slurm}"
conf="$dir/slurm.conf"

log() { printf 'cluster: %s\n' "$*" >&2; }

install_packages() {
    local need=()
    command -v slurmctld >/dev/null || need+=(slurm-wlm)
    command -v munged >/dev/null || need+=(munge)
    command -v sbatch >/dev/null || need+=(slurm-client)
    if ((${#need[@]} == 0)); then
        log "slurm-wlm and munge are installed"
        return
    fi
    if [[ $(id -u) != 0 ]]; then
        log "need root to install ${need[*]} (apt-get)"
        exit 1
    fi
    log "installing ${need[*]} (apt-get)"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
}

pid_alive() { [[ -f $1 ]] && kill -0 "$(cat "$1")" 2>/dev/null; }

write_conf() {
    local host node
    host=$(hostname -s)
    # The node line as slurmd itself detects it (CPUs, sockets, cores, threads), without the
    # memory figure, which drifts and would drain the node if it came out larger than found.
    node=$(slurmd -C | head -n 1 | sed -E 's/ RealMemory=[0-9]+//')
    [[ $node == NodeName=* ]] || node="NodeName=$host CPUs=$(nproc)"
    cat >"$conf" <<EOF
# Written by scripts/slurm/cluster.sh: a single-node cluster on $host.
ClusterName=flapwing
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MinJobAge=600
SlurmctldPort=6817
SlurmdPort=6818
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmdSpoolDir=$dir/slurmd
StateSaveLocation=$dir/state
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
$node State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
}

start_munge() {
    if pid_alive /run/munge/munged.pid; then
        log "munged is already running (pid $(cat /run/munge/munged.pid)); using it"
        return
    fi
    install -d -o munge -g munge -m 0755 /run/munge
    install -d -o munge -g munge -m 0700 /etc/munge /var/lib/munge /var/log/munge
    if [[ ! -s /etc/munge/munge.key ]]; then
        if command -v mungekey >/dev/null; then
            mungekey --create --keyfile=/etc/munge/munge.key
        else
            dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 status=none
        fi
    fi
    chown munge:munge /etc/munge/munge.key
    chmod 0400 /etc/munge/munge.key
    runuser -u munge -- /usr/sbin/munged
    # Ours to stop: remember the PID.
    for _ in $(seq 50); do
        pid_alive /run/munge/munged.pid && break
        sleep 0.1
    done
    cp /run/munge/munged.pid "$dir/munged.pid"
    log "munged started (pid $(cat "$dir/munged.pid"))"
}

start() {
    install_packages
    stop quiet
    rm -rf "$dir/state" "$dir/slurmd"
    mkdir -p "$dir/state" "$dir/slurmd"
    write_conf
    start_munge
    export SLURM_CONF="$conf"
    if timeout 5 sinfo -h >/dev/null 2>&1; then
        log "a Slurm controller already answers on this host's port 6817 (another cluster.sh start? stop it with FLAPWING_SLURM_DIR=<its dir> $0 stop)"
        exit 1
    fi
    /usr/sbin/slurmctld -f "$conf"
    /usr/sbin/slurmd -f "$conf"
    local host state=""
    host=$(hostname -s)
    for _ in $(seq 120); do
        state=$(sinfo -h -n "$host" -o %t 2>/dev/null || true)
        [[ $state == idle ]] && break
        sleep 0.5
    done
    if [[ $state != idle ]]; then
        log "node $host is '$state', not idle, after 60 s; logs in $dir:"
        tail -n 20 "$dir/slurmctld.log" "$dir/slurmd.log" >&2 || true
        exit 1
    fi
    log "node $host idle (slurm.conf: $conf; export SLURM_CONF=$conf)"
}

stop() {
    local f pid
    for f in "$dir/slurmd.pid" "$dir/slurmctld.pid" "$dir/munged.pid"; do
        if pid_alive "$f"; then
            pid=$(cat "$f")
            kill "$pid"
            for _ in $(seq 50); do
                kill -0 "$pid" 2>/dev/null || break
                sleep 0.1
            done
            kill -0 "$pid" 2>/dev/null && kill -9 "$pid"
            [[ ${1:-} == quiet ]] || log "stopped $(basename "$f" .pid) (pid $pid)"
        fi
        rm -f "$f"
    done
}

mkdir -p "$dir"
case "${1:-}" in
    install) install_packages ;;
    start) start ;;
    stop) stop ;;
    env) echo "export SLURM_CONF=$conf" ;;
    *)
        echo "usage: $0 install|start|stop|env" >&2
        exit 2
        ;;
esac
