"""The post-count study of the paper's Figs 7–8 from Python: stall thrust and no-load speed
against preload for 10000, 6400, 4356, 2500 and 1089 posts of 20 µm in a 4 × 4 mm array.

Two sources of η (the effective contact ratio of each post array and preload):

- ``--eta committed`` (default, seconds): η of every point from the static FEM as committed in
  ``validation/paper-figures/fig7-8-post-count/results.csv``; only the dynamic stage runs, once
  per point, through ``sawdrive.dynamic``.
- ``--eta fem`` (minutes; ≈ 134 s cold on 2 cores, ≈ 68 s with the FEM cache): the sweep file
  ``validation/paper-figures/fig7-8-post-count.toml`` through ``sawdrive.sweep``: every point
  runs the static FEM and the dynamics.

Writes ``fig7_stall_thrust.png``, ``fig8_no_load_speed.png`` and ``post_count.csv`` into
``--out`` (default ``out/python-post-count``) and prints the table.

    python python/examples/post_count_study.py [--eta committed|fem] [--out DIR]
        [--arrays 100x100,80x80,...] [--preloads "10 N,40 N,..."]

``--arrays``/``--preloads`` pick a subset of the committed points (``--eta committed`` only;
the default is all 25). The 10000- and 6400-post arrays run the period average (≈ 1 ms a point),
the others the transient (their pitch does not divide the wavelength: ≈ 10–20 s a point on 2
shared cores).
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path
from typing import Dict, List

import sawdrive

REPO = Path(__file__).resolve().parents[2]
STUDY = REPO / "validation" / "paper-figures" / "results"
SWEEP_FILE = REPO / "validation" / "paper-figures" / "fig7-8-post-count.toml"
#: Post arrays of Figs 7–8 (count along x and y; 20 µm posts in a 4 mm array).
ARRAYS = {"10000 posts": "100x100", "6400 posts": "80x80", "4356 posts": "66x66",
          "2500 posts": "50x50", "1089 posts": "33x33"}
PRELOADS = ["10 N", "20 N", "40 N", "70 N", "100 N"]


def committed_eta() -> Dict[tuple, float]:
    """η by (variant, preload as written) from the committed FEM sweep."""
    with open(STUDY / "fig7-8-post-count.csv", newline="") as f:
        return {
            (r["variant"], f"{float(r['preload_n']):g} N"): float(r["effective_contact_ratio"])
            for r in csv.DictReader(f)
        }


def study_with_committed_eta(arrays: Dict[str, str], preloads: List[str]) -> List[dict]:
    """Every point's dynamic stage with its committed FEM η."""
    eta = committed_eta()
    rows = []
    for variant, count in arrays.items():
        for preload in preloads:
            scene = sawdrive.Scene.default().set("posts.count", count).set("preload", preload)
            scene.set("effective_ratio", eta[(variant, preload)])
            # The paper's model: the constant-amplitude wave, as the committed sweep.
            scene.set("wave.attenuation", "off")
            r = sawdrive.dynamic(scene, progress=False)
            rows.append({"variant": variant, "preload": preload, "preload_n": scene.resolve()["load"]["preload_n"],
                         "effective_contact_ratio": r.effective_ratio, "stall_thrust_n": r.stall_thrust_n,
                         "no_load_speed_m_per_s": r.no_load_speed_m_per_s})
    return rows


def study_with_fem(out: Path) -> List[dict]:
    """The whole sweep (static FEM and dynamics of every point)."""
    result = sawdrive.sweep(SWEEP_FILE, out=out / "sweep")
    return [{k: r[k] for k in ("variant", "preload", "preload_n", "effective_contact_ratio",
                               "stall_thrust_n", "no_load_speed_m_per_s")} for r in result.records()]


def plot(rows: List[dict], column: str, label: str, title: str, file: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.2))
    for variant in dict.fromkeys(r["variant"] for r in rows):
        points = sorted((r["preload_n"], r[column]) for r in rows if r["variant"] == variant)
        ax.plot(*zip(*points), marker="o", label=variant)
    ax.set_xlabel("preload (N)")
    ax.set_ylabel(label)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(file, dpi=120)
    plt.close(fig)


def main(argv=None) -> List[dict]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--eta", choices=["committed", "fem"], default="committed")
    parser.add_argument("--out", type=Path, default=Path("out/python-post-count"))
    parser.add_argument("--arrays", default=",".join(ARRAYS.values()), help="post arrays, e.g. 100x100,33x33")
    parser.add_argument("--preloads", default=",".join(PRELOADS), help='preloads, e.g. "40 N,100 N"')
    args = parser.parse_args(argv)
    arrays = {v: c for v, c in ARRAYS.items() if c in args.arrays.split(",")}
    preloads = [p for p in PRELOADS if p in args.preloads.split(",")]
    if not arrays or not preloads:
        parser.error(f"--arrays from {', '.join(ARRAYS.values())}; --preloads from {', '.join(PRELOADS)}")
    args.out.mkdir(parents=True, exist_ok=True)
    if args.eta == "committed":
        rows = study_with_committed_eta(arrays, preloads)
    else:
        rows = study_with_fem(args.out)
        arrays, preloads = ARRAYS, PRELOADS
    with open(args.out / "post_count.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plot(rows, "stall_thrust_n", "stall thrust (N)", "Fig. 7: maximum thrust vs preload, 20 µm posts",
         args.out / "fig7_stall_thrust.png")
    plot(rows, "no_load_speed_m_per_s", "no-load speed (m/s)", "Fig. 8: no-load speed vs preload, 20 µm posts",
         args.out / "fig8_no_load_speed.png")
    print(f"{'preload':>8} " + " ".join(f"{v:>15}" for v in arrays))
    for preload in preloads:
        cells = [next(r for r in rows if r["variant"] == v and r["preload"] == preload) for v in arrays]
        print(f"{preload:>8} " + " ".join(f"{c['stall_thrust_n']:6.2f} N {c['no_load_speed_m_per_s']:5.3f}" for c in cells))
    print(f"charts and table in {args.out}")
    return rows


if __name__ == "__main__":
    main()
