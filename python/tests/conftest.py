"""Shared fixtures: the repository's paths and the `sawdrive` command line to compare with."""

import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SMALL_SCENE = REPO / "tests" / "scenes" / "small-strip.toml"
SMALL_SWEEP = REPO / "tests" / "sweeps" / "small-preload.toml"


@pytest.fixture(scope="session")
def cli() -> Path:
    """The `sawdrive` binary: $SAWDRIVE_CLI, or target/{release,debug}/sawdrive of this
    repository (built with `cargo build -p sawdrive-cli --bin sawdrive` when missing)."""
    given = os.environ.get("SAWDRIVE_CLI")
    if given:
        return Path(given)
    for profile in ("debug", "release"):
        binary = REPO / "target" / profile / "sawdrive"
        if binary.exists():
            return binary
    subprocess.run(["cargo", "build", "-p", "sawdrive-cli", "--bin", "sawdrive"], cwd=REPO, check=True)
    return REPO / "target" / "debug" / "sawdrive"


def run_cli(cli: Path, *args: str, cwd: Path) -> subprocess.CompletedProcess:
    """Run the command line in `cwd` (results land in cwd/out)."""
    return subprocess.run([str(cli), *args], cwd=cwd, capture_output=True, text=True)
