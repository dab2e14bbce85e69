"""The package as a user gets it: the wheel `python/test.sh` builds (`maturin build`), installed
into a brand-new virtual environment, runs a meshed static stage (gmsh through the package, the
embedded strip script) and a dynamic stage from an empty folder, with `HOME` and
`XDG_CACHE_HOME` there, no other variable but `PATH`, and the checkout out of reach: the
current folder is elsewhere, the extension holds no path of the checkout's `crates/`, and (where
`strace` exists) the process opens no file under the checkout.

The wheel is `$SAWDRIVE_WHEEL` (set by `python/test.sh`); without it the tests are skipped.
"""

import json
import os
import shutil
import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest

from conftest import REPO, run_cli

WHEEL = os.environ.get("SAWDRIVE_WHEEL")
pytestmark = pytest.mark.skipif(not WHEEL, reason="python/test.sh builds the wheel and sets SAWDRIVE_WHEEL")

# A 6 × 6 post strip (Tet4): meshed by gmsh, no committed mesh matches it.
SMALL_SCENE = """name = "wheel"
[slider]
length = "0.24 mm"
width = "0.24 mm"
[posts]
count = "6x6"
array = "0.24 mm"
[load]
preload = "0.144 N"
[static]
element_order = 1
"""

# Run inside the fresh environment, from the empty work folder: a meshed static stage (no
# results folder, no FEM result cache: the mesh goes to the cache folder) and a dynamic stage
# at a given η (period average); prints what the test checks.
SCRIPT = """
import json, sys
import sawdrive
scene = sawdrive.Scene.load("scene.toml")
st = sawdrive.static(scene, progress=False)
dy = sawdrive.dynamic(scene.copy().set("effective_ratio", 0.6), progress=False)
print(json.dumps({
    "package": sawdrive.__file__,
    "eta": st.effective_ratio,
    "forces_shape": list(st.post_forces_n.shape),
    "stall_thrust_n": dy.stall_thrust_n,
    "no_load_speed_m_per_s": dy.no_load_speed_m_per_s,
}))
"""


def wheel() -> Path:
    return Path(WHEEL).resolve()


@pytest.fixture(scope="module")
def fresh(tmp_path_factory) -> Path:
    """A temporary root with `venv/` (the wheel installed into a new environment) and empty
    `work/`, `home/`, `xdg/` folders."""
    root = tmp_path_factory.mktemp("wheel").resolve()
    for name in ("work", "home", "xdg"):
        (root / name).mkdir()
    venv.create(root / "venv", with_pip=True)
    pip = [str(root / "venv" / "bin" / "python"), "-m", "pip", "install", "--quiet",
           "--disable-pip-version-check"]
    subprocess.run(pip + [str(wheel())], check=True, cwd=root)
    (root / "work" / "scene.toml").write_text(SMALL_SCENE)
    (root / "work" / "run.py").write_text(SCRIPT)
    return root


def run_in_fresh_venv(root: Path, trace: Path = None) -> dict:
    """The script in `work/` with only PATH, HOME and XDG_CACHE_HOME set; its JSON line."""
    command = [str(root / "venv" / "bin" / "python"), "run.py"]
    if trace is not None:
        command = ["strace", "-f", "-qq", "-e", "trace=%file", "-o", str(trace)] + command
    env = {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "HOME": str(root / "home"),
           "XDG_CACHE_HOME": str(root / "xdg")}
    done = subprocess.run(command, cwd=root / "work", env=env, capture_output=True, text=True)
    assert done.returncode == 0, f"the wheel's package failed:\n{done.stderr}"
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_wheel_extension_holds_no_path_of_the_checkouts_crates_folder():
    needle = str((REPO / "crates").resolve()).encode()
    with zipfile.ZipFile(wheel()) as z:
        natives = [n for n in z.namelist() if n.endswith((".so", ".pyd", ".dylib"))]
        assert natives, f"no extension module in {wheel().name}: {z.namelist()}"
        for name in natives:
            data = z.read(name)
            at = data.find(needle)
            assert at < 0, f"{name} names the checkout's crates folder: {data[at:at + 160]!r}"


def test_wheel_in_a_fresh_venv_meshes_and_runs_from_an_empty_folder(fresh, cli, tmp_path):
    trace = fresh / "files.trace" if shutil.which("strace") else None
    got = run_in_fresh_venv(fresh, trace)
    # The installed package, not python/sawdrive of the checkout.
    assert Path(got["package"]).resolve().is_relative_to(fresh / "venv"), got["package"]
    # Meshed by gmsh from the embedded script into $XDG_CACHE_HOME/sawdrive.
    geo = fresh / "xdg" / "sawdrive" / "geo"
    assert (geo / "slider-strip.geo").exists(), f"embedded gmsh script in the cache: {list(geo.glob('*'))}"
    meshes = list((fresh / "xdg" / "sawdrive" / "meshes").glob("*.msh"))
    assert meshes, "strip mesh in $XDG_CACHE_HOME/sawdrive/meshes"
    assert not (fresh / "home" / ".cache").exists(), "XDG_CACHE_HOME wins over HOME/.cache"
    written = sorted(p.name for p in (fresh / "work").iterdir())
    assert written == ["run.py", "scene.toml"], f"nothing written without out=: {written}"
    assert 0 < got["eta"] <= 1.5 and got["forces_shape"][1] == 6, got
    # The dynamic stage as the command line gives it.
    (tmp_path / "scene.toml").write_text(SMALL_SCENE)
    done = run_cli(cli, "dynamic", "scene.toml", "--set", "effective_ratio=0.6", "--json",
                   cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    expected = json.loads(done.stdout)
    assert got["stall_thrust_n"] == expected["stall_thrust_n"]
    assert got["no_load_speed_m_per_s"] == expected["no_load_speed_m_per_s"]
    if trace is not None:
        checkout = str(REPO.resolve())
        opened = [line for line in trace.read_text().splitlines()
                  if f'"{checkout}/' in line or f'"{checkout}"' in line]
        assert not opened, "the run touched the checkout:\n" + "\n".join(opened[:10])
