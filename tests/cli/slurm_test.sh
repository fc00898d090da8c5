#!/usr/bin/env bash
# The Slurm job array of examples/slurm on a real, single-node Slurm started here (as root, on
# localhost, with munge): three array tasks of two frames each, every task warming up on the
# frames before its chunk, must write the bytes of one sequential run. Skipped, saying why, where
# Slurm or root is missing (exit 77, ctest's SKIP_RETURN_CODE).
# Usage: slurm_test.sh FRAMEPASS SOURCE_DIR SCRATCH
set -u
source "$(cd "$(dirname "$0")" && pwd)/checks.sh"
FP="$1"; SRC="$2"; DIR="$3/slurm"
for tool in slurmctld slurmd sbatch sinfo munged; do
    command -v "$tool" >/dev/null || { echo "skipped: no $tool (apt-get install slurm-wlm munge)"; exit 77; }
done
[ "$(id -u)" = 0 ] || { echo "skipped: starting a Slurm cluster needs root"; exit 77; }
rm -rf "$DIR"; mkdir -p "$DIR/state" "$DIR/spool"; DIR="$(cd "$DIR" && pwd)"; cd "$DIR"

# munge: the Debian package made a key; start the daemon unless one runs.
started_munge=0
if ! munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
    mkdir -p /run/munge /var/log/munge /var/lib/munge && chown munge:munge /run/munge /var/log/munge /var/lib/munge
    [ -f /etc/munge/munge.key ] || { mungekey --create 2>/dev/null || dd if=/dev/urandom of=/etc/munge/munge.key bs=128 count=1 2>/dev/null; chown munge:munge /etc/munge/munge.key; chmod 400 /etc/munge/munge.key; }
    runuser -u munge -- munged && started_munge=1
fi
host=$(hostname -s)
cat > slurm.conf <<CONF
ClusterName=framepass-test
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/slurmctld.pid
SlurmdPidFile=$DIR/slurmd.pid
SlurmctldPort=16917
SlurmdPort=16918
SlurmctldLogFile=$DIR/slurmctld.log
SlurmdLogFile=$DIR/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$DIR/slurm.conf"
stop() {  # the daemons this script started, and only those
    local pids=""
    for p in slurmd slurmctld; do [ -f "$DIR/$p.pid" ] && pids="$pids $(cat "$DIR/$p.pid")"; done
    # and any process left with our config on its command line (no procps needed)
    for c in /proc/[0-9]*/cmdline; do
        tr '\0' ' ' < "$c" 2>/dev/null | grep -qF "$DIR/slurm.conf" && pids="$pids $(basename "$(dirname "$c")")"
    done
    [ -n "${pids// }" ] && kill $pids 2>/dev/null
    for i in $(seq 1 40); do kill -0 $pids 2>/dev/null || break; sleep 0.25; done
    kill -9 $pids 2>/dev/null
    [ "$started_munge" = 1 ] && [ -f /run/munge/munged.pid ] && kill "$(cat /run/munge/munged.pid)" 2>/dev/null
    return 0
}
trap stop EXIT
check "a single-node Slurm starts" bash -c "slurmctld -f '$SLURM_CONF' && slurmd -f '$SLURM_CONF' &&
    for i in \$(seq 1 60); do sinfo -h -o %t 2>/dev/null | grep -q idle && exit 0; sleep 0.5; done; cat '$DIR/slurmctld.log' '$DIR/slurmd.log'; exit 1"

check "capture a 12-frame shot" "$FP" capture "$SRC/examples/cornell/scene.json" -o shot.####.exr --frames 1-12 --width 48 --height 48
echo '{ "version": 1, "capture": "shot.####.exr" }' > shot.json
check "the sequential run" "$FP" run shot.json --frames 1-12 -o sequential
# The script's defaults: the last task (frames 9-12) warms up from frame 1, more than 8 back.
check "the job array: 3 tasks of 4 frames, each warming up from the shot's start" bash -c "sbatch --wait --array=0-2 -o '$DIR/task.%a.log' \
    --export=ALL,FRAMEPASS='$FP',CONFIG='$DIR/shot.json',FIRST=1,LAST=12,CHUNK=4,OUT='$DIR/array' \
    '$SRC/examples/slurm/framepass_array.sbatch' && grep -q 'warm-up frame 1:' task.2.log && grep -q 'warm-up frame 8:' task.2.log"
check "every task wrote its report" bash -c "ls array/report.0.json array/report.1.json array/report.2.json && rm array/report.*.json"
check "the array's outputs are the sequential run's, byte for byte" diff -r sequential array
finish
