#!/usr/bin/env bash
# Peer benchmark on the same punch meshes: validation's FEM (elastic-fem, direct and iterative)
# vs TUNED scikit-fem (CG + pyamg smoothed aggregation with rigid-body modes,
# scripts/compare-skfem-tuned.py) and CalculiX ccx (SPOOLES, scripts/compare-ccx.py).
#
#   scripts/compare-peers.sh [--threads N] [--peers skfem,ccx] [--ours iterative,direct] LEVEL|MESH.msh ...
#       LEVEL: quarter Tet10 mesh of that level of the springs-study family (gmsh, cached in
#              target/sawdrive-meshes; level 0 ≈ 20k, 1 ≈ 55k, 2 ≈ 140k, 3 ≈ 350k, 4 ≈ 900k,
#              5 ≈ 2.5M unknowns; a fraction lies between two levels: 4.2 ≈ 1.1M)
#
# Whole-process wall time, CPU time (user + sys), peak resident memory of each code (/usr/bin/time -v)
# and the 1-minute load average before it started, one thread
# by default (OMP/OpenBLAS/MKL/RAYON/ccx thread variables all set to N), and k_sn (frictionless
# normal punch, clamped far field) of every code, which must agree to 1e-6 (same mesh, same
# isoparametric Tet10, same boundary conditions). Ours runs the punch_scaling example with
# --clamped-only: problem A (clamped far field, one right-hand side), the problem the peers solve
# (validation's springs study solves B as well, for the far-field correction).
# Prints one JSON line per code and mesh, then a summary line per mesh (ratios of one run).
# Python peers live in a venv in the target folder (pip: scikit-fem, meshio, pyamg); ccx from
# Debian (apt-get install calculix-ccx).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
target="${CARGO_TARGET_DIR:-$root/target}"
venv="$target/skfem-venv"
threads=1
peers="skfem,ccx"
ours_methods="iterative,direct"
args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --threads) threads="$2"; shift 2 ;;
    --peers) peers="$2"; shift 2 ;;
    --ours) ours_methods="$2"; shift 2 ;;
    *) args+=("$1"); shift ;;
  esac
done
[[ ${#args[@]} -gt 0 ]] || { echo "usage: $0 [--threads N] [--peers skfem,ccx] [--ours iterative,direct] LEVEL|MESH.msh ..." >&2; exit 2; }
[[ "$ours_methods" == *iterative* ]] || { echo "--ours must include iterative (the ratios are against it)" >&2; exit 2; }
if [[ ! -x "$venv/bin/python" ]]; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q scikit-fem meshio pyamg
fi
command -v ccx >/dev/null || [[ "$peers" != *ccx* ]] || { echo "ccx not found: apt-get install calculix-ccx" >&2; exit 1; }
export OMP_NUM_THREADS="$threads" OPENBLAS_NUM_THREADS="$threads" MKL_NUM_THREADS="$threads" \
  RAYON_NUM_THREADS="$threads" CCX_NPROC_STIFFNESS="$threads" CCX_NPROC_EQUATION_SOLVER="$threads"
(cd "$root" && cargo build -q --release -p validation --example punch_scaling)
ours="$target/release/examples/punch_scaling"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

# Runs a command under /usr/bin/time -v; prints its stdout's last line with wall_s and peak_mb added.
timed() {
  local name="$1"; shift
  local load
  load="$(cut -d' ' -f1 /proc/loadavg)"
  /usr/bin/time -v "$@" >"$out/$name.json" 2>"$out/$name.time"
  python3 - "$out/$name.json" "$out/$name.time" "$name" "$load" <<'PY'
import json, re, sys
line = open(sys.argv[1]).read().strip().splitlines()[-1]
t = open(sys.argv[2]).read()
d = json.loads(line)
m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([\d.]+)", t)
d["wall_s"] = (int(m.group(1) or 0) * 3600 + int(m.group(2)) * 60 + float(m.group(3)))
d["peak_mb"] = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1024
d["cpu_s"] = sum(float(re.search(rf"{k} time \(seconds\): ([\d.]+)", t).group(1)) for k in ("User", "System"))
d["load_before"] = float(sys.argv[4])
d["run"] = sys.argv[3]
print(json.dumps(d))
PY
}

for arg in "${args[@]}"; do
  if [[ "$arg" =~ ^[0-9]+(\.[0-9]+)?$ ]]; then
    mesh="$("$ours" --method direct --level "$arg" --mesh-only)"
  else
    mesh="$arg"
  fi
  : >"$out/lines"
  for method in ${ours_methods//,/ }; do
    timed "ours-$method" "$ours" --method "$method" --clamped-only "$mesh" | tee -a "$out/lines"
  done
  if [[ "$peers" == *skfem* ]]; then
    timed skfem-tuned "$venv/bin/python" "$root/scripts/compare-skfem-tuned.py" "$mesh" | tee -a "$out/lines"
  fi
  if [[ "$peers" == *ccx* ]]; then
    timed ccx "$venv/bin/python" "$root/scripts/compare-ccx.py" "$mesh" --workdir "$out/ccx" | tee -a "$out/lines"
  fi
  python3 - "$out/lines" "$threads" <<'PY'
import json, sys
runs = {d["run"]: d for d in map(json.loads, open(sys.argv[1]))}
ours = runs["ours-iterative"]
k = ours["k_sn_clamped_n_per_m"]
parts = [f'{ours["unknowns"]} unknowns, {sys.argv[2]} thread(s): ours iterative {ours["wall_s"]:.1f} s (CPU {ours["cpu_s"]:.1f} s) {ours["peak_mb"]:.0f} MB ({ours["iterations"]} it, load {ours["load_before"]})']
for name, d in runs.items():
    if name == "ours-iterative":
        continue
    dk = d["k_sn_clamped_n_per_m"] / k - 1
    parts.append(f'{name} {d["wall_s"]:.1f} s (CPU {d["cpu_s"]:.1f} s) {d["peak_mb"]:.0f} MB (wall x{d["wall_s"] / ours["wall_s"]:.2f}, CPU x{d["cpu_s"] / ours["cpu_s"]:.2f}, dk {dk:+.1e}, load {d["load_before"]})')
print("SUMMARY " + "; ".join(parts))
PY
done
