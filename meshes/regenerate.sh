#!/usr/bin/env bash
# Regenerate every committed mesh in meshes/ with the exact commands recorded in
# meshes/README.md (gmsh 4.8.4, one thread). Run from anywhere: meshes/regenerate.sh
#
# Every committed mesh is ASCII MSH 4.1 (so that the tree holds text only). Meshes whose
# coordinates must keep every bit are written by gmsh as binary and then converted by
# scripts/msh-to-ascii.py, which prints shortest round-trip floats and checks that its text
# re-encodes to gmsh's binary bytes exactly; gmsh's own ASCII writer keeps 16 significant
# digits, which does not always give back the same f64.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
mesh="$here/../scripts/mesh.sh"
to_ascii="$here/../scripts/msh-to-ascii.py"

# gmsh binary, then the exact ASCII conversion in place.
exact() {
  local geometry="$1" out="$2"
  shift 2
  "$mesh" --binary "$geometry" "$out" "$@"
  "$to_ascii" "$out"
}

"$mesh" punch "$here/punch_a10um_R20a_tet4_5k.msh" a=10e-6 R_over_a=20 h_edge_over_a=0.03 growth=0.3 sym=0 order=1
exact punch "$here/punch-quarter_a10um_R100a_tet10_8k.msh" a=10e-6 R_over_a=100 h_edge_over_a=0.05 growth=0.3 sym=2 order=2
exact punch "$here/punch-half_a10um_R100a_tet10_14k.msh" a=10e-6 R_over_a=100 h_edge_over_a=0.05 growth=0.3 sym=1 order=2
exact slider-strip "$here/slider-strip_p40um_d20um_n10_tet4_10k.msh" pitch=40e-6 d=20e-6 h=2e-6 t=0.5e-3 n_posts=10 margin=0 stator_depth=1e-3 h_post=2.5e-6 h_body=100e-6 growth=0.3 order=1 periodic_x=0
"$mesh" slider-strip "$here/slider-strip-periodic_p40um_d20um_n1_tet4_1k.msh" pitch=40e-6 d=20e-6 h=2e-6 t=0.5e-3 n_posts=1 margin=0 stator_depth=1e-3 h_post=2.5e-6 h_body=100e-6 growth=0.3 order=1 periodic_x=1
exact slider-body "$here/slider-body_5x5x0.5mm_tet10_2k.msh" length=5e-3 width=5e-3 thickness=0.5e-3 h_size=0.5e-3 order=2

# The contract: no committed mesh is binary.
for file in "$here"/*.msh; do
  "$to_ascii" --check-ascii "$file" >/dev/null
done
