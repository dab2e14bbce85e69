#!/usr/bin/env bash
# Peer comparison on the same punch meshes: validation's FEM (Rust, elastic-fem) vs scikit-fem.
#
#   scripts/compare-skfem.sh [MESH.msh ...]      # default: the committed quarter Tet10 mesh and
#                                                # the study's quarter level-1 mesh (gmsh)
#
# Both codes solve k_sn (frictionless normal punch, clamped far field, quarter symmetry) with the
# same isoparametric Tet10 elements on the same .msh; the stiffness must agree to ~1e-6 (same
# discretisation) and the wall times are compared (scikit-fem: basis + assembly + condense +
# solve with its default direct solver; ours: pattern, assembly, reduction, METIS ordering,
# Cholesky, solve). scikit-fem and meshio are installed into a venv in the validation target
# folder on first use (pip, PyPI). Prints one line per mesh and the time ratio.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
target="${CARGO_TARGET_DIR:-$root/target}"
venv="$target/skfem-venv"
if [[ ! -x "$venv/bin/python" ]]; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q scikit-fem meshio
fi
meshes=("$@")
if [[ ${#meshes[@]} -eq 0 ]]; then
  level1="$(cd "$root" && cargo run -q --release -p validation --example punch_scaling -- --level 1 | sed -n 's/.*"mesh":"\([^"]*\)".*/\1/p')"
  meshes=("$root/meshes/punch-quarter_a10um_R100a_tet10_8k.msh" "$level1")
fi
for mesh in "${meshes[@]}"; do
  ours="$(cd "$root" && cargo run -q --release -p validation --example punch_scaling -- "$mesh")"
  theirs="$("$venv/bin/python" "$root/scripts/compare-skfem.py" "$mesh" 2>/dev/null)"
  python3 - "$ours" "$theirs" <<'PY'
import json, sys
ours, theirs = json.loads(sys.argv[1]), json.loads(sys.argv[2])
diff = ours["k_sn_clamped_n_per_m"] / theirs["k_sn_clamped_n_per_m"] - 1
print(f'{ours["mesh"]}: {ours["unknowns"]} unknowns (scikit-fem {theirs["unknowns"]})')
print(f'  k_sn clamped: ours {ours["k_sn_clamped_n_per_m"]:.9e}  scikit-fem {theirs["k_sn_clamped_n_per_m"]:.9e}  relative difference {diff:.1e}')
print(f'  wall time:    ours {ours["total_s"]:.2f} s (assembly {ours["pattern_s"] + ours["assembly_s"]:.2f}, factor {ours["symbolic_s"] + ours["numeric_s"]:.2f}, peak {ours["peak_rss_mb"]:.0f} MB)'
      f'  scikit-fem {theirs["total_s"]:.2f} s (assembly {theirs["assembly_s"]:.2f}, condense+solve {theirs["condense_solve_s"]:.2f}, peak {theirs["peak_rss_mb"]:.0f} MB)')
print(f'  scikit-fem / ours wall time: {theirs["total_s"] / ours["total_s"]:.1f}')
PY
done
