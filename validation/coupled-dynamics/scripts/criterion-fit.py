#!/usr/bin/env python3
"""Can a sharper `lumped_error_estimate` keep the lumped model where it is within 2 %?

Reads the two studies of this folder (results/sliders.csv: short strips; results/whole-row.csv: whole
rows) and, for estimates of the form C * r_fit^a * (V_crest / v0_lumped)^b with C the envelope
(the smallest C that bounds the measured error of every scene with a moving slider), prints how
many scenes each form would send to the lumped model at the 2 % tolerance, how many are really
within 2 %, and how far it overestimates. The crate's estimate is a = b = 1 (C = 0.6).

r_fit * V_crest / v0_lumped is recovered from each row's `lumped_error_estimate` / 0.6, and
V_crest from a short-strip row, where r_fit is a column.

Usage: criterion-fit.py   (from anywhere; standard library only)
"""
import csv, math, os

HERE = os.path.dirname(os.path.abspath(__file__))
FACTOR = 0.6  # coupled_dynamics::criterion::LUMPED_ERROR_FACTOR, with which both CSVs were made
TOLERANCE = 0.02
FORMS = [(1, 1), (1, 1.5), (1, 2), (1, 2.5), (1.5, 2), (2, 1)]


def scenes():
    strip = list(csv.DictReader(open(os.path.join(HERE, "..", "results", "sliders.csv"))))
    first = strip[0]
    v0 = float(first["lumped_static_no_load_speed_m_per_s"])
    crest = float(first["lumped_error_estimate"]) / FACTOR / float(first["eta_fit_misfit"]) * v0
    rows = []
    for x in strip:
        rows.append(("short strip", x["posts_per_side"], x["preload_n"], float(x["lumped_static_error"]),
                     float(x["lumped_error_estimate"]), float(x["lumped_static_no_load_speed_m_per_s"])))
    for x in csv.DictReader(open(os.path.join(HERE, "..", "results", "whole-row.csv"))):
        rows.append(("whole row", x["posts"], x["preload_n"], float(x["lumped_error"]),
                     float(x["lumped_error_estimate"]), float(x["no_load_lumped_m_per_s"])))
    # (study, posts, preload, measured error, r_fit, V_crest / v0)
    return crest, [(s, p, f, e, est / FACTOR * v / crest, crest / v) for s, p, f, e, est, v in rows]


def main():
    crest, rows = scenes()
    moving = [r for r in rows if math.isfinite(r[3]) and r[5] < 100]
    within = sum(1 for r in rows if r[3] <= TOLERANCE)
    print(f"V_crest = {crest:.4f} m/s; {len(rows)} scenes, {len(moving)} with a moving slider, "
          f"{within} within {TOLERANCE:.0%} measured")
    print("a    b    envelope C  picks lumped  of which really within  largest overestimate")
    for a, b in FORMS:
        C = max(e / (r ** a * q ** b) for *_, e, r, q in moving)
        estimate = [C * r ** a * q ** b for *_, e, r, q in rows]
        picked = [row for row, s in zip(rows, estimate) if s <= TOLERANCE]
        good = sum(1 for row in picked if row[3] <= TOLERANCE)
        over = max(s / row[3] for row, s in zip(rows, estimate) if row in moving and row[3] > 0)
        print(f"{a:<4} {b:<4} {C:<11.4f} {len(picked):<13} {good:<23} {over:.1f}x")


if __name__ == "__main__":
    main()
