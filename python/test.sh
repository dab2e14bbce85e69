#!/usr/bin/env bash
# The Python package's tests: `pip install ./python` (maturin builds the extension in release
# mode into python/target) into a virtual environment, then pytest. Needs python3 with venv and
# the Rust toolchain; maturin, numpy, pandas, matplotlib and pytest come from PyPI.
# Environment: SAWDRIVE_PYTHON_VENV (default target/python-venv); SAWDRIVE_CLI (the `sawdrive`
# binary the tests compare with; default target/debug/sawdrive, built if missing).
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${SAWDRIVE_PYTHON_VENV:-target/python-venv}"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
python="$(cd "$(dirname "$venv/bin/python")" && pwd)/python"
"$python" -m pip install --quiet --disable-pip-version-check maturin numpy pandas matplotlib pytest
"$python" -m pip install --quiet --disable-pip-version-check ./python
# From the repository root: python/ itself would shadow the installed package.
"$python" -m pytest python/tests -q "$@"
