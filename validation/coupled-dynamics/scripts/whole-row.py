#!/usr/bin/env python3
"""The coupled-vs-lumped study on whole-row strips: for the paper's sliders (five counts of
20 um posts, four diameters at equal tip area) at 10, 40 and 100 N, run `sawdrive dynamic --json`
with model.dynamics = "coupled" on the static stage's own strip (the whole row of posts along the
wave) and write one CSV row per run to stdout: the coupled and lumped (static eta) stall thrust
and no-load speed, the lumped model's error and its estimate, eta and eta_dyn, wall time.

The wave at constant amplitude (wave.attenuation = off), as the study was made.

Usage: whole-row.py SAWDRIVE OUT   (OUT/.cache keeps the meshes, FEM reports and compliances)
"""
import csv, json, subprocess, sys

SLIDERS = [("20 um", "100x100"), ("20 um", "80x80"), ("20 um", "66x66"), ("20 um", "50x50"),
           ("20 um", "33x33"), ("30 um", "67x67"), ("40 um", "50x50"), ("50 um", "40x40")]
PRELOADS = ["10 N", "40 N", "100 N"]
STEPS_PER_PERIOD = 128

def run(binary, out, diameter, count, preload):
    sets = [f"posts.diameter={diameter}", f"posts.count={count}", f"preload={preload}",
            "model.dynamics=coupled", f"model.coupled.steps_per_period={STEPS_PER_PERIOD}",
            "wave.attenuation=off"]
    args = [binary, "dynamic", "--out", out, "--json"]
    for s in sets:
        args += ["--set", s]
    return json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)

def relative(lumped, coupled):
    """|lumped/coupled - 1|; 0 when both are 0 (a locked slider), inf when only the coupled is."""
    if coupled == 0:
        return 0.0 if lumped == 0 else float("inf")
    return abs(lumped / coupled - 1)

def main():
    binary, out = sys.argv[1], sys.argv[2]
    w = None
    for diameter, count in SLIDERS:
        for preload in PRELOADS:
            d = run(binary, out, diameter, count, preload)
            lumped = d["lumped"]
            err_f = relative(lumped["stall_thrust_n"], d["stall_thrust_n"])
            err_v = relative(lumped["no_load_speed_m_per_s"], d["no_load_speed_m_per_s"])
            nx, ny = (int(v) for v in count.split("x"))
            row = {
                "post_diameter_um": diameter.split()[0], "posts": nx * ny,
                "strip_posts": d["posts"], "preload_n": preload.split()[0],
                "eta_dyn": d["eta_dyn"],
                "stall_coupled_n": d["stall_thrust_n"], "stall_lumped_n": lumped["stall_thrust_n"],
                "no_load_coupled_m_per_s": d["no_load_speed_m_per_s"],
                "no_load_lumped_m_per_s": lumped["no_load_speed_m_per_s"],
                "lumped_error": max(err_f, err_v),
                # JSON has no infinity: a bound that says nothing (a nearly locked slider) is null.
                "lumped_error_estimate": d["lumped_error_estimate"] if d["lumped_error_estimate"] is not None else float("inf"),
                "energy_balance_residual": d["energy_balance_residual"],
                "coupled_wall_s": d["wall_time_s"],
            }
            if w is None:
                w = csv.DictWriter(sys.stdout, fieldnames=list(row), lineterminator="\n")
                w.writeheader()
            w.writerow(row)
            sys.stdout.flush()

main()
