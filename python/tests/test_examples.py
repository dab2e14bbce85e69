"""The post-count example (paper Figs 7–8) runs and reproduces the committed FEM study."""

import csv
import importlib.util
from pathlib import Path

import pytest

from conftest import REPO

EXAMPLE = REPO / "python" / "examples" / "post_count_study.py"


def load_example():
    spec = importlib.util.spec_from_file_location("post_count_study", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_post_count_example_reproduces_figs_7_and_8(tmp_path):
    pytest.importorskip("matplotlib")
    # The two stiffest arrays (period average, ≈ 1 ms a point) and the softest (transient,
    # ≈ 10 s a point) at a moderate and the highest preload; all 25 points: the example's default.
    rows = load_example().main(["--out", str(tmp_path), "--arrays", "100x100,80x80,33x33",
                                "--preloads", "40 N,100 N"])
    for chart in ("fig7_stall_thrust.png", "fig8_no_load_speed.png"):
        assert (tmp_path / chart).stat().st_size > 10_000, f"{chart} drawn"
    with open(REPO / "validation/paper-figures/results/fig7-8-post-count.csv", newline="") as f:
        committed = {(r["variant"], f"{float(r['preload_n']):g} N"): r for r in csv.DictReader(f)}
    assert len(rows) == 6 and len(committed) == 25
    for row in rows:
        cli = committed[(row["variant"], row["preload"])]
        for column in ("stall_thrust_n", "no_load_speed_m_per_s"):
            assert row[column] == pytest.approx(float(cli[column]), rel=1e-9, abs=1e-12), (
                f"{column} of {row['variant']} at {row['preload']} as the committed CLI sweep")
    by = {(r["variant"], r["preload"]): r for r in rows}
    for preload in ("40 N", "100 N"):
        thrust = [by[(v, preload)]["stall_thrust_n"] for v in ("10000 posts", "6400 posts", "1089 posts")]
        assert thrust == sorted(thrust, reverse=True), f"more posts, more thrust at {preload} (Fig. 7)"
