#!/usr/bin/env python3
"""Write docs/performance.md from the project's own benchmark and timing scripts.

    scripts/performance.sh [--quick] [--section NAME ...] [--list]

Every section of docs/performance.md lies between the markers
`<!-- performance.sh section NAME -->` and `<!-- /performance.sh section NAME -->` and is
produced by one command (listed by --list). A run rewrites the sections it runs and the machine
block at the top, and keeps every other section as it was, with the date and commit it states.
Without --section it runs the ordinary sections (not the `heavy` ones: peers, FEM growth to
2.5M unknowns, threads, Python; name those to run them). --quick runs each command at its
cheaper setting (fewer repeats, smaller problems; the command printed in the section is the one
that ran).

Figures: whole-process timings are taken from the scripts' output lines; criterion benches are
read from `target/criterion/**/new/estimates.json` (median and its 95 % confidence interval) of
the benchmarks written during this run, never from the console. Ratios are only formed between
figures of one command's run. Each section states its date, commit, load average before and
after, and how long it took.
"""

import argparse
import datetime
import json
import os
import pathlib
import re
import textwrap
import shlex
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "performance.md"
TARGET = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
BEGIN = "<!-- performance.sh section {} -->"
END = "<!-- /performance.sh section {} -->"


class Failed(Exception):
    """A command of a section failed; the section is left as it was."""


# --- running commands --------------------------------------------------------------------------


def load():
    return " ".join(open("/proc/loadavg").read().split()[:3])


def run(command, env=None, shell=False):
    """Run `command` in the repository; return its stdout (stderr goes to the terminal)."""
    shown = command if shell else shlex.join(command)
    print(f"performance.sh: $ {shown}", file=sys.stderr, flush=True)
    full_env = dict(os.environ, **(env or {}))
    done = subprocess.run(command, cwd=ROOT, env=full_env, shell=shell, text=True,
                          stdout=subprocess.PIPE)
    sys.stderr.write(done.stdout)
    if done.returncode != 0:
        raise Failed(f"`{shown}` exited with status {done.returncode}")
    return done.stdout


def commit():
    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, text=True,
                          capture_output=True).stdout.strip()
    dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT,
                           text=True, capture_output=True).stdout.splitlines()
    # The page being written is not a change to what was measured.
    dirty = [line for line in dirty if not line.endswith(" docs/performance.md")]
    return head + (f" + uncommitted changes in {len(dirty)} files" if dirty else "")


def stamp(started, load_before, command):
    took = time.time() - started
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return (f"*Generated {when} at commit {commit()} by `{command}` ({took:.0f} s; load average "
            f"{load_before} before, {load()} after).*")


# --- criterion ---------------------------------------------------------------------------------


def criterion_since(started):
    """{full_id: (median_s, low_s, high_s)} of the benchmarks written after `started`."""
    found = {}
    for estimates in (TARGET / "criterion").glob("**/new/estimates.json"):
        meta_file = estimates.parent / "benchmark.json"
        # Another job's benchmark may be half written (estimates before benchmark.json).
        if estimates.stat().st_mtime < started or not meta_file.exists():
            continue
        try:
            meta = json.loads(meta_file.read_text())
            median = json.loads(estimates.read_text())["median"]
        except (OSError, ValueError, KeyError):
            continue
        ci = median["confidence_interval"]
        found[meta["full_id"]] = tuple(x * 1e-9 for x in (
            median["point_estimate"], ci["lower_bound"], ci["upper_bound"]))
    if not found:
        raise Failed("no criterion estimates were written")
    return found


def seconds(value):
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6), ("ns", 1e-9)):
        if value >= scale or unit == "ns":
            return f"{value / scale:.3g} {unit}"


def median_ci(entry):
    median, low, high = entry
    return f"{seconds(median)} [{seconds(low)}, {seconds(high)}]"


def bench_table(found, rows):
    """Markdown rows `| what | median [95 % CI] | target |` for (label, full_id, target)."""
    lines = ["| what | median [95 % CI] | target |", "|---|---:|---:|"]
    for label, full_id, target in rows:
        if full_id in found:
            lines.append(f"| {label} | {median_ci(found[full_id])} | {target} |")
    return lines


def bench_section(command, env, rows, note):
    started = time.time()
    before = load()
    run(command, env=env)
    found = criterion_since(started)
    shown = " ".join(f"{k}={v}" for k, v in (env or {}).items()) + (" " if env else "")
    shown += shlex.join(command)
    body = [stamp(started, before, shown), ""] + bench_table(found, rows(found))
    return body + ([""] + note(found) if note else [])


# --- the sections ------------------------------------------------------------------------------


def timed_lines(text):
    """{name: [(wall_s, cpu_s, rss_mb), ...]} of `name wall user sys maxrss_kb` lines."""
    runs = {}
    for line in text.splitlines():
        f = line.split()
        if len(f) == 5 and not line.startswith("#") and re.fullmatch(r"[\d.]+", f[1]):
            runs.setdefault(f[0], []).append(
                (float(f[1]), float(f[2]) + float(f[3]), float(f[4]) / 1024))
    return runs


def span(values, unit="s", digits=2):
    lo, hi = min(values), max(values)
    return f"{lo:.{digits}f} {unit}" if lo == hi else f"{lo:.{digits}f}–{hi:.{digits}f} {unit}"


def section_default(quick):
    runs = 1 if quick else 3
    command = ["scripts/perf-default.sh", "--runs", str(runs)]
    started, before = time.time(), load()
    out = run(command)
    timed = timed_lines(out)
    labels = [
        ("run_cached_mesh", "`sawdrive run`, mesh cached, no FEM result cache", "≤ 3 s"),
        ("run_cached_mesh_constant_wave", "the same with `--set wave.attenuation=off`", "—"),
        ("run_cached_fem", "`sawdrive run`, FEM result cached (dynamic stage and output)", "—"),
        ("run_cached_fem_constant_wave", "the same with `--set wave.attenuation=off`", "—"),
        ("run_cold", "`sawdrive run`, cold (gmsh meshes the strip), no FEM result cache", "≤ 6 s"),
        ("static_cached_mesh", "`sawdrive static`, mesh cached", "—"),
        ("static_cold", "`sawdrive static`, cold", "—"),
        ("sweep_fig7_8_cold", "Figs 7–8 sweep (`validation/paper-figures/fig7-8-post-count.toml`, "
         "25 points, 5 geometries), cold", "≤ 30 s"),
    ]
    body = [stamp(started, before, shlex.join(command)), "",
            f"Whole process, {runs} run(s) each (min–max):", "",
            "| what | wall | CPU (user + sys) | peak memory | target |", "|---|---:|---:|---:|---:|"]
    for key, label, target in labels:
        if key in timed:
            v = timed[key]
            body.append(f"| {label} | {span([w for w, _, _ in v])} | {span([c for _, c, _ in v])} "
                        f"| {max(m for _, _, m in v):.0f} MB | {target} |")
    ratios = []
    for on, off, what in [("run_cached_mesh", "run_cached_mesh_constant_wave", "FEM computed"),
                          ("run_cached_fem", "run_cached_fem_constant_wave", "FEM result cached")]:
        if on in timed and off in timed:
            walls = sorted(w for w, _, _ in timed[on]), sorted(w for w, _, _ in timed[off])
            median = [v[len(v) // 2] for v in walls]
            ratios.append(f"{median[0] / median[1]:.2f}× with the {what}")
    if ratios:
        body += ["", "The energy-conserving wave (the default scene attenuates) against the constant "
                 "wave, median wall times of this run: " + ", ".join(ratios) + "."]
    notes = [line[2:] for line in out.splitlines() if line.startswith("# breakdown")
             or line.startswith("# slider strip")]
    if notes:
        body += ["", "From the last cached run's `static.json`: " + "; ".join(notes) + "."]
    return body


def section_default_stage(quick):
    repeat = 1 if quick else 3
    started, before = time.time(), load()
    with tempfile.TemporaryDirectory() as scratch:
        run(["cargo", "build", "--release", "-q", "-p", "sawdrive-cli"])
        run([str(TARGET / "release" / "sawdrive"), "run", "--out", f"{scratch}/out"])
        cached = sorted(pathlib.Path(scratch).glob("out/**/compliance-*.json"))
        if not cached:
            raise Failed("`sawdrive run` wrote no compliance-*.json cache entry")
        command = ["cargo", "run", "--release", "-q", "-p", "coupled-dynamics", "--example",
                   "default_stage", "--", str(cached[0]), "--repeat", str(repeat)]
        out = run(command)
    walls = [float(m) for m in re.findall(r"coupled stage ([\d.]+) s wall", out)]
    cpu = re.search(r"CPU ([\d.]+) s over (\d+) repeats \((\d+) threads\)", out)
    shown = ("cargo run --release -p coupled-dynamics --example default_stage -- "
             f"COMPLIANCE.json --repeat {repeat}")
    return [stamp(started, before, shown), "",
            "COMPLIANCE.json is the `out/.cache/compliance-<key>.json` a `sawdrive run` of the "
            "default scene writes (made by the section first). The coupled dynamic stage alone "
            "(64 steps per period, the 50-point curve, post histories, the step-error points, "
            f"η_dyn): {span(walls, digits=3)} wall per stage over {len(walls)} repeat(s); "
            f"{float(cpu.group(1)) / int(cpu.group(2)):.2f} s of CPU per stage "
            f"({cpu.group(3)} threads)."]


def section_strip_mesh(quick):
    command = ["scripts/perf-strip-mesh.sh"]
    started, before = time.time(), load()
    out = run(command)
    lines = [line for line in out.splitlines()
             if line.startswith(("cold:", "cached:")) or "gmsh process" in line
             or line.startswith("Info    : Done")]
    return [stamp(started, before, shlex.join(command)), "",
            "The default scene's strip mesh: gmsh meshes half the Tet4 strip (cold), Rust "
            "reflects it and adds the Tet10 midside nodes; the cached run reads the Tet4 file. "
            "`mesh_s` is mesh choice + gmsh + reading + elevation:", "", "```"] + lines + ["```"]


def section_bench_stick_slip(quick):
    def rows(found):
        return [
            ("50-point speed–thrust curve, period average", "periodic_average_curve_50_points",
             "≤ 20 ms"),
            ("period average, full solve", "periodic_average_full_solve", "—"),
            ("transient, default slider (100 phase groups), 1000 periods, T/256",
             "transient/default_slider_1000_periods_return_mapping_T/256", "≤ 2 s"),
            ("transient, event driven, 100 periods",
             "transient/default_slider_100_periods_event_driven", "—"),
        ]
    return bench_section(["cargo", "bench", "-q", "-p", "stick-slip", "--bench", "speed", "--",
                          "--quick"], None, rows, None)


def section_bench_coupled(quick):
    def rows(found):
        return [(f"`{k}`", k, "—") for k in sorted(found) if k.startswith("coupled/")]
    extra = ["--quick"] if quick else []
    return bench_section(["cargo", "bench", "-q", "-p", "coupled-dynamics", "--bench", "curve",
                          "--", "100 posts"] + extra, None, rows, None)


def section_bench_fem(quick):
    env = None if quick else {"ELASTIC_FEM_BENCH_LARGE": "1"}

    def sizes(found):
        return sorted({int(k.split("/")[1]) for k in found if k.startswith("assembly/")})

    def rows(found):
        out = []
        for n in sizes(found):
            for group, what in (("pattern_build", "pattern"), ("assembly", "assembly"),
                                ("symbolic_cholesky_metis", "METIS ordering + symbolic"),
                                ("numeric_cholesky_metis", "numeric Cholesky (METIS)"),
                                ("numeric_cholesky_amd", "numeric Cholesky (AMD)"),
                                ("solve_metis", "triangular solves")):
                out.append((f"{what}, {n:,} unknowns".replace(",", " "), f"{group}/{n}", "—"))
        return out

    def note(found):
        lines = ["Ratios of this run (medians):", ""]
        for n in sizes(found):
            a, f = found.get(f"assembly/{n}"), found.get(f"numeric_cholesky_metis/{n}")
            if a and f:
                lines.append(f"- {n:,} unknowns: assembly ÷ numeric factorisation "
                             f"{100 * a[0] / f[0]:.1f} % (target ≤ 15 %)".replace(",", " "))
            amd = found.get(f"numeric_cholesky_amd/{n}")
            if amd and f:
                lines.append(f"- {n:,} unknowns: numeric factorisation with METIS "
                             f"{amd[0] / f[0]:.2f}× faster than with AMD".replace(",", " "))
        return lines
    extra = ["--quick"] if quick else []
    return bench_section(["cargo", "bench", "-q", "-p", "elastic-fem", "--bench", "fem_pipeline",
                          "--"] + extra, env, rows, note)


def section_bench_slider(quick):
    def rows(found):
        return [
            ("operator build (default slider, rigid back)", "default_slider/operator_build", "—"),
            ("one phase at 40 N", "default_slider/one_phase_40n", "—"),
            ("4 phases + η at 40 N", "default_slider/four_phases_and_eta_40n", "—"),
            ("whole stage: operator + 4 phases + η", "default_slider/whole_stage_40n", "≤ 2 s"),
        ]
    extra = ["--quick"] if quick else []
    return bench_section(["cargo", "bench", "-q", "-p", "slider-contact", "--profile", "test",
                          "--bench", "default_slider", "--", "default_slider/"] + extra,
                         None, rows, None)


def section_whole_slider_cli(quick):
    started, before = time.time(), load()
    run(["cargo", "build", "--release", "-q", "-p", "sawdrive-cli"])
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        env = {"SAWDRIVE_MESH_CACHE": f"{scratch}/meshes"}
        cases = [
            ("strip mesh made, cell FEM and slider stage", ["--set", "static.model=slider"]),
            ("the strip mesh cached (cell FEM + slider stage)", ["--set", "static.model=slider"]),
            ("cell FEM cached, another preload", ["--set", "static.model=slider",
                                                  "--set", "preload=41N"]),
            ("same inputs again (verified cached report)", ["--set", "static.model=slider",
                                                            "--set", "preload=41N"]),
        ]
        out = f"{scratch}/out"
        for i, (label, args) in enumerate(cases):
            if i == 1:
                # Same mesh cache, fresh result cache: the FEM runs again on the cached mesh.
                out = f"{scratch}/out-cached-mesh"
            command = [str(TARGET / "release" / "sawdrive"), "static"] + args + ["--out", out]
            t0 = time.time()
            run(command, env=env)
            rows.append(f"| {label} | `sawdrive static {shlex.join(args)}` | "
                        f"{time.time() - t0:.2f} s |")
    return [stamp(started, before, "scripts/performance.sh --section whole-slider-cli"), "",
            "The whole slider from the command line on the default scene, one empty mesh cache "
            "and output folder for the first line, then each line after the one above "
            "(wall time of the whole process):", "",
            "| case | command | wall |", "|---|---|---:|"] + rows


def section_whole_slider_coupled(quick):
    """The whole slider's coupled curve from the command line, constant and attenuated wave."""
    started, before = time.time(), load()
    run(["cargo", "build", "--release", "-q", "-p", "sawdrive-cli"])
    binary = str(TARGET / "release" / "sawdrive")
    base = ["dynamic", "--set", "static.model=slider", "--set", "model.dynamics=coupled", "--json"]
    cases = [("constant-amplitude wave", ["--set", "wave.attenuation=off"]),
             ("energy-conserving wave (the default `auto` turns it on)", [])]
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for name, extra in cases:
            argv = [binary] + base + extra + ["--out", f"{scratch}/out"]
            timing = f"{scratch}/time.txt"
            out = run(["/usr/bin/time", "-o", timing, "-f", "%e %U %S"] + argv)
            wall, user, system = (float(x) for x in open(timing).read().split()[-3:])
            result = json.loads(out)
            shown = "sawdrive " + shlex.join(base[:-1] + extra)
            rows.append(
                f"| {name} | `{shown}` | {wall:.1f} s | {user + system:.1f} s | "
                f"{result['stall_thrust_n']:.3f} N | {result['no_load_speed_m_per_s']:.4f} m/s | "
                f"{result['wave_attenuation']} |")
    return [stamp(started, before, "scripts/performance.sh --section whole-slider-coupled"), "",
            "The coupled model of every post of the default slider (10 000 posts, 64 steps per "
            "period, 8 curve points, maps and the middle row's histories; the static stage "
            "included), one run each; target: the default slider's coupled curve ≤ 60 s wall on "
            "2 cores:", "",
            "| case | command | wall | CPU | stall thrust | no-load speed | wave |",
            "|---|---|---:|---:|---:|---:|---|"] + rows


def section_uq(quick):
    samples = 50 if quick else 200
    command = ["scripts/perf-design.sh", "--no-design", "--samples", str(samples)]
    started, before = time.time(), load()
    out = run(command)
    timed = timed_lines(out)
    wall, cpu, rss = timed[f"uq-{samples}"][0]
    rate = re.search(r"samples_per_s=([\d.]+) cpu_per_sample_s=([\d.]+)", out)
    cost = next((line for line in out.splitlines() if line.startswith("cost uq")), "")
    failed = re.search(r"failed=(\d+)", cost)
    target = " (target for 200: ≤ 60 s)" if samples == 200 else ""
    return [stamp(started, before, shlex.join(command)), "",
            f"{samples} samples of the default scene under `validation/design/scatter.toml`, "
            f"seed 1: {wall:.1f} s wall{target}, {cpu:.1f} s CPU, {rate.group(1)} samples/s, "
            f"{rate.group(2)} s CPU per sample, {failed.group(1) if failed else '?'} failed, "
            f"peak {rss:.0f} MB.", "", "```", cost, "```"]


def section_uq_coupled(quick):
    """`uq` with the whole slider's coupled model on the default slider, 5 nm height scatter."""
    samples = 4 if quick else 50
    started, before = time.time(), load()
    run(["cargo", "build", "--release", "-q", "-p", "sawdrive-cli"])
    binary = str(TARGET / "release" / "sawdrive")
    args = ["uq", "--samples", str(samples), "--seed", "1", "--set", "static.model=slider",
            "--set", "model.dynamics=coupled", "--set", 'scatter.posts.height_scatter=5 nm']
    with tempfile.TemporaryDirectory() as scratch:
        timing = f"{scratch}/time.txt"
        out = run(["/usr/bin/time", "-o", timing, "-f", "%e %U %S"] + [binary] + args
                  + ["--out", f"{scratch}/out"])
        wall, user, system = (float(x) for x in open(timing).read().split()[-3:])
    cost = [line for line in out.splitlines() if line.startswith("cost")]
    failed = re.search(r"^(\d+) samples failed", out, re.M)
    bands = [line for line in out.splitlines()
             if re.match(r"(stall_thrust_n|no_load_speed_m_per_s|max_output_power_w|"
                         r"efficiency) ", line)][-4:]
    target = " (target: ≤ 600 s)" if samples == 50 else ""
    return [stamp(started, before, "scripts/performance.sh --section uq-coupled"), "",
            f"`sawdrive {shlex.join(args)}`: {samples} samples of the default slider (10 000 "
            f"posts, 40 N) on the energy-conserving wave, every sample through the whole "
            f"slider's coupled model: {wall:.1f} s wall{target}, {user + system:.1f} s CPU, "
            f"{failed.group(1) if failed else '?'} failed. Columns: the deterministic nominal, "
            f"then the samples' mean, P5, P50, P95.", "", "```"] + bands + cost + ["```"]


def section_sharded(quick):
    command = ["scripts/slurm-speedup.sh", str(TARGET / "release" / "sawdrive"), "2"]
    started, before = time.time(), load()
    run(["cargo", "build", "--release", "-q", "-p", "sawdrive-cli"])
    out = run(command)
    table = [line for line in out.splitlines() if line.strip()]
    return [stamp(started, before, "scripts/slurm-speedup.sh target/release/sawdrive 2"), "",
            "Three 8-point sweeps of the small scene as 1 shard and as 2 shards at once "
            "(`--jobs 1` each): `eta` η given, transient dynamics; `fem` one FEM geometry, "
            "period average; `geo` 4 geometries, period average. `f` is the serial fraction "
            "(serial CPU ÷ one-shard CPU) and `S(4)` Amdahl's law 1/(f + (1 − f)/4), not a "
            "measurement (2 cores here). A sweep whose one FEM condensation outweighs its "
            "dynamics (`fem`) does not gain from shards; give it `--jobs` instead.", "",
            "```"] + table + ["```"]


def section_python(quick):
    calls = 1000 if quick else 3000
    probe = subprocess.run([sys.executable, "-c", "import sawdrive._native"], cwd=ROOT,
                           capture_output=True)
    if probe.returncode != 0:
        raise Failed("the Python package is not installed (pip install ./python)")
    command = [sys.executable, "python/benchmarks/dynamic_overhead.py", "--calls", str(calls)]
    started, before = time.time(), load()
    out = run(command)
    report = json.loads(out)
    verdict = []
    for key, what in (("ratio_call_only", "the call alone"), ("ratio_with_reads", "the call with "
                      "`r.stall_thrust_n` and `r.curve` read")):
        low, high = report[f"{key}_95ci"]
        ok = "met" if high <= 1.05 else "not met"
        verdict.append(f"{what} {report[f'{key}_median_of_pairs']:.3f}× [{low:.3f}, {high:.3f}] "
                       f"(target ≤ 1.05×: {ok})")
    return [stamp(started, before, f"python python/benchmarks/dynamic_overhead.py --calls "
                  f"{calls}"), "",
            f"The call `sawdrive.dynamic(scene)` against the same call made from Rust "
            f"({report['rust_median_s'] * 1e3:.3f} ms, the constant wave with η given), median "
            f"of {report['pairs']} per-pair ratios [95 % interval]: " + "; ".join(verdict) + ".",
            "", "```"] + out.strip().splitlines() + ["```"]


def peer_cell(d):
    """`wall s / memory` of one code's run, its CPU time beside the wall when they differ."""
    cpu = f" (CPU {d['cpu_s']:.1f} s)" if abs(d["cpu_s"] - d["wall_s"]) > 0.1 * d["wall_s"] else ""
    memory = (f"{d['peak_mb']:.0f} MB" if d["peak_mb"] < 1024 else f"{d['peak_mb'] / 1024:.2f} GB")
    return f"{d['wall_s']:.2f} s{cpu} / {memory}"


def peer_table(meshes):
    """Markdown rows of the peers' runs, one per mesh ({run: json}), and the verdict lines."""
    rows = ["| unknowns | ours | tuned scikit-fem | ccx | scikit-fem ÷ ours | ccx ÷ ours | load "
            "before (ours, skfem, ccx) |", "|---:|---:|---:|---:|---:|---:|---:|"]
    worst_dk, verdict = 0.0, {}
    for runs in meshes:
        ours, skfem, ccx = runs["ours-iterative"], runs["skfem-tuned"], runs["ccx"]
        n = ours["unknowns"]
        for peer in (skfem, ccx):
            worst_dk = max(worst_dk, abs(peer["k_sn_clamped_n_per_m"] /
                                         ours["k_sn_clamped_n_per_m"] - 1))
        ratio = {name: (d["wall_s"] / ours["wall_s"], d["cpu_s"] / ours["cpu_s"])
                 for name, d in (("skfem", skfem), ("ccx", ccx))}
        cells = [f"{w:.1f}× (CPU {c:.1f}×)" for w, c in ratio.values()]
        loads = ", ".join(f"{d['load_before']:.1f}" for d in (ours, skfem, ccx))
        rows.append(f"| {n:,} | {peer_cell(ours)} | {peer_cell(skfem)} | {peer_cell(ccx)} | "
                    .replace(",", " ") + f"{cells[0]} | {cells[1]} | {loads} |")
        verdict[n] = (ratio, ours, ccx)
    return rows, worst_dk, verdict


def peer_verdicts(verdict):
    """The three targets against this run's figures (CPU ratios: the machine is shared)."""
    lines = []
    near = min(verdict, key=lambda n: abs(n - 350_000), default=None)
    if near is not None and abs(near - 350_000) < 50_000:
        ratio, ours, ccx = verdict[near]
        lines.append(f"- ≥ 3× tuned scikit-fem at 350k: {met_in(ratio['skfem'], 3)}.")
        mem = ours["peak_mb"] <= ccx["peak_mb"]
        lines.append(f"- peak memory at 350k ≤ CalculiX's: {ours['peak_mb'] / 1024:.2f} GB "
                     f"against {ccx['peak_mb'] / 1024:.2f} GB: {'met' if mem else 'not met'}.")
    big = {n: v for n, v in verdict.items() if n >= 55_000}
    if big:
        low = tuple(min(v[0]["ccx"][k] for v in big.values()) for k in (0, 1))
        sizes = ", ".join(f"{n:,}".replace(",", " ") for n in sorted(big))
        lines.append(f"- ≥ 10× CalculiX from 55k up (the smallest ratio over {sizes} "
                     f"unknowns): {met_in(low, 10)}.")
    return lines


def met_in(ratio, target):
    """`(wall, cpu)` ratios against `target`, judged on each (a short run's wall time carries the
    other jobs' load, its CPU time much less)."""
    wall, cpu = ratio
    judged = [f"{what} {value:.1f}× ({'met' if value >= target else 'not met'})"
              for what, value in (("CPU time", cpu), ("wall time", wall))]
    return ", ".join(judged)


def section_peers(quick):
    venv = TARGET / "skfem-venv" / "bin" / "python"
    have_skfem = venv.exists() and subprocess.run(
        [str(venv), "-c", "import skfem, pyamg"], capture_output=True).returncode == 0
    if not have_skfem or subprocess.run(["sh", "-c", "command -v ccx"],
                                        capture_output=True).returncode != 0:
        raise Failed("peers not installed (scikit-fem venv in target/skfem-venv, CalculiX ccx)")
    levels = ["0", "1"] if quick else ["0", "1", "3", "4.2"]
    command = ["scripts/compare-peers.sh", "--ours", "iterative"] + levels
    started, before = time.time(), load()
    out = run(command)
    meshes, current = [], {}
    for line in out.splitlines():
        if line.startswith("{"):
            d = json.loads(line)
            current[d["run"]] = d
        elif line.startswith("SUMMARY"):
            meshes.append(current)
            current = {}
    if not meshes or any(set(m) != {"ours-iterative", "skfem-tuned", "ccx"} for m in meshes):
        raise Failed("compare-peers.sh did not report ours, scikit-fem and ccx on every mesh")
    rows, worst_dk, verdict = peer_table(meshes)
    skfem_code = meshes[0]["skfem-tuned"]["code"]
    ccx_version = subprocess.run(["sh", "-c", "ccx -v 2>&1 | grep -o 'Version [0-9.]*'"],
                                 capture_output=True, text=True).stdout.strip()
    return ([stamp(started, before, shlex.join(command)), "",
             "The rigid-punch meshes of the springs validation (quarter Tet10; levels 0, 1, 3 and "
             "4.2 of its family), one thread each, whole process (`/usr/bin/time -v`: wall, "
             "user + sys CPU, peak resident memory). Ours: `punch_scaling --method iterative "
             "--clamped-only`, CG with a p-multigrid preconditioner on an assembled K. Peers: "
             f"{skfem_code} (rigid-body near-null space, sparse-LU coarse solve; "
             "scripts/compare-skfem-tuned.py), CalculiX ccx "
             f"{ccx_version.removeprefix('Version ')} with SPOOLES (scripts/compare-ccx.py). "
             f"The three codes' clamped stiffness k_sn agrees to {worst_dk:.1e} on every mesh. "
             "Ratios are the peer's figure over ours in this run; the CPU ratio is the fair one "
             "on a shared machine (a code's wall time grows with the load, its CPU time much "
             "less).", ""] + rows + ["", "Targets, from this run:", ""] + peer_verdicts(verdict)
            + ["", "Peer configurations and the agreement checks: "
               "[validation/fem-peers/README.md](../validation/fem-peers/README.md)."])


def section_fem_scaling(quick):
    command = ["scripts/fem-scaling.sh", "--repeats", "1" if quick else "2"]
    if quick:
        command += ["--levels", "1 3"]
    started, before = time.time(), load()
    out = run(command)
    lines = [line for line in out.splitlines() if line.startswith(("level", "least"))]
    fit = re.search(r"exponent of the median wall time: N\^([\d.]+) \((\d+) to (\d+)", out)
    peaks = [float(g) for g in re.findall(r"peak ([\d.]+) GB", out)]
    verdict = []
    if fit:
        exponent, low, high = float(fit.group(1)), int(fit.group(2)), int(fit.group(3))
        reach = "met" if exponent <= 1.2 and low <= 55025 and high >= 2e6 else "not met"
        verdict = ["", f"Target: total cost growing no faster than N^1.2 from 55k to ≥ 2M "
                   f"unknowns within 24 GB. This run: N^{exponent:.2f} from {low:,} to {high:,} "
                   .replace(",", " ") + f"unknowns, peak {max(peaks):.2f} GB: {reach}."]
    return ([stamp(started, before, shlex.join(command)), "",
             "The punch family's quarter Tet10 meshes, one thread, `punch_scaling --method "
             "iterative --clamped-only` (CG with the p-multigrid preconditioner on an assembled "
             "K: the problem the peers below solve), whole process. Each line of the output is "
             "one run: unknowns, PCG iterations, wall s, CPU s, peak GB, k_sn, and the phases "
             "(s):", "", "```"] + [l for l in out.splitlines() if re.match(r"\d+ \d+ ", l)]
            + lines + ["```"] + verdict)


def section_threads(quick):
    command = ["scripts/threads-scaling.sh", "--repeats", "1" if quick else "3", "--no-strip"]
    started, before = time.time(), load()
    out = run(command)
    lines = [line for line in out.splitlines() if not line.startswith("#")]
    return ([stamp(started, before, shlex.join(command)), "",
             "The punch at 350k unknowns (`punch_scaling --method iterative`, level 3), each "
             "repeat one thread then two back to back, then two one-thread copies side by side: "
             "2 × t(alone) / t(side by side) is the most two threads can gain on this machine "
             "under its present load (`ceiling`), measured in the same run. Times are the "
             "minimum over the repeats (s):", "", "```"] + lines + ["```", ""]
            + threads_verdict(out))


def threads_verdict(out):
    """The 2-thread target (≥ 1.7× on assembly and on the PCG solve) against this run."""
    rows = {}
    for line in out.splitlines():
        f = line.split()
        if len(f) == 7 and f[0] in ("assembly_s", "solve_s", "total_s", "wall_s"):
            rows[f[0]] = (float(f[3]), float(f[5]))
    if not {"assembly_s", "solve_s"} <= set(rows):
        return []
    parts = []
    for key, what in (("assembly_s", "assembly"), ("solve_s", "PCG solve")):
        speedup, ceiling = rows[key]
        verdict = "met" if speedup >= 1.7 else (
            "not met; the machine's own ceiling in this run is below the target" if ceiling < 1.7
            else "not met")
        parts.append(f"{what} {speedup:.2f}× against a ceiling of {ceiling:.2f}× "
                     f"({speedup / ceiling:.0%} of it): {verdict}")
    return ["Target: two threads ≥ 1.7× one on assembly and on the PCG solve at 350k. This run: "
            + "; ".join(parts) + "."]


def section_operator(quick):
    def rows(found):
        return [(f"`{k}`", k, "—") for k in sorted(found)
                if k.split("/")[0] in ("product", "setup") or "csr" in k or "matrix_free" in k]

    def note(found):
        lines = []
        for n in sorted({k.rsplit("/", 1)[-1] for k in found if "csr_f64" in k}):
            csr = next((v for k, v in found.items() if k.endswith(f"csr_f64/{n}")), None)
            for k, v in sorted(found.items()):
                if csr and "matrix_free" in k and k.endswith(f"/{n}") and "setup" not in k:
                    lines.append(f"- `{k}` ÷ `csr_f64` product at {n}: {v[0] / csr[0]:.2f}×")
        return (["Ratios of this run (medians):", ""] + lines) if lines else []
    return bench_section(["cargo", "bench", "-q", "-p", "elastic-fem", "--bench", "operator", "--",
                          "--sample-size", "10"], None, rows, note)


# name: (heading, function, heavy)
SECTIONS = {
    "default": ("The default scene (the paper's motor)", section_default, False),
    "default-stage": ("The coupled dynamic stage of the default run", section_default_stage,
                      False),
    "strip-mesh": ("The strip mesh alone", section_strip_mesh, False),
    "bench-stick-slip": ("Benchmark: lumped stick–slip models", section_bench_stick_slip, False),
    "bench-coupled": ("Benchmark: coupled model of a post row", section_bench_coupled, False),
    "bench-fem": ("Benchmark: FEM pipeline (assembly, ordering, factorisation)",
                  section_bench_fem, False),
    "bench-slider": ("Benchmark: whole slider, rigid back", section_bench_slider, False),
    "whole-slider-cli": ("The whole slider through the command line", section_whole_slider_cli,
                         False),
    "whole-slider-coupled": ("The whole slider's coupled curve", section_whole_slider_coupled,
                             False),
    "uq": ("UQ", section_uq, False),
    "uq-coupled": ("UQ on the whole slider's coupled model", section_uq_coupled, True),
    "sharded": ("Sharded sweeps", section_sharded, False),
    "python": ("Python overhead", section_python, True),
    "peers": ("The FEM against tuned peers", section_peers, True),
    "fem-scaling": ("FEM cost against problem size", section_fem_scaling, True),
    "threads": ("Two threads against one", section_threads, True),
    "operator": ("Matrix-free or assembled stiffness product", section_operator, True),
}


# --- the document ------------------------------------------------------------------------------


def machine_block(ran, quick):
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo")
                if l.startswith("model name")), "unknown CPU")
    mem_kb = int(next(l.split()[1] for l in open("/proc/meminfo") if l.startswith("MemTotal")))
    osname = next((l.split("=", 1)[1].strip().strip('"') for l in open("/etc/os-release")
                   if l.startswith("PRETTY_NAME")), "unknown OS")
    rustc = subprocess.run(["rustc", "-V"], capture_output=True, text=True).stdout.strip()
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return [
        f"**Machine.** {cpu}, {os.cpu_count()} cores, {mem_kb / 2**20:.0f} GB, {osname} "
        f"(Linux {os.uname().release}), {rustc}, release builds unless a section says otherwise. "
        f"The machine is shared with other jobs: every section states the load average before "
        f"and after it ran (a load above the core count means the figures are upper bounds). "
        f"Last run: {when} at commit {commit()}, load average {load()} at its end, "
        f"`scripts/performance.sh{' --quick' if quick else ''} --section {' '.join(ran)}`.",
    ]


HEADER = [
    "# Performance: the current figures",
    "",
    "Written by `scripts/performance.sh` from the output of the project's benchmark and timing",
    "scripts; do not edit between the markers (the next run overwrites it). Every section names",
    "the one command that produced its figures, with its date, commit and the load average;",
    "ratios are only formed within one section's run. Regenerate everything with",
    "`scripts/performance.sh` or one section with `scripts/performance.sh --section NAME`",
    "(`--list` names them; `--quick` is the cheaper setting). Older figures are not kept here",
    "(the [CHANGELOG](../CHANGELOG.md) says what made the code faster).",
    "",
]


def split_doc(text):
    """(machine lines, {name: body lines}) of an existing document."""
    bodies, machine = {}, []
    for name in SECTIONS:
        m = re.search(re.escape(BEGIN.format(name)) + r"\n(.*?)\n" + re.escape(END.format(name)),
                      text, re.S)
        if m:
            lines = m.group(1).split("\n")
            bodies[name] = lines[2:] if lines[:1] == [f"## {SECTIONS[name][0]}"] else lines
    m = re.search(re.escape(BEGIN.format("machine")) + r"\n(.*?)\n" + re.escape(END.format(
        "machine")), text, re.S)
    if m:
        machine = m.group(1).split("\n")
    return machine, bodies


def not_generated(name):
    return ["*Not generated yet: run `scripts/performance.sh --section " + name + "`.*"]


def wrapped(lines, width=100):
    """Prose lines wrapped at `width` (Markdown lines stay readable and under the docs' 400
    characters); table rows, headings, markers, list items and code blocks are kept as they are."""
    out, code = [], False
    for line in lines:
        if line.startswith("```"):
            code = not code
        keep = (code or len(line) <= width or line.startswith(("|", "#", "<!--", "    "))
                or line.lstrip().startswith(("- ", "* ", "`")))
        out += [line] if keep else textwrap.wrap(line, width, break_long_words=False,
                                                 break_on_hyphens=False)
    return out


def write_doc(machine, bodies):
    lines = list(HEADER)
    lines += [BEGIN.format("machine")] + wrapped(machine) + [END.format("machine"), ""]
    for name, (heading, _, _) in SECTIONS.items():
        body = wrapped(bodies.get(name) or not_generated(name))
        lines += [BEGIN.format(name), f"## {heading}", ""] + body + [END.format(name), ""]
    DOC.write_text("\n".join(lines).rstrip("\n") + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="cheaper setting of every command")
    parser.add_argument("--section", nargs="+", metavar="NAME", choices=list(SECTIONS),
                        help="regenerate only these sections")
    parser.add_argument("--list", action="store_true", help="list the sections and exit")
    args = parser.parse_args()
    if args.list:
        for name, (heading, _, heavy) in SECTIONS.items():
            print(f"{name:<18} {heading}{'  (heavy: only when named)' if heavy else ''}")
        return 0
    names = args.section or [n for n, (_, _, heavy) in SECTIONS.items() if not heavy]
    machine, bodies = split_doc(DOC.read_text() if DOC.exists() else "")
    ran, failed = [], []
    for name in names:
        started = time.time()
        try:
            bodies[name] = SECTIONS[name][1](args.quick)
            ran.append(name)
            print(f"performance.sh: section {name} done in {time.time() - started:.0f} s",
                  file=sys.stderr)
        except Failed as error:
            failed.append(f"{name}: {error}")
            print(f"performance.sh: section {name} NOT regenerated: {error}", file=sys.stderr)
        # Written after every section, so that an interrupted run keeps what it measured.
        if ran:
            write_doc(machine_block(ran, args.quick), bodies)
    for line in failed:
        print(f"performance.sh: kept as it was: {line}", file=sys.stderr)
    return 1 if failed and args.section else 0


if __name__ == "__main__":
    sys.exit(main())
