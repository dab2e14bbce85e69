"""Sweeps from Python: the results table as a DataFrame, progress, bad input."""

import json
import time

import numpy as np
import pytest

import sawdrive
from conftest import SMALL_SCENE, SMALL_SWEEP, run_cli


def given_eta_sweep(tmp_path):
    """Two preloads of the small scene with η given (dynamic stage only: fast)."""
    path = tmp_path / "given.toml"
    path.write_text(
        f'name = "given"\nscene = "{SMALL_SCENE}"\n[set]\neffective_ratio = 0.36\n'
        '[grid]\npreload = ["0.2 N", "0.4 N"]\n[[charts]]\nx = "preload_n"\ny = "stall_thrust_n"\n'
    )
    return path


def test_sweep_rows_equal_the_dynamic_stage_and_the_cli(cli, tmp_path):
    pd = pytest.importorskip("pandas")
    file = given_eta_sweep(tmp_path)
    result = sawdrive.sweep(file, out=tmp_path / "py", jobs=1)
    frame = result.frame()
    assert isinstance(frame, pd.DataFrame) and len(frame) == len(result) == 2
    assert list(frame["preload"]) == ["0.2 N", "0.4 N"], "grid values as written"
    for _, row in frame.iterrows():
        scene = sawdrive.Scene.load(SMALL_SCENE).set("effective_ratio", 0.36).set("preload", row["preload"])
        assert row["stall_thrust_n"] == sawdrive.dynamic(scene).stall_thrust_n, "stall thrust (N) of the point"
    assert (tmp_path / "py" / "given" / "results.csv").exists()
    shown = run_cli(cli, "sweep", str(file), "--out", str(tmp_path / "cli"), "--json", cwd=tmp_path)
    rows = json.loads(shown.stdout)
    assert [r["values"] for r in rows] == [r["values"] for r in result.rows], "same table as the CLI"
    again = sawdrive.sweep(file, out=tmp_path / "py", jobs=1)
    assert again.resumed == 2, "a second run resumes every saved point"
    assert sawdrive.sweep_points(file)[1]["overrides"] == ["effective_ratio=0.36", "preload=0.4 N"]


def test_fem_sweep_reports_saved_points_as_progress(tmp_path):
    ticks = []
    result = sawdrive.sweep(SMALL_SWEEP, out=tmp_path, jobs=1, progress=lambda *t: ticks.append(t))
    assert len(result) == 2
    eta = [row["values"]["effective_contact_ratio"] for row in result.rows]
    assert all(0 < e <= 1.5 for e in eta), "η of each point from the static FEM"
    assert ticks, "a sweep with FEM runs longer than one tick"
    assert all(total == 2 and 0 <= done <= 2 for _, done, total in ticks), "points done / total"
    assert [t[0] for t in ticks] == sorted(t[0] for t in ticks), "elapsed time (s) grows"


def test_bad_jobs_and_bad_sweep_files_are_value_errors(tmp_path):
    file = given_eta_sweep(tmp_path)
    with pytest.raises(ValueError) as error:
        sawdrive.sweep(file, out=tmp_path, jobs=0)
    assert "--jobs 0" in str(error.value)
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "bad"\ngrdi = 3\n')
    with pytest.raises(sawdrive.SweepError) as error:
        sawdrive.sweep(bad, out=tmp_path)
    assert "grdi" in str(error.value)
    assert not (tmp_path / "bad").exists()


def test_failed_points_raise_with_the_completed_ones(tmp_path):
    file = tmp_path / "half.toml"
    file.write_text(
        f'name = "half"\nscene = "{SMALL_SCENE}"\n[set]\neffective_ratio = 0.36\n'
        '[grid]\n"model.lumped.regularization_velocity" = ["auto", "1 m/s"]\n'
    )
    with pytest.raises(sawdrive.SweepPointsFailed) as error:
        sawdrive.sweep(file, out=tmp_path, jobs=1)
    assert "1 of 2 sweep points failed" in str(error.value)
    assert "model.lumped.regularization_velocity" in error.value.failures[0][1]
    assert len(error.value.result) == 1, "the completed point is kept"


def slow_sweep(tmp_path, points=8):
    """`points` preloads of the small scene through a 200-period transient (≈ 0.2 s a point)."""
    path = tmp_path / "slow.toml"
    preloads = ", ".join(f'"{0.1 + 0.05 * k:.2f} N"' for k in range(points))
    path.write_text(
        f'name = "slow"\nscene = "{SMALL_SCENE}"\n[set]\neffective_ratio = 0.36\n'
        f'"model.dynamics" = "transient"\n"model.transient.periods" = 200\n[grid]\npreload = [{preloads}]\n'
    )
    return path


def saved_points(folder):
    return len(list(folder.glob("*.json"))) if folder.exists() else 0


def test_an_interrupted_sweep_starts_no_further_point_and_a_rerun_completes_it(tmp_path):
    file, out = slow_sweep(tmp_path), tmp_path / "out"
    points = out / "slow" / "points"

    def interrupt(elapsed_s, done, total):
        if elapsed_s > 0.4:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sawdrive.sweep(file, out=out, jobs=1, progress=interrupt)
    # The point running at the interrupt stops inside its stages (not saved); then nothing moves.
    seen, still_since = saved_points(points), time.monotonic()
    while time.monotonic() - still_since < 2.0:
        time.sleep(0.1)
        if saved_points(points) != seen:
            seen, still_since = saved_points(points), time.monotonic()
    assert seen < 8, f"the sweep stopped after the interrupt ({seen} of 8 points saved)"
    assert not (out / "slow" / "results.csv").exists(), "no results table after an interrupt"
    result = sawdrive.sweep(file, out=out, jobs=1, progress=False)
    assert len(result) == 8 and result.resumed == seen, "the rerun resumes the saved points"
