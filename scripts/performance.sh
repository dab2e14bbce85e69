#!/usr/bin/env bash
# Runs the project's benchmarks and timing scripts and (re)writes docs/performance.md from their
# output, one section per command (scripts/performance.py holds the sections and the parsing).
#
#   scripts/performance.sh [--quick] [--section NAME ...] [--list]
#
# --section NAME ... regenerates only those sections (the rest of the file is kept as it was);
# --list names the sections; --quick runs each at its cheaper setting (each section prints the
# command that ran).
set -euo pipefail
exec python3 "$(dirname "${BASH_SOURCE[0]}")/performance.py" "$@"
