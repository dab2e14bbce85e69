#!/usr/bin/env python3
"""Tabulate the whole-row sweep's point summaries (points/*.json) as CSV on stdout: per slider and
preload, the coupled model's stall thrust and no-load speed, the lumped model's at the static η,
their relative errors, η (static) and η_dyn, the lumped error estimate, and the wall time."""
import csv, glob, json, os, sys

rows = []
for path in glob.glob(os.path.join(sys.argv[1], "*.json")):
    point = json.load(open(path))
    s = point.get("summary", point)
    c = s["coupled"]
    lumped = c["lumped"]
    scene = s["scene"]
    posts = scene["posts"]
    err_f = abs(lumped["stall_thrust_n"] - s["stall_thrust_n"]) / s["stall_thrust_n"]
    err_v = abs(lumped["no_load_speed_m_per_s"] - s["no_load_speed_m_per_s"]) / s["no_load_speed_m_per_s"]
    rows.append({
        "post_diameter_um": round(posts["diameter_m"] * 1e6, 3),
        "posts": posts["count_x"] * posts["count_y"],
        "strip_posts": c["posts"],
        "preload_n": scene["load"]["preload_n"],
        "eta_static": s["effective_contact_ratio"],
        "eta_dyn": c["eta_dyn"],
        "stall_coupled_n": s["stall_thrust_n"],
        "stall_lumped_n": lumped["stall_thrust_n"],
        "no_load_coupled_m_per_s": s["no_load_speed_m_per_s"],
        "no_load_lumped_m_per_s": lumped["no_load_speed_m_per_s"],
        "lumped_error": max(err_f, err_v),
        "lumped_error_estimate": s["lumped_error_estimate"],
        "energy_balance_residual": c["energy_balance_residual"],
        "dynamic_wall_s": s["timings"]["dynamic_s"],
    })
rows.sort(key=lambda r: (r["post_diameter_um"], -r["posts"], r["preload_n"]))
w = csv.DictWriter(sys.stdout, fieldnames=list(rows[0].keys()), lineterminator="\n")
w.writeheader()
w.writerows(rows)
