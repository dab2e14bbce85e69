"""Scenes from Python: default, files, overrides, SI resolution, errors naming the key."""

import pytest

import sawdrive
from conftest import SMALL_SCENE, run_cli


def test_default_scene_resolves_to_si_like_the_cli(cli, tmp_path):
    scene = sawdrive.Scene.default()
    resolved = scene.resolve()
    assert resolved["load"]["preload_n"] == 40.0, "default preload (N)"
    assert resolved["name"] == scene.name == "paper-motor"
    shown = run_cli(cli, "scene", "--resolve", "--json", cwd=tmp_path)
    import json

    assert resolved == json.loads(shown.stdout), "resolved scene equals `sawdrive scene --resolve --json`"
    assert "preload_n = 40.0" in scene.to_toml()
    assert sawdrive.default_scene_toml() == run_cli(cli, "scene", cwd=tmp_path).stdout


def test_set_overrides_reach_the_resolved_scene():
    scene = sawdrive.Scene.default().set("preload", "20 N").set("posts.count", "50x50")
    scene.set("friction", 0.25).set("effective_ratio", 0.36)
    resolved = scene.resolve()
    assert resolved["load"]["preload_n"] == 20.0, "preload (N)"
    assert resolved["posts"]["count"] == 2500, "post count"
    assert resolved["friction"]["mu_kinetic"] == 0.25 and resolved["friction"]["mu_static"] == 0.25
    assert resolved["contact"]["effective_ratio"] == 0.36, "η"
    copy = scene.copy().set("preload", "30 N")
    assert scene.resolve()["load"]["preload_n"] == 20.0, "a copy's change leaves the original"
    assert copy.resolve()["load"]["preload_n"] == 30.0


def test_scene_file_loads_with_its_relative_mesh():
    scene = sawdrive.Scene.load(SMALL_SCENE)
    resolved = scene.resolve()
    assert resolved["name"] == "small-strip"
    assert resolved["posts"]["count"] == 100, "10x10 posts"
    assert resolved["slider"]["length_m"] == pytest.approx(0.4e-3), "slider length (m)"


@pytest.mark.parametrize(
    "key, value, named",
    [
        ("preload", "20", "load.preload"),  # no unit
        ("preload", "20 kg", "load.preload"),  # wrong unit
        ("preload", 20, "load.preload"),  # a number for a dimensional key
        ("posts.count", "many", "posts.count"),
        ("posts.colour", "red", "colour"),  # unknown key
        ("friction", "high", "friction"),
        ("preload", [20, "N"], "preload"),  # a Python type no scene takes
        ("effective_ratio", float("nan"), "effective_ratio"),
    ],
)
def test_bad_types_and_units_raise_value_error_naming_the_key(key, value, named):
    scene = sawdrive.Scene.default().set("preload", "25 N")
    with pytest.raises(ValueError) as error:
        scene.set(key, value)
    assert isinstance(error.value, sawdrive.SceneError)
    assert named in str(error.value), f"message names {named}: {error.value}"
    assert "\n" not in str(error.value), "one line"
    assert scene.resolve()["load"]["preload_n"] == 25.0, "the scene keeps its earlier overrides"


def test_scene_errors_carry_the_cli_one_line_message(cli, tmp_path):
    for override in ["preload=20", "posts.count=0x5", "wave.frequency=9.61 MHz extra"]:
        key, value = override.split("=", 1)
        with pytest.raises(sawdrive.SceneError) as error:
            sawdrive.Scene.default().set(key, value)
        shown = run_cli(cli, "scene", "--resolve", "--set", override, cwd=tmp_path)
        assert shown.returncode != 0
        assert shown.stderr.strip() == f"error: {error.value}", "same message as the CLI"


def test_missing_scene_file_is_an_os_error_naming_it(tmp_path):
    missing = tmp_path / "nope.toml"
    with pytest.raises(OSError) as error:
        sawdrive.Scene.load(missing)
    assert isinstance(error.value, sawdrive.SceneFileError)
    assert str(missing) in str(error.value)
