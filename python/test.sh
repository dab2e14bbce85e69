#!/usr/bin/env bash
# The Python package's tests: build the wheel (`maturin build --release` into
# target/python-wheel; the extension is compiled in python/target), install it into a virtual
# environment, then pytest. One of the tests installs the same wheel into a brand-new virtual
# environment and runs it from an empty folder, away from the checkout (tests/test_wheel.py).
# Needs python3 with venv, the Rust toolchain and gmsh; maturin, numpy, pandas, matplotlib and
# pytest come from PyPI.
# Environment: SAWDRIVE_PYTHON_VENV (default target/python-venv); SAWDRIVE_CLI (the `sawdrive`
# binary the tests compare with; default target/debug/sawdrive, built if missing).
set -euo pipefail
cd "$(dirname "$0")/.."
repo="$(pwd)"
venv="${SAWDRIVE_PYTHON_VENV:-target/python-venv}"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
python="$(cd "$(dirname "$venv/bin/python")" && pwd)/python"
"$python" -m pip install --quiet --disable-pip-version-check maturin numpy pandas matplotlib pytest
# Source paths of the workspace's crates are recorded relative to the checkout (as in the
# command-line binary), so the extension holds no path of this folder. The native linux tag, as
# `pip install ./python` builds it: the extension links the system's freetype and fontconfig
# (the charts' fonts) instead of bundling them.
wheels="$repo/target/python-wheel"
rm -rf "$wheels"
(cd python && RUSTFLAGS="${RUSTFLAGS:-} --remap-path-prefix=$repo/=" \
  "$python" -m maturin build --release --quiet --compatibility linux --interpreter "$python" \
  --out "$wheels")
wheel="$(ls "$wheels"/sawdrive-*.whl)"
"$python" -m pip install --quiet --disable-pip-version-check --force-reinstall --no-deps "$wheel"
# From the repository root: python/ itself would shadow the installed package.
SAWDRIVE_WHEEL="$wheel" "$python" -m pytest python/tests -q "$@"
