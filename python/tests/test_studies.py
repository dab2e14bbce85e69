"""UQ and design from Python: the library functions `sawdrive uq` and `sawdrive design` call,
on tiny inputs (4 samples of a 10 × 10 slider; a 3-point design search)."""

import json
import time

import numpy as np
import pytest

import sawdrive
from conftest import run_cli

#: A 10 × 10 slider at 40 mN a post (a working motor whose bands spread), as the library's tests.
SMALL = ["posts.count=10x10", "posts.array=0.4mm", "load.preload=4N"]
SCATTER = {"posts.height_scatter": "5 nm", "friction": 0.03, "load.preload": "0.2 N"}

DESIGN = """
name = "small"
objective = "max_output_power_w"
set = { "posts.count" = "10x10", "posts.array" = "0.4mm" }
[variables]
"load.preload" = ["1 N", "4 N"]
[optimiser]
presearch_points = 3
starts = 1
max_evaluations_per_start = 3
finalists = 1
"""


def small_scene():
    scene = sawdrive.Scene.default()
    for override in SMALL:
        scene.set(*override.split("=", 1))
    return scene


def cli_json(cli, tmp_path, *args):
    shown = run_cli(cli, *args, "--json", cwd=tmp_path)
    assert shown.returncode == 0, shown.stderr
    return json.loads(shown.stdout)


def test_uq_bands_equal_the_cli_to_the_last_bit(cli, tmp_path):
    r = sawdrive.uq(small_scene(), scatter=SCATTER, samples=4, seed=3, out=tmp_path / "py", progress=False)
    sets = sum((["--set", o] for o in SMALL + [f"scatter.{k}={v}" for k, v in SCATTER.items()]), [])
    expected = cli_json(cli, tmp_path, "uq", *sets, "--samples", "4", "--seed", "3", "--out", str(tmp_path / "cli"))
    for output in sawdrive.UQ_OUTPUTS:
        assert r.data[output] == expected[output], f"band of {output} as `sawdrive uq --json`"
    assert r.curve_band.shape == (len(expected["curve_band"]["speed_m_per_s"]), 4)
    assert np.array_equal(r.curve_band[:, 2], expected["curve_band"]["thrust_p50_n"]), "median thrust (N)"
    assert r.samples == 4 and r.scatter["height_scatter_m"] == 5e-9, "scatter in SI (m)"
    assert r.stall_thrust_n["p5"] <= r.stall_thrust_n["p50"] <= r.stall_thrust_n["p95"], "stall thrust band (N)"


def test_uq_frames_hold_every_sample_and_band(tmp_path):
    pd = pytest.importorskip("pandas")
    r = sawdrive.uq(small_scene(), scatter=SCATTER, samples=4, out=tmp_path, progress=False)
    samples = r.samples_frame()
    assert isinstance(samples, pd.DataFrame) and len(samples) == 4, "one row per sample"
    assert "stall_thrust_n" in samples.columns
    bands = r.bands_frame()
    assert list(bands.index) == list(sawdrive.UQ_OUTPUTS)
    assert bands.loc["stall_thrust_n", "p50"] == r.stall_thrust_n["p50"], "median stall thrust (N)"


@pytest.mark.parametrize(
    "kwargs, named",
    [
        ({"samples": 0}, "--samples"),
        ({"samples": 2**32}, "--samples"),
        ({"samples": 2, "scatter": {"posts.heigth_scatter": "5 nm"}}, "heigth_scatter"),
        ({"samples": 2, "scatter": {"posts.height_scatter": "5 parsec"}}, "posts.height_scatter"),
        ({"samples": 2, "scatter": {"height_scatter": "5 nm"}}, "scatter.posts.height_scatter"),
    ],
)
def test_bad_uq_input_is_a_value_error_naming_the_key(tmp_path, kwargs, named):
    with pytest.raises(ValueError) as error:
        sawdrive.uq(small_scene(), out=tmp_path, progress=False, **kwargs)
    assert named in str(error.value)
    assert not any(tmp_path.iterdir()), "nothing written for refused input"


def test_design_optimum_equals_the_cli_and_is_a_frame(cli, tmp_path):
    file = tmp_path / "small.toml"
    file.write_text(DESIGN)
    r = sawdrive.design(file, out=tmp_path / "py", progress=False)
    assert r.optimum["fidelity"] == "lattice-slider", "optimum confirmed by the whole-slider model"
    assert 1.0 <= r.optimum["variables"]["preload_n"] <= 4.0, "optimal preload (N) within its bounds"
    expected = cli_json(cli, tmp_path, "design", str(file), "--out", str(tmp_path / "cli"))
    assert r.optimum == expected["optimum"], "optimum as `sawdrive design --json`"
    frame = r.evaluations_frame()
    assert len(frame) == len(r.evaluations) and "preload_n" in frame.columns
    assert r.folder.endswith("small")


def test_bad_design_file_is_a_value_error_naming_the_key(tmp_path):
    file = tmp_path / "bad.toml"
    file.write_text(DESIGN.replace('["1 N", "4 N"]', '["4 N", "1 N"]'))
    with pytest.raises(ValueError) as error:
        sawdrive.design(file, out=tmp_path / "out", progress=False)
    assert "variables.load.preload" in str(error.value)
    assert not (tmp_path / "out").exists()


def test_an_interrupted_uq_commits_no_results_folder(tmp_path):
    def interrupt(elapsed_s, done, total):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sawdrive.uq(small_scene(), scatter=SCATTER, samples=64, out=tmp_path, progress=interrupt)
    # The samples finish in the background (saved for a rerun); the staged folder is dropped.
    deadline = time.monotonic() + 300
    while any(".staging-" in p.name for p in tmp_path.iterdir()):
        assert time.monotonic() < deadline, "the background UQ ended"
        time.sleep(0.2)
    assert not (tmp_path / "paper-motor-uq").exists(), "an interrupted call commits nothing"
    again = sawdrive.uq(small_scene(), scatter=SCATTER, samples=64, out=tmp_path, progress=False)
    assert again.data["resumed_samples"] == 64, "the samples computed in the background are kept"
