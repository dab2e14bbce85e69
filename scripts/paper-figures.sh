#!/usr/bin/env bash
# Regenerate the paper-figure study with its checks: the sweeps of validation/paper-figures/*.toml
# through the pipeline, their tables in results/ and charts in figures/ (sawdrive validate
# paper-figures). Needs gmsh for the strip meshes (scripts/install-deps.sh).
# Usage: scripts/paper-figures.sh [LEVEL]   (default: full; smoke and quick run fewer points)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo build --release -p sawdrive-cli
level=${1:-full}
/usr/bin/time -f "paper-figures: %e s wall, %M KB max RSS" \
  target/release/sawdrive validate paper-figures --level "$level" --out validation/paper-figures
