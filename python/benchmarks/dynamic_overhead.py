"""Cost of calling the dynamic stage from Python over the same call made from Rust.

Both sides do the same work on the same resolved scene (built once, as a Rust caller keeps its
`Scene`): the post springs and the dynamic model (`sawdrive::pipeline::run_dynamic`) with η
given. The Rust side is timed inside the extension (`sawdrive._native.time_rust_dynamic`: the
Rust call between two `Instant::now()`, no Python in between). The Python side is timed around
what a user writes, `r = sawdrive.dynamic(scene)` with default arguments, then reading
`r.stall_thrust_n` and `r.curve` (the fields and the numpy curve are converted when first read,
so reading them is part of the cost). Calls alternate one by one, so that load from other
processes hits both sides alike; the ratio of the whole-call medians is reported (and of the
call alone, without reading the result).

    python python/benchmarks/dynamic_overhead.py [--calls 3000] [--set preload=20N ...]
"""

import argparse
import json
import statistics
import time

import sawdrive
from sawdrive import _native


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--calls", type=int, default=3000, help="calls per side")
    parser.add_argument("--set", action="append", default=["preload=20N", "effective_ratio=0.36"],
                        help="scene overrides (key=value)")
    args = parser.parse_args()
    scene = sawdrive.Scene.default()
    for override in args.set:
        scene.set(*override.split("=", 1))
    native = scene._native
    clock = time.perf_counter
    for _ in range(20):  # warm up both paths
        sawdrive.dynamic(scene).curve
        _native.time_rust_dynamic(native, 1)
    rust_s, read_s, call_s = [], [], []
    for _ in range(args.calls):
        rust_s.extend(_native.time_rust_dynamic(native, 1))
        start = clock()
        r = sawdrive.dynamic(scene)
        r.stall_thrust_n
        r.curve
        read_s.append(clock() - start)
        rust_s.extend(_native.time_rust_dynamic(native, 1))
        start = clock()
        sawdrive.dynamic(scene)
        call_s.append(clock() - start)
    rust = statistics.median(rust_s)
    report = {
        "scene_overrides": scene.overrides,
        "calls_per_side": args.calls,
        "rust_median_s": rust,
        "python_median_s": statistics.median(read_s),
        "python_call_only_median_s": statistics.median(call_s),
        "ratio_median": statistics.median(read_s) / rust,
        "ratio_call_only_median": statistics.median(call_s) / rust,
        "ratio_min": min(read_s) / min(rust_s),
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
