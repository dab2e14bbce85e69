#!/usr/bin/env bash
# How a sharded sweep scales: one shard vs N shards run at once on this machine (as N tasks of
# a job array would on N cores), and the serial part that bounds the speed-up (Amdahl).
#
#   scripts/slurm-speedup.sh [SAWDRIVE binary] [N]        (defaults: target/debug/sawdrive, 2)
#
# Three sweeps of the small scene (tests/scenes/small-strip.toml, committed mesh), 8 points each:
#   eta — η given (effective_ratio = 0.36), transient dynamics, 4 preloads × 2 frictions: nothing
#         serial but each shard's start-up and the merge;
#   fem — η from the FEM of one slider geometry, period-average dynamics, 4 preloads × 2
#         frictions: the one condensation is serial (the first shard to lock it runs it, the
#         others wait);
#   geo — η from the FEM of 4 geometries (4 wave amplitudes, same mesh) × 2 preloads, period
#         average: the shards condense different geometries at once, so with M ≤ 4 shards only
#         start-up and merge are serial.
# For each: wall and CPU time of 1 shard and of N shards together (fresh OUT each), the serial
# CPU time (a rerun that finds every point saved — start-up, hashing, merge — plus, for fem, the
# condensation: fresh run minus a run on the filled cache), the serial fraction f = serial / one
# shard's CPU time, and Amdahl's speed-up 1/(f + (1−f)/M) for M = 4 shards on 4 cores. CPU time,
# unlike wall time, does not depend on what else the machine runs; wall times on a shared machine
# depend on its load (printed).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
sawdrive=$(realpath "${1:-$root/target/debug/sawdrive}")
shards=${2:-2}
work=$(mktemp -d /tmp/sawdrive-speedup.XXXXXX)
trap 'rm -rf "$work"' EXIT
cd "$work"

write_sweep() { # name eta-line dynamics grid
    cat >"$1.toml" <<TOML
name = "$1"
scene = "$root/tests/scenes/small-strip.toml"
[set]
$2
"model.dynamics" = "$3"
[grid]
$4
TOML
}
four_by_two='preload = ["0.1 N", "0.2 N", "0.3 N", "0.4 N"]
friction = [0.2, 0.3]'
write_sweep eta "effective_ratio = 0.36" transient "$four_by_two"
write_sweep fem "" periodic-average "$four_by_two"
write_sweep geo "" periodic-average 'preload = ["0.2 N", "0.4 N"]
"wave.normal_amplitude" = ["15 nm", "20 nm", "25 nm", "30 nm"]'

# seconds: wall user+sys of a command (children included)
measure() {
    local t0 t1 c0 c1 me=$BASHPID
    t0=$(date +%s.%N)
    c0=$(awk '{print $14+$15+$16+$17}' /proc/$me/stat)
    "$@" >/dev/null
    t1=$(date +%s.%N)
    c1=$(awk '{print $14+$15+$16+$17}' /proc/$me/stat)
    echo "$(echo "$t1 - $t0" | bc -l) $(echo "($c1 - $c0) / $(getconf CLK_TCK)" | bc -l)"
}
one_shard() { "$sawdrive" sweep "$1.toml" --out "$2" --jobs 1 --shard 1/1; }
n_shards() {
    local k pids=()
    for k in $(seq "$shards"); do
        "$sawdrive" sweep "$1.toml" --out "$2" --jobs 1 --shard "$k/$shards" >/dev/null &
        pids+=($!)
    done
    for k in "${pids[@]}"; do wait "$k"; done
}

printf 'load average: %s; cores: %s; shards: %s\n' "$(cut -d' ' -f1-3 /proc/loadavg)" "$(nproc)" "$shards"
printf '%-4s %9s %9s %9s %9s %8s %10s %7s %6s\n' sweep 1-wall_s 1-cpu_s N-wall_s N-cpu_s speedup serial_cpu f 'S(4)'
for name in eta fem geo; do
    read -r w1 c1 < <(measure one_shard "$name" "one-$name")
    read -r wn cn < <(measure n_shards "$name" "n-$name")
    # Serial: a rerun that finds every point saved (start-up, hashing, merge) ...
    read -r _ co < <(measure one_shard "$name" "one-$name")
    # ... plus, for the one-geometry FEM sweep, the condensation: the fresh run minus a run on
    # the filled cache.
    rm -rf "one-$name/$name"
    read -r _ cc < <(measure one_shard "$name" "one-$name")
    condensation=0
    [ "$name" = fem ] && condensation=$(echo "if ($c1 - $cc > 0) $c1 - $cc else 0" | bc -l)
    serial=$(echo "$co + $condensation" | bc -l)
    f=$(echo "$serial / $c1" | bc -l)
    printf '%-4s %9.2f %9.2f %9.2f %9.2f %8.2f %10.2f %7.3f %6.2f\n' "$name" "$w1" "$c1" "$wn" "$cn" \
        "$(echo "$w1 / $wn" | bc -l)" "$serial" "$f" "$(echo "1 / ($f + (1 - $f) / 4)" | bc -l)"
done
