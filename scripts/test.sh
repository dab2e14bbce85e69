#!/usr/bin/env bash
# The project's test command: install missing system packages, then run the whole test suite.
# Long FEM cases are #[ignore]d: run them with `cargo test --workspace --release -- --ignored`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
# CI builds once from a clean clone: incremental-compilation state would only take disk space.
if [ "${CI:-}" = true ]; then export CARGO_INCREMENTAL=0; fi
cargo test --workspace "$@"
cargo check -p stick-slip -p static-contact --no-default-features  # solvers build without plotting (feature `charts` off)
python/test.sh  # the Python package: pip install ./python into target/python-venv, then pytest
if [ "${CI:-}" = true ]; then du -sh target 2>/dev/null || true; df -h . | tail -1; fi  # disk footprint, logged
