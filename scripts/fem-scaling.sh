#!/usr/bin/env bash
# Cost of our FEM against problem size (target: "total cost growing no faster than
# N^1.2 from 55k to ≥ 2M unknowns within 24 GB"): the punch family's quarter Tet10 meshes, one
# thread, `punch_scaling --method iterative --clamped-only` (the problem the peers of
# compare-peers.sh solve), whole-process wall time and peak memory.
#
#   scripts/fem-scaling.sh [--levels "1 3 4 5"] [--repeats N] [--threads T]
#
# Levels (mesh family, validation::MeshFamily::tet10): 1 = 55k, 3 = 350k, 4 = 0.93M, 5 = 2.5M
# unknowns. Missing meshes are generated first, outside the timing (gmsh; level 5 takes ≈ 9 min
# and 4 GB). Each repeat runs every level once, smallest first. Output: one line per run
# (`unknowns iterations wall_s cpu_s peak_gb k_sn_clamped phases`), then per level the median
# wall time, and the least-squares exponent of wall time against unknowns over all levels and
# per interval. Needs ≈ 8 GB of memory for level 5.
set -euo pipefail
cd "$(dirname "$0")/.."

levels="1 3 4 5"
repeats=1
threads=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --levels) levels="$2"; shift 2 ;;
    --repeats) repeats="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    *) echo "usage: $0 [--levels \"1 3 4 5\"] [--repeats N] [--threads T]" >&2; exit 2 ;;
  esac
done
[[ "$repeats" =~ ^[1-9][0-9]*$ ]] || { echo "error: --repeats must be a positive integer" >&2; exit 2; }
[[ "$threads" =~ ^[1-9][0-9]*$ ]] || { echo "error: --threads must be a positive integer" >&2; exit 2; }
for l in $levels; do
  [[ "$l" =~ ^[0-9]+$ ]] || { echo "error: --levels: \`$l\` is not a level number" >&2; exit 2; }
done

cargo build --release -q -p validation --example punch_scaling
bin="${CARGO_TARGET_DIR:-$PWD/target}/release/examples/punch_scaling"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
declare -A mesh
for l in $levels; do
  mesh[$l]="$("$bin" --mesh-only --level "$l" | tail -1)"
done

echo "# $(date -u '+%F %H:%M') UTC, $(git rev-parse --short HEAD), $threads thread(s), load $(cut -d' ' -f1 /proc/loadavg) before"
echo "# unknowns iterations wall_s cpu_s peak_gb k_sn_clamped phases"
for r in $(seq 1 "$repeats"); do
  for l in $levels; do
    RAYON_NUM_THREADS="$threads" /usr/bin/time -f "%e %U %S %M" -o "$scratch/time" \
      "$bin" --method iterative --clamped-only "${mesh[$l]}" >"$scratch/out" 2>"$scratch/err" || {
        echo "error: level $l failed:" >&2; tail -5 "$scratch/err" >&2; exit 1; }
    python3 - "$scratch/time" "$scratch/out" >>"$scratch/runs" <<'EOF'
import json, sys
wall, user, sys_, rss_kb = (float(x) for x in open(sys.argv[1]).read().split()[-4:])
r = json.loads(open(sys.argv[2]).read().strip().splitlines()[-1])
phases = {k: round(r[k], 2) for k in ("read_s", "pattern_s", "assembly_s", "reduction_s",
                                       "numeric_s", "solve_s", "total_s")}
print(r["unknowns"], r["iterations"][0], wall, round(user + sys_, 2), round(rss_kb / 1e6, 2),
      repr(r["k_sn_clamped_n_per_m"]), json.dumps(phases))
EOF
    tail -1 "$scratch/runs"
  done
done

python3 - "$scratch/runs" <<'EOF'
import math, statistics, sys
runs = {}
for line in open(sys.argv[1]):
    f = line.split(maxsplit=6)
    runs.setdefault(int(f[0]), []).append((float(f[2]), float(f[4]), float(f[3])))
sizes = sorted(runs)
med = {n: statistics.median(w for w, _, _ in runs[n]) for n in sizes}
for n in sizes:
    print(f"level of {n} unknowns: median wall {med[n]:.2f} s, CPU (user + sys) "
          f"{statistics.median(c for _, _, c in runs[n]):.2f} s over {len(runs[n])} run(s), "
          f"peak {max(m for _, m, _ in runs[n]):.2f} GB")
if len(sizes) >= 2:
    xs = [math.log(n) for n in sizes]
    ys = [math.log(med[n]) for n in sizes]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    steps = ", ".join(f"N^{(ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]):.2f}" for i in range(len(xs) - 1))
    print(f"least-squares exponent of the median wall time: N^{slope:.2f} "
          f"({sizes[0]} to {sizes[-1]} unknowns); per interval {steps}")
EOF
