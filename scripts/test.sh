#!/usr/bin/env bash
# The project's test command: install missing system packages, then run the whole test suite.
# Long FEM cases are #[ignore]d: run them with `cargo test --workspace --release -- --ignored`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cargo test --workspace "$@"
cargo check -p stick-slip -p static-contact --no-default-features  # solvers build without plotting (feature `charts` off)
python/test.sh  # the Python package: pip install ./python into target/python-venv, then pytest
