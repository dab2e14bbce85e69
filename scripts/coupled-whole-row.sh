#!/usr/bin/env bash
# The coupled-vs-lumped study on whole-row strips (validation/coupled-dynamics/scripts/whole-row.py):
# 8 sliders × 3 preloads through `sawdrive dynamic --json` with model.dynamics = "coupled"; gmsh
# meshes, FEM reports and tip compliances are cached in OUT/.cache (one strip FEM per slider).
# Writes validation/coupled-dynamics/results/whole-row.csv (the reference of the
# coupled-dynamics validation case's whole-row checks).
# Usage: scripts/coupled-whole-row.sh [OUT]   (default OUT = out; needs gmsh: scripts/install-deps.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out}
# The package of the `sawdrive` binary (crates/sawdrive-cli; crates/sawdrive before it).
package=sawdrive-cli
[ -f crates/sawdrive-cli/Cargo.toml ] || package=sawdrive
cargo build --release -p "$package" --bin sawdrive
/usr/bin/time -f "whole-row: %e s wall, %M KB max RSS" \
  python3 validation/coupled-dynamics/scripts/whole-row.py target/release/sawdrive "$out" \
  > validation/coupled-dynamics/results/whole-row.csv.tmp
mv validation/coupled-dynamics/results/whole-row.csv.tmp validation/coupled-dynamics/results/whole-row.csv
