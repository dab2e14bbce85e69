#!/usr/bin/env bash
# The main job: install missing system packages (gmsh meshes the slider strip), build, and run
# the whole pipeline. Arguments go to `sawdrive run` (default: the embedded paper scene).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo run --release -q -p sawdrive-cli -- run "$@"
