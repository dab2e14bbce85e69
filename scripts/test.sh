#!/usr/bin/env bash
# The project's test command: install missing system packages, then run the whole test suite.
# Long FEM cases are #[ignore]d: run them with `cargo test --workspace --release -- --ignored`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
# CI builds once from a clean clone: incremental-compilation state would only take disk space.
if [ "${CI:-}" = true ]; then export CARGO_INCREMENTAL=0; fi
cargo test --workspace "$@"
# Validation studies through the one command (the test build's binary, no extra build): every
# case at smoke level, then the quick level of the cases whose code paths smoke does not reach:
# springs (work-precision Tet4 vs Tet10, locking, the floating punch refused by every solver
# path, distorted meshes), stick-slip (return-mapping order, stability maps), whole-slider (tilt
# and bow, every mechanism with scatter) and coupled-dynamics (the default 100-post row: its
# step convergence and the energy-conserving wave at 100 N). paper-figures' quick level only
# adds grid points on the path its smoke points take. A failing check exits non-zero naming it.
# Then the binary copied away from the checkout meshes into its XDG/HOME cache and passes the
# quick springs study.
validate_out="$(mktemp -d)"
target/debug/sawdrive validate all --level smoke --out "$validate_out/smoke"
for case in springs stick-slip whole-slider coupled-dynamics; do
  target/debug/sawdrive validate "$case" --level quick --out "$validate_out/$case"
done
rm -rf "$validate_out"
cargo test -p sawdrive-cli --test relocated_binary -- --ignored
cargo check -p stick-slip -p static-contact --no-default-features  # solvers build without plotting (feature `charts` off)
python/test.sh  # the Python package: its wheel (maturin build) into target/python-venv and a fresh venv, then pytest
if [ "${CI:-}" = true ]; then du -sh target 2>/dev/null || true; df -h . | tail -1; fi  # disk footprint, logged
