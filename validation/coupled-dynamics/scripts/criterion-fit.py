#!/usr/bin/env python3
"""The calibration of `lumped_error_estimate` and whether a sharper form of it exists.

Reads the two studies of this folder (results/sliders.csv: short strips; results/whole-row.csv:
whole rows). For every scene with a moving slider it prints x = r_fit * V_crest / v0_lumped, the
difference of the two models relative to the lumped figures,
eps_l = max(|dF|/F_lumped, |dv0|/v0_lumped), the error relative to the coupled figures
e = max(|dF|/F_coupled, |dv0|/v0_coupled), and the ratios eps_l / x (whose envelope is the
crate's factor C = coupled_dynamics::LUMPED_ERROR_FACTOR) and e / bound, where
bound = C x / (1 - C x) is the estimate (e <= eps_l / (1 - eps_l) by construction).

Then, for bounds of the form eps = C * r_fit^a * (V_crest / v0_lumped)^b, C the envelope of
eps_l, it prints how many scenes each form would send to the lumped model at the 2 % tolerance,
how many of those are really within 2 %, and how far it overestimates. The crate's form is
a = b = 1.

x is recovered from each row's `lumped_error_estimate` (x = est / (1 + est) / C), and V_crest
from a short-strip row, where r_fit is a column.

Usage: criterion-fit.py   (from anywhere; standard library only)
"""
import csv, math, os

HERE = os.path.dirname(os.path.abspath(__file__))
FACTOR = 0.6  # coupled_dynamics::criterion::LUMPED_ERROR_FACTOR, with which both CSVs were made
TOLERANCE = 0.02
FORMS = [(1, 1), (1, 1.5), (1, 2), (1, 2.5), (1.5, 2), (2, 1)]


def number(text):
    return math.inf if text in ("", "None", "inf", "null") else float(text)


def x_of(estimate):
    """r_fit * V_crest / v0_lumped from the bound est = C x / (1 - C x)."""
    return estimate / (1 + estimate) / FACTOR if math.isfinite(estimate) else math.inf


def errors(fc, vc, fl, vl):
    if vc <= 0 or not math.isfinite(vc) or vc < 1e-6:
        return None
    e = max(abs(fl / fc - 1), abs(vl / vc - 1))
    eps_l = max(abs(fc / fl - 1), abs(vc / vl - 1))
    return e, eps_l


def scenes():
    strip = list(csv.DictReader(open(os.path.join(HERE, "..", "results", "sliders.csv"))))
    first = strip[0]
    v0 = float(first["lumped_static_no_load_speed_m_per_s"])
    crest = x_of(number(first["lumped_error_estimate"])) / float(first["eta_fit_misfit"]) * v0
    rows = []
    for x in strip:
        fc, vc = float(x["coupled_stall_thrust_n"]), float(x["coupled_no_load_speed_m_per_s"])
        fl = float(x["lumped_static_stall_thrust_n"])
        vl = float(x["lumped_static_no_load_speed_m_per_s"])
        rows.append(("short strip", float(x["post_diameter_m"]) * 1e6, int(x["posts_per_side"]) ** 2,
                     x["preload_n"], (fc, vc, fl, vl), number(x["lumped_error_estimate"])))
    for x in csv.DictReader(open(os.path.join(HERE, "..", "results", "whole-row.csv"))):
        fc, vc = float(x["stall_coupled_n"]), float(x["no_load_coupled_m_per_s"])
        fl, vl = float(x["stall_lumped_n"]), float(x["no_load_lumped_m_per_s"])
        rows.append(("whole row", float(x["post_diameter_um"]), int(x["posts"]), x["preload_n"],
                     (fc, vc, fl, vl), number(x["lumped_error_estimate"])))
    out = []
    for study, d, n, p, figures, est in rows:
        x = x_of(est)
        r_fit = x * figures[3] / crest
        out.append((study, d, n, p, errors(*figures), r_fit, crest / figures[3], est))
    return crest, out


def calibration(rows):
    print("study        slider           P (N)  x       eps_l   e       eps_l/x  e/bound")
    moving = [r for r in rows if r[4] is not None]
    for study, d, n, p, (e, eps_l), r_fit, q, est in moving:
        x = r_fit * q
        print(f"{study:<12} {d:>2.0f} um x {n:<6} {p:>5}  {x:<7.4f} {eps_l:<7.4f} {e:<7.4f} "
              f"{eps_l / x:<8.3f} {e / est:.3f}")
    ratios = [r[4][1] / (r[5] * r[6]) for r in moving]
    over = [r[4][0] / r[7] for r in moving]
    plain = [r[4][0] / (r[5] * r[6]) for r in moving]
    print(f"{len(moving)} moving scenes: eps_l / x in {min(ratios):.3f}-{max(ratios):.3f} "
          f"(the factor {FACTOR} is its envelope rounded up); e / x in "
          f"{min(plain):.3f}-{max(plain):.3f}; e / bound in {min(over):.3f}-{max(over):.3f}")
    return moving


def forms(rows, moving):
    within = sum(1 for r in rows if r[4] is not None and r[4][0] <= TOLERANCE)
    print(f"\n{len(rows)} scenes, {len(moving)} with a moving slider, {within} within "
          f"{TOLERANCE:.0%} measured")
    print("a    b    envelope C  picks lumped  of which really within  largest overestimate")
    for a, b in FORMS:
        C = max(r[4][1] / (r[5] ** a * r[6] ** b) for r in moving)
        bounds = []
        for r in rows:
            eps = C * r[5] ** a * r[6] ** b
            bounds.append(eps / (1 - eps) if eps < 1 else math.inf)
        picked = [r for r, s in zip(rows, bounds) if s <= TOLERANCE]
        good = sum(1 for r in picked if r[4] is not None and r[4][0] <= TOLERANCE)
        worst = max(s / r[4][0] for r, s in zip(rows, bounds) if r in moving and r[4][0] > 0)
        print(f"{a:<4} {b:<4} {C:<11.4f} {len(picked):<13} {good:<23} {worst:.1f}x")


def main():
    crest, rows = scenes()
    print(f"V_crest = {crest:.4f} m/s")
    moving = calibration(rows)
    forms(rows, moving)


if __name__ == "__main__":
    main()
