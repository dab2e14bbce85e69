#!/usr/bin/env bash
# Regenerate a mesh from one of the parametric geometries in meshes/.
#
#   scripts/mesh.sh [--binary] GEOMETRY OUT.msh [NAME=VALUE ...]
#
# GEOMETRY is a name from meshes/ (punch, slider-strip, slider-body) or a path to a .geo file.
# NAME=VALUE pairs are passed as `gmsh -setnumber NAME VALUE` (parameters in SI units, see
# meshes/README.md). Output is MSH 4.1, ASCII unless --binary. The mesh is written to a
# temporary file beside OUT.msh and moved into place only if gmsh succeeds, so a failed run never
# leaves a partial mesh. Meshing runs on one thread so that the result is reproducible.
#
# Environment: GMSH (default: gmsh on PATH) selects the gmsh binary.
set -euo pipefail

usage() {
  echo "usage: $0 [--binary] GEOMETRY OUT.msh [NAME=VALUE ...]" >&2
  echo "  GEOMETRY: punch | slider-strip | slider-body | path/to/file.geo" >&2
}

binary=0
if [[ "${1:-}" == "--binary" ]]; then
  binary=1
  shift
fi
if [[ $# -lt 2 ]]; then
  usage
  exit 2
fi
geometry="$1"
out="$2"
shift 2

gmsh_bin="${GMSH:-gmsh}"
if ! command -v "$gmsh_bin" >/dev/null 2>&1; then
  echo "error: gmsh not found (looked for '$gmsh_bin'); install it with: apt-get install -y gmsh" >&2
  exit 127
fi

script_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [[ -f "$geometry" ]]; then
  geo="$geometry"
elif [[ -f "$script_dir/../meshes/$geometry.geo" ]]; then
  geo="$script_dir/../meshes/$geometry.geo"
else
  echo "error: geometry '$geometry' is neither a file nor one of:" \
    "$(cd "$script_dir/../meshes" && ls -- *.geo 2>/dev/null | sed 's/\.geo$//' | tr '\n' ' ')" >&2
  exit 2
fi

args=(-3 -format msh41 -nt 1)
if [[ $binary == 1 ]]; then
  args+=(-bin)
fi
for pair in "$@"; do
  if [[ ! "$pair" =~ ^[A-Za-z_][A-Za-z0-9_.]*=[-+0-9.eE]+$ ]]; then
    echo "error: parameter '$pair' is not NAME=NUMBER" >&2
    exit 2
  fi
  args+=(-setnumber "${pair%%=*}" "${pair#*=}")
done

out_dir="$(dirname -- "$out")"
if [[ ! -d "$out_dir" ]]; then
  echo "error: output directory '$out_dir' does not exist" >&2
  exit 2
fi
tmp="$(mktemp --suffix=.msh "$out_dir/.$(basename -- "$out").XXXXXX")"
log="$(mktemp)"
cleanup() { rm -f -- "$tmp" "$log"; }
trap cleanup EXIT

if ! "$gmsh_bin" "$geo" "${args[@]}" -o "$tmp" >"$log" 2>&1; then
  echo "error: gmsh failed on $geo ${*:-}" >&2
  grep -E "^(Error|Warning)" "$log" >&2 || tail -n 20 "$log" >&2
  exit 1
fi
if grep -q "^Error" "$log"; then
  echo "error: gmsh reported errors on $geo ${*:-}" >&2
  grep -E "^Error" "$log" >&2
  exit 1
fi
if [[ ! -s "$tmp" ]]; then
  echo "error: gmsh wrote no mesh for $geo ${*:-}" >&2
  tail -n 20 "$log" >&2
  exit 1
fi
chmod 644 -- "$tmp"
mv -f -- "$tmp" "$out"
echo "wrote $out from $geo ${*:-}"
