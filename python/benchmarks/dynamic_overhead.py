"""Cost of calling the dynamic stage from Python over the same call made from Rust.

Both sides do the same work: resolve the scene (default + overrides), the post springs and the
dynamic model (`sawdrive::pipeline::run_dynamic`) with η given. The Rust side is timed inside the
extension (`sawdrive._native.time_rust_dynamic`: a loop of Rust calls, no Python in between);
the Python side is `sawdrive.dynamic(scene)` as a user calls it (JSON across, numpy curve,
result object). Rounds alternate the two so that load from other processes hits both; the ratio
of the medians is reported.

    python python/benchmarks/dynamic_overhead.py [--rounds 30] [--calls 20] [--set preload=20N ...]
"""

import argparse
import json
import statistics
import time

import sawdrive
from sawdrive import _native


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rounds", type=int, default=30, help="alternating rounds")
    parser.add_argument("--calls", type=int, default=20, help="calls per round and side")
    parser.add_argument("--set", action="append", default=["preload=20N", "effective_ratio=0.36"],
                        help="scene overrides (key=value)")
    args = parser.parse_args()
    scene = sawdrive.Scene.default()
    for override in args.set:
        scene.set(*override.split("=", 1))
    path, overrides = scene.path, scene.overrides
    for _ in range(3):  # warm up both paths
        sawdrive.dynamic(scene, progress=False)
        _native.time_rust_dynamic(path, overrides, 1)
    python_s, rust_s = [], []
    for _ in range(args.rounds):
        rust_s.extend(_native.time_rust_dynamic(path, overrides, args.calls))
        for _ in range(args.calls):
            start = time.perf_counter()
            sawdrive.dynamic(scene, progress=False)
            python_s.append(time.perf_counter() - start)
    report = {
        "scene_overrides": overrides,
        "calls_per_side": len(python_s),
        "rust_median_s": statistics.median(rust_s),
        "python_median_s": statistics.median(python_s),
        "rust_min_s": min(rust_s),
        "python_min_s": min(python_s),
    }
    report["ratio_median"] = report["python_median_s"] / report["rust_median_s"]
    report["ratio_min"] = report["python_min_s"] / report["rust_min_s"]
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
