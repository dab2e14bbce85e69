#!/usr/bin/env bash
# Wall and CPU time of the default pipeline (targets: ≤ 3 s with the mesh cached, ≤ 6 s cold), whole process, this machine:
#
#   cold    `sawdrive run` of the default scene, empty mesh cache (gmsh meshes the strip), no FEM
#           result cache;
#   cached  the same with the mesh cached (the run above made it, with the fill-reducing ordering
#           of its stiffness stored beside it: no METIS run), still no FEM result cache;
#   constant_wave  the cached run with `wave.attenuation = "off"` (the default attenuates: the
#           energy-conserving wave's cost is the ratio of the two);
#   cached_fem  `sawdrive run` with the FEM result cache filled by the run before it (the dynamic
#           stage and the output alone), with and without the energy-conserving wave;
#   static  `sawdrive static` of the default scene, cold and with the mesh cached: the static stage
#           and its output alone (the dynamic stage the scene picks is not in these two lines);
#   sweep   validation/paper-figures/fig7-8-post-count.toml (25 points, 5 geometries), empty mesh
#           cache, fresh output folder (no resumed points);
#
# then the breakdown of the cached run (mesh read, assembly, ordering + symbolic analysis, numeric
# factorisation, condensation onto the posts, contact solves and η fits) from the run's
# static.json. Numbers go to stdout as `name wall_s user_s sys_s max_rss_kb` lines.
#
#   scripts/perf-default.sh [--runs N] [--no-sweep]
#
# Builds the release binary first (cargo build --release -p sawdrive-cli). On a machine shared with
# other jobs, user+sys (CPU time) is the steadier number; the wall time is what a user waits.
set -euo pipefail
cd "$(dirname "$0")/.."

runs=1
sweep=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --runs) runs="$2"; shift 2 ;;
    --no-sweep) sweep=0; shift ;;
    *) echo "usage: $0 [--runs N] [--no-sweep]" >&2; exit 2 ;;
  esac
done
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "error: --runs must be a positive integer" >&2; exit 2; }

cargo build --release -q -p sawdrive-cli
bin="${CARGO_TARGET_DIR:-$PWD/target}/release/sawdrive"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

# timed NAME CMD...: one line "NAME wall user sys maxrss".
timed() {
  local name="$1"; shift
  /usr/bin/time -f "$name %e %U %S %M" -o "$scratch/time" "$@" >"$scratch/stdout" 2>"$scratch/stderr" || {
    echo "error: $name failed:" >&2; tail -5 "$scratch/stderr" >&2; exit 1; }
  cat "$scratch/time"
}

echo "# name wall_s user_s sys_s max_rss_kb (load average: $(cut -d' ' -f1-3 /proc/loadavg))"
for r in $(seq 1 "$runs"); do
  export SAWDRIVE_MESH_CACHE="$scratch/meshes-$r"
  timed "run_cold" "$bin" run --no-cache --out "$scratch/out-cold-$r"
  timed "run_cached_mesh" "$bin" run --no-cache --out "$scratch/out-cached-$r"
  timed "run_cached_mesh_constant_wave" "$bin" run --no-cache --set wave.attenuation=off \
    --out "$scratch/out-constant-$r"
  timed "run_fem_cache_fill" "$bin" run --out "$scratch/out-fem-$r"
  timed "run_cached_fem" "$bin" run --out "$scratch/out-fem-$r"
  timed "run_cached_fem_constant_wave" "$bin" run --set wave.attenuation=off --out "$scratch/out-fem-$r"
  export SAWDRIVE_MESH_CACHE="$scratch/meshes-static-$r"
  timed "static_cold" "$bin" static --no-cache --out "$scratch/out-static-cold-$r"
  timed "static_cached_mesh" "$bin" static --no-cache --out "$scratch/out-static-cached-$r"
done
report="$(find "$scratch/out-cached-$runs" -name static.json | head -1)"
if [[ -n "$report" ]]; then
  python3 - "$report" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
t, f = r["timings"], r["fem"]["slider"]
print(f"# breakdown of the cached run (s): mesh read {t['mesh_s']:.2f}, assembly {f['assembly_s']:.2f} "
      f"(with the ordering+symbolic analysis beside it: {f.get('analysis_s', float('nan')):.2f}, "
      f"ordering {'from the mesh cache' if f.get('ordering_cached') else 'by METIS'}), "
      f"numeric factorisation {f['factor_s'] - f.get('analysis_s', 0.0):.2f}, "
      f"condensation onto the posts {f['solve_s']:.4f}, contact solves + eta fits {t['contact_s']:.4f}, "
      f"static stage {t['wall_time_s']:.2f}")
print(f"# slider strip: {f['nodes']} nodes, {f['reduced_unknowns']} unknowns, factor {f['factor_nnz']} entries, "
      f"{f.get('factor_flops', 0.0) / 1e9:.1f} G multiply-adds; eta = {r['effective_contact_ratio']!r}")
EOF
fi
if [[ $sweep == 1 ]]; then
  export SAWDRIVE_MESH_CACHE="$scratch/meshes-sweep"
  timed "sweep_fig7_8_cold" "$bin" sweep validation/paper-figures/fig7-8-post-count.toml --out "$scratch/out-sweep"
fi
