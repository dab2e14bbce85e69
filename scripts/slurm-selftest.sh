#!/usr/bin/env bash
# Run scripts/slurm-sweep.sh under a throwaway single-node Slurm on this machine and check that
# the job array's merged results equal an unsharded run (apart from the wall_time_s column).
#
#   scripts/slurm-selftest.sh [SAWDRIVE binary]       (as root; needs slurmctld, slurmd, munge:
#                                                      apt-get install slurmd slurmctld slurm-client munge)
#
# Starts munged (if no munge socket answers), slurmctld and slurmd with a private config in a
# temporary folder (ports 16817/16818), and stops the daemons it started on exit.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
sawdrive=$(realpath "${1:-$root/target/debug/sawdrive}")
for tool in slurmctld slurmd sbatch squeue munged; do
    command -v "$tool" >/dev/null || { echo "$0: $tool not installed (apt-get install slurmd slurmctld slurm-client munge)" >&2; exit 2; }
done
work=$(mktemp -d /tmp/sawdrive-slurm.XXXXXX)
pids=()
cleanup() {
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    wait 2>/dev/null || true
}
trap cleanup EXIT

if ! munge -n </dev/null >/dev/null 2>&1; then
    mkdir -p /run/munge && chown munge:munge /run/munge
    runuser -u munge -- munged --foreground >"$work/munged.out" 2>&1 &
    pids+=($!)
    for _ in $(seq 50); do munge -n </dev/null >/dev/null 2>&1 && break; sleep 0.1; done
fi
host=$(hostname -s)
cpus=$(nproc)
mkdir -p "$work/state" "$work/spool"
cat >"$work/slurm.conf" <<CONF
ClusterName=sawdrive-selftest
SlurmctldHost=$host
SlurmUser=root
SlurmctldPort=16817
SlurmdPort=16818
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=selftest Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf
slurmctld -D -i >"$work/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D >"$work/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do
    sinfo -h -o %T 2>/dev/null | grep -q idle && break
    sleep 0.2
done
sinfo -h -o %T | grep -q idle || { echo "$0: the Slurm node did not come up; see $work/*.log" >&2; exit 1; }

# A given-η sweep (dynamic stage only): 4 preloads × 2 frictions, 3 shards.
cat >"$work/sweep.toml" <<TOML
name = "slurm-selftest"
scene = "$root/tests/scenes/small-strip.toml"
[set]
effective_ratio = 0.36
[grid]
preload = ["0.1 N", "0.2 N", "0.3 N", "0.4 N"]
friction = [0.2, 0.3]
[[charts]]
x = "preload_n"
y = "stall_thrust_n"
TOML
cd "$work"
ids=$(SAWDRIVE="$sawdrive" "$here/slurm-sweep.sh" sweep.toml sharded 3)
echo "$ids"
for _ in $(seq 600); do
    [ -z "$(squeue -h -o %i)" ] && break
    sleep 0.5
done
[ -z "$(squeue -h -o %i)" ] || { echo "$0: jobs still queued after 5 min: $(squeue)" >&2; exit 1; }
"$sawdrive" sweep sweep.toml --out whole --jobs 1 >/dev/null
strip() { sed 's/,[^,]*$//' "$1"; }
if ! diff <(strip whole/slurm-selftest/results.csv) <(strip sharded/slurm-selftest/results.csv) >/dev/null; then
    echo "$0: merged results of the Slurm array differ from the unsharded run" >&2
    cat slurm-sweep-*.out >&2
    exit 1
fi
grep -h "shard" slurm-sweep-*_*.out
cat slurm-sweep-*-merge.out
echo "slurm self-test passed: 3-task array merged to the unsharded results ($work)"
