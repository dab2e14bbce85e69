"""Springs, static, dynamic and the whole pipeline from Python, against the command line."""

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import sawdrive
from conftest import SMALL_SCENE, run_cli

#: η given where the FEM is not the point (the paper's 36 %).
ETA = 0.36


def cli_json(cli, tmp_path, *args):
    shown = run_cli(cli, *args, "--json", cwd=tmp_path)
    assert shown.returncode == 0, shown.stderr
    return json.loads(shown.stdout)


def test_springs_equal_the_cli(cli, tmp_path):
    k = sawdrive.springs(diameter="20 um")
    expected = cli_json(cli, tmp_path, "springs", "--diameter", "20um")
    assert k.to_dict() == expected, "the four springs and their series values (N/m)"
    assert k.k_n_n_per_m == pytest.approx(1.786e6, rel=1e-3), "k_n of a 20 µm post (README)"
    assert sawdrive.springs(sawdrive.Scene.default()).to_dict() == expected, "the default scene's posts"
    thin = sawdrive.springs(sawdrive.Scene.default().set("posts.diameter", "10 um"))
    assert thin.k_n_n_per_m < k.k_n_n_per_m, "a thinner post is softer"


@pytest.mark.parametrize(
    "kwargs, named", [({"diameter": "20"}, "--diameter"), ({"diameter": "-5 um"}, "--diameter"),
                      ({"diameter": "20 um", "stator": "steel"}, "--stator steel")]
)
def test_bad_spring_arguments_are_value_errors_naming_them(kwargs, named):
    with pytest.raises(ValueError) as error:
        sawdrive.springs(**kwargs)
    assert named in str(error.value)


def test_dynamic_equals_the_cli_json_to_the_last_bit(cli, tmp_path):
    scene = sawdrive.Scene.default().set("preload", "20 N").set("effective_ratio", ETA)
    r = sawdrive.dynamic(scene)
    expected = cli_json(cli, tmp_path, "dynamic", "--set", "preload=20N", "--set", f"effective_ratio={ETA}")
    assert r.stall_thrust_n == expected["stall_thrust_n"], "stall thrust (N), bit for bit"
    assert r.no_load_speed_m_per_s == expected["no_load_speed_m_per_s"], "no-load speed (m/s)"
    curve = np.array([[p["speed_m_per_s"], p["thrust_n"]] for p in expected["curve"]])
    assert r.curve.shape == (len(expected["curve"]), 2) and r.curve.dtype == np.float64
    assert np.array_equal(r.curve, curve), "curve (speed m/s, thrust N), bit for bit"
    assert r.curve_points == expected["curve"], "every column of the curve"
    for key, value in expected.items():
        if key not in ("wall_time_s", "curve"):
            assert r.data[key] == value, f"field {key} as the CLI prints it"
            assert getattr(r, key) == value, f"field {key} read as an attribute, bit for bit"
    assert r.effective_ratio == ETA and r.effective_ratio_source == "given"
    assert r.folder is None, "nothing written without out="


def test_dynamic_curve_frame_has_the_curve_csv_columns():
    pd = pytest.importorskip("pandas")
    r = sawdrive.dynamic(sawdrive.Scene.default().set("effective_ratio", ETA))
    frame = r.curve_frame()
    assert isinstance(frame, pd.DataFrame)
    assert list(frame.columns[:2]) == ["speed_m_per_s", "thrust_n"]
    assert np.array_equal(frame[["speed_m_per_s", "thrust_n"]].to_numpy(), r.curve)
    assert 0 < r.stall_thrust_n <= r.friction_limit_n, "stall thrust (N) within the friction limit μP"


def test_dynamic_writes_the_cli_files_with_out(tmp_path):
    scene = sawdrive.Scene.load(SMALL_SCENE).set("effective_ratio", ETA)
    r = sawdrive.dynamic(scene, out=tmp_path / "out")
    folder = Path(r.folder)
    assert folder == tmp_path / "out" / "small-strip" / "dynamic"
    written = json.loads((folder / "dynamic.json").read_text())
    assert written["stall_thrust_n"] == r.stall_thrust_n
    assert (folder / "curve.csv").exists()


def test_static_small_case_gives_arrays_per_phase_and_the_cli_eta(cli, tmp_path, capsys):
    s = sawdrive.static(sawdrive.Scene.load(SMALL_SCENE), out=tmp_path / "out", progress=True)
    phases, posts = s.post_forces_n.shape
    assert phases == 4, "static.phases of the default scene"
    assert posts == s.posts_in_strip and s.post_x_m.shape == (posts,)
    assert s.post_gaps_m.shape == s.in_contact.shape == (phases, posts)
    assert (s.post_forces_n >= 0).all(), "contact forces are compressive (N ≥ 0)"
    assert (s.post_gaps_m >= 0).all(), "gaps are open (m ≥ 0)"
    assert np.all(s.post_forces_n[~s.in_contact] == 0), "no force on a post out of contact"
    assert s.in_contact.any() and not s.in_contact.all(), "posts on the wave: some touch, some not"
    assert 0 < s.effective_ratio <= 1.5 and s.effective_ratio == s.effective_contact_ratio
    expected = cli_json(cli, tmp_path, "static", str(SMALL_SCENE))
    assert s.effective_contact_ratio == expected["effective_contact_ratio"], "η as `sawdrive static --json`"
    assert Path(s.folder, "static.json").exists()
    err = capsys.readouterr().err
    if s.report["timings"]["wall_time_s"] > 1.0:
        assert "sawdrive static" in err, "progress line shown when asked"
        assert err.endswith("\r"), "and erased at the end"


def test_run_writes_summary_and_out_none_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    scene = sawdrive.Scene.load(SMALL_SCENE).set("effective_ratio", ETA)
    r = sawdrive.run(scene, out=tmp_path / "out")
    summary = json.loads(Path(r.folder, "summary.json").read_text())
    assert summary["stall_thrust_n"] == r.stall_thrust_n == sawdrive.dynamic(scene).stall_thrust_n
    assert np.array_equal(r.curve, sawdrive.dynamic(scene).curve)
    assert sorted(os.listdir(tmp_path / "out")) == ["small-strip"], "no scratch folder left"
    again = sawdrive.run(scene, out=None)
    assert again.folder is None and again.stall_thrust_n == r.stall_thrust_n
    assert sorted(os.listdir(tmp_path)) == ["out"], "out=None writes nothing"


def wait_for_scratch_to_go(out: Path, timeout_s: float = 120.0) -> None:
    """Wait until the background work of an interrupted call removed its scratch folder."""
    deadline = time.monotonic() + timeout_s
    while any(p.name.startswith(".sawdrive-python-") for p in out.iterdir()):
        assert time.monotonic() < deadline, "the interrupted call's scratch folder was removed"
        time.sleep(0.1)


def long_scene():
    """The small scene through a 4000-period transient (≈ 4 s of work): long enough for an
    interrupt at 0.3 s, whatever the machine (its FEM run alone now takes ≈ 0.3 s)."""
    scene = sawdrive.Scene.load(SMALL_SCENE).set("effective_ratio", ETA)
    return scene.set("model.dynamics", "transient").set("model.transient.periods", 4000)


def test_interrupted_run_keeps_the_earlier_results(tmp_path):
    out = tmp_path / "out"
    given = sawdrive.Scene.load(SMALL_SCENE).set("effective_ratio", ETA)
    first = sawdrive.run(given, out=out)
    before = Path(first.folder, "summary.json").read_bytes()

    def interrupt(elapsed_s, done, total):
        raise KeyboardInterrupt

    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        sawdrive.run(long_scene(), out=out, cache=False, progress=interrupt)
    assert time.monotonic() - started < 1.0, "the interrupt is immediate"
    wait_for_scratch_to_go(out)
    assert Path(first.folder, "summary.json").read_bytes() == before, "earlier results untouched"
    assert sorted(p.name for p in out.iterdir()) == ["small-strip"], "no half-written folder"


def test_an_interrupted_run_leaves_no_scratch_folder_when_the_interpreter_exits(tmp_path):
    # The interpreter exits right after the interrupt, before the background stage has ended
    # (20000 periods: seconds of work): the folder is removed at exit, not left behind.
    out = tmp_path / "out"
    code = f"""
import sawdrive
scene = sawdrive.Scene.load({str(SMALL_SCENE)!r}).set("effective_ratio", {ETA})
scene = scene.set("model.dynamics", "transient").set("model.transient.periods", 20000)
def interrupt(elapsed_s, done, total):
    raise KeyboardInterrupt
try:
    sawdrive.run(scene, out={str(out)!r}, cache=False, progress=interrupt)
except KeyboardInterrupt:
    pass
"""
    subprocess.run([sys.executable, "-c", code], check=True, timeout=300, cwd=tmp_path)
    assert out.is_dir(), "the call made its scratch folder in OUT"
    assert not any(p.name.startswith(".sawdrive-python-") for p in out.iterdir()), "no litter"


def test_an_interrupt_stops_the_dynamic_stage_instead_of_finishing_it_in_the_background(tmp_path):
    # 16 transient runs of 20000 periods: ≈ 21 s of CPU uninterrupted, ≈ 1.3 s per run (small
    # scene, η given). The interrupt (first progress tick) cancels the stage, which stops before
    # its next run. CPU time (all threads of this process) is what load from other processes
    # does not inflate; the bound leaves room for the run in progress and a few more.
    out = tmp_path / "out"
    scene = long_scene().set("model.transient.periods", 20000)

    def interrupt(elapsed_s, done, total):
        raise KeyboardInterrupt

    cpu = time.process_time()
    with pytest.raises(KeyboardInterrupt):
        sawdrive.run(scene, out=out, cache=False, progress=interrupt)
    wait_for_scratch_to_go(out)  # the scratch folder goes when the background job ends
    spent_s = time.process_time() - cpu
    assert spent_s < 8.0, f"the cancelled stage stopped early: {spent_s:.1f} s of CPU of ≈ 21 s"
    assert not (out / "small-strip").exists(), "a cancelled run writes no results"


def test_ctrl_c_raises_keyboard_interrupt_during_a_long_call(tmp_path):
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    started = time.monotonic()
    try:
        with pytest.raises(KeyboardInterrupt):
            sawdrive.run(long_scene(), out=tmp_path / "out", cache=False, progress=False)
    finally:
        timer.cancel()  # never let a late SIGINT reach pytest itself
    assert time.monotonic() - started < 2.0, "SIGINT handled within a tick"
    wait_for_scratch_to_go(tmp_path / "out")
    assert not (tmp_path / "out" / "small-strip").exists(), "an interrupted run writes no results"


def test_long_calls_release_the_gil():
    done = threading.Event()
    result = {}

    def work():
        result["static"] = sawdrive.static(sawdrive.Scene.load(SMALL_SCENE), progress=False)
        done.set()

    thread = threading.Thread(target=work)
    ticks = 0
    thread.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    thread.join()
    seconds = result["static"].report["timings"]["wall_time_s"]
    assert ticks > 0.2 * seconds / 0.001, f"Python ran {ticks} ticks during a {seconds:.2f} s static stage"


def test_stage_failure_is_a_pipeline_error_with_the_cli_message(cli, tmp_path):
    overrides = ["effective_ratio=0.36", "model.transient.periods=20"]  # periods with the period average: refused
    scene = sawdrive.Scene.default()
    for o in overrides:
        scene.set(*o.split("=", 1))
    with pytest.raises(sawdrive.PipelineError) as error:
        sawdrive.dynamic(scene)
    assert "model.transient.periods" in str(error.value)
    shown = run_cli(cli, "dynamic", *sum((["--set", o] for o in overrides), []), cwd=tmp_path)
    assert shown.stderr.strip() == f"error: {error.value}", "same one-line message as the CLI"
