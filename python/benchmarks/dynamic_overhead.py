"""Cost of calling the dynamic stage from Python over the same call made from Rust.

Both sides do the same work on the same resolved scene (built once, as a Rust caller keeps its
`Scene`): the post springs and the dynamic stage (`sawdrive::pipeline::run_dynamic_stage`) with
η given. The Rust side is timed inside the extension (`sawdrive._native.time_rust_dynamic`: the
Rust call between two `Instant::now()`, no Python in between). The Python side is timed around
what a user writes, `r = sawdrive.dynamic(scene)` with default arguments, then reading
`r.stall_thrust_n` and `r.curve` (fields and the numpy curve are converted when first read, so
reading them is part of the cost); and, separately, the call alone.

The default call is a light one (the constant wave, ≈ 1 ms: the default scene's
energy-conserving wave makes it ≈ 0.25 s, which would hide the overhead), since a fixed
per-call overhead weighs most there.

Noise on a shared machine: calls are paired (Rust and Python-with-reads, then Rust and
Python-call-only; within each pair the order is drawn at random, seed 1, so neither side always
runs on the caches the other left), so that load from other processes hits both members of a
pair alike;
the reported ratio is the median of the per-pair ratios, with its 95 % confidence interval from
the order statistics of the median (a distribution-free interval: ranks n/2 ∓ 0.98 √n). The
ratio of the medians is reported next to it. CPU time (user + sys) of the whole benchmark and
the load average are printed too.

    python python/benchmarks/dynamic_overhead.py [--calls 3000] [--set preload=20N ...]
"""

import argparse
import json
import math
import os
import random
import resource
import statistics
import time

import sawdrive
from sawdrive import _native


def median_ci(values):
    """(median, low, high): the median and its distribution-free 95 % confidence interval."""
    ordered = sorted(values)
    n = len(ordered)
    half_width = 0.98 * math.sqrt(n)
    low = max(0, int(math.floor(n / 2 - half_width)))
    high = min(n - 1, int(math.ceil(n / 2 + half_width)))
    return statistics.median(ordered), ordered[low], ordered[high]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--calls", type=int, default=3000, help="pairs per measurement")
    parser.add_argument("--set", action="append", default=["preload=20N", "effective_ratio=0.36",
                                 "wave.attenuation=off"],
                        help="scene overrides (key=value)")
    args = parser.parse_args()
    scene = sawdrive.Scene.default()
    for override in args.set:
        scene.set(*override.split("=", 1))
    native = scene._native
    clock = time.perf_counter
    for _ in range(50):  # warm up both paths
        sawdrive.dynamic(scene).curve
        _native.time_rust_dynamic(native, 1)
    usage0 = resource.getrusage(resource.RUSAGE_SELF)
    load0 = os.getloadavg()[0]
    def with_reads():
        start = clock()
        r = sawdrive.dynamic(scene)
        r.stall_thrust_n
        r.curve
        del r  # freed inside the timing, as the Rust side drops its result
        return clock() - start

    def call_only():
        start = clock()
        sawdrive.dynamic(scene)
        return clock() - start

    def pair(python):
        """(Rust time, Python time), in a random order: no side always runs second."""
        if order.random() < 0.5:
            rust = _native.time_rust_dynamic(native, 1)[0]
            return rust, python()
        py = python()
        return _native.time_rust_dynamic(native, 1)[0], py

    order = random.Random(1)
    rust_read, read_s, rust_call, call_s = [], [], [], []
    for _ in range(args.calls):
        rust, py = pair(with_reads)
        rust_read.append(rust)
        read_s.append(py)
        rust, py = pair(call_only)
        rust_call.append(rust)
        call_s.append(py)
    usage1 = resource.getrusage(resource.RUSAGE_SELF)
    ratio_read = median_ci([p / r for p, r in zip(read_s, rust_read)])
    ratio_call = median_ci([p / r for p, r in zip(call_s, rust_call)])
    rust = statistics.median(rust_read + rust_call)
    report = {
        "scene_overrides": scene.overrides,
        "pairs": args.calls,
        "rust_median_s": rust,
        "python_with_reads_median_s": statistics.median(read_s),
        "python_call_only_median_s": statistics.median(call_s),
        "ratio_with_reads_median_of_pairs": ratio_read[0],
        "ratio_with_reads_95ci": [ratio_read[1], ratio_read[2]],
        "ratio_call_only_median_of_pairs": ratio_call[0],
        "ratio_call_only_95ci": [ratio_call[1], ratio_call[2]],
        "ratio_with_reads_of_medians": statistics.median(read_s) / statistics.median(rust_read),
        "ratio_with_reads_of_minima": min(read_s) / min(rust_read),
        "cpu_user_plus_sys_s": (usage1.ru_utime - usage0.ru_utime) + (usage1.ru_stime - usage0.ru_stime),
        "load_average_1min": [load0, os.getloadavg()[0]],
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
