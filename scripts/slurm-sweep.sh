#!/usr/bin/env bash
# Submit a sawdrive sweep to Slurm as a job array of N shards plus a merge job.
#
#   scripts/slurm-sweep.sh SWEEP.toml OUT N [sbatch options, e.g. --cpus-per-task=4 -p short]
#
# Task K runs `sawdrive sweep SWEEP.toml --out OUT --shard K/N` (points K, K+N, …) with
# --jobs = its CPUs; the shard that saves the last point writes OUT/<name>/results.csv and the
# charts. The merge job (`--merge`, after every task ended, whatever their exit status) writes
# them again, identically, or names the points still missing. Prints the two job ids.
# SAWDRIVE: the sawdrive binary (default: `sawdrive` on PATH, else target/release/sawdrive).
set -euo pipefail
if [ $# -lt 3 ]; then
    echo "usage: $0 SWEEP.toml OUT N [sbatch options]" >&2
    exit 2
fi
sweep=$(realpath "$1") out=$(realpath -m "$2") shards=$3
shift 3
case $shards in
    '' | *[!0-9]* | 0) echo "$0: N = \"$shards\": give the number of shards, a whole number ≥ 1" >&2; exit 2 ;;
esac
here=$(cd "$(dirname "$0")" && pwd)
sawdrive=${SAWDRIVE:-$(command -v sawdrive || echo "$here/../target/release/sawdrive")}
sawdrive=$(realpath "$sawdrive")
[ -x "$sawdrive" ] || { echo "$0: no sawdrive binary at $sawdrive (set SAWDRIVE)" >&2; exit 2; }
mkdir -p "$out"
array=$(sbatch --parsable --array="1-$shards" --export="ALL,SAWDRIVE=$sawdrive" "$@" \
    "$here/slurm-sweep.sbatch" "$sweep" "$out" "$shards")
merge=$(sbatch --parsable --dependency="afterany:$array" --job-name=sawdrive-merge \
    --output="slurm-sweep-$array-merge.out" "$@" \
    --wrap="'$sawdrive' sweep '$sweep' --out '$out' --merge")
echo "array job $array ($shards shards), merge job $merge; results in $out"
