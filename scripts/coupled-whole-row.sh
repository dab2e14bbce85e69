#!/usr/bin/env bash
# Issue 14's coupled-vs-lumped study on whole-row strips (validation/coupled-dynamics/whole-row.toml):
# runs the sweep (gmsh meshes and FEM condensations cached in OUT/.cache) and tabulates every
# point's summary into validation/coupled-dynamics/whole-row/results.csv with the charts.
# Usage: scripts/coupled-whole-row.sh [OUT]   (default OUT = out; needs gmsh: scripts/install-deps.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out}
cargo build -p sawdrive
/usr/bin/time -f "whole-row: %e s wall, %M KB max RSS" \
  target/debug/sawdrive sweep validation/coupled-dynamics/whole-row.toml --out "$out" --jobs 1
dest=validation/coupled-dynamics/whole-row
mkdir -p "$dest"
python3 validation/coupled-dynamics/whole-row.py "$out/whole-row/points" > "$dest/results.csv"
cp "$out"/whole-row/*.svg "$dest"/
