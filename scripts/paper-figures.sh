#!/usr/bin/env bash
# Regenerate the paper-figure sweeps and copy their tables and charts into
# validation/paper-figures/<sweep>/. Needs gmsh for the strip meshes (scripts/install-deps.sh).
# Usage: scripts/paper-figures.sh [SWEEP.toml ...]   (default: all validation/paper-figures/*.toml)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo build --release -p sawdrive
sweeps=("$@")
[ ${#sweeps[@]} -gt 0 ] || sweeps=(validation/paper-figures/*.toml)
for sweep in "${sweeps[@]}"; do
  name=$(basename "$sweep" .toml)
  /usr/bin/time -f "$name: %e s wall, %M KB max RSS" target/release/sawdrive sweep "$sweep" --out out
  dest="validation/paper-figures/$name"
  mkdir -p "$dest"
  cp out/"$name"/results.csv out/"$name"/*.svg "$dest"/
  cp out/"$name"/*.png "$dest"/ 2>/dev/null || true
done
