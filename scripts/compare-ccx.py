#!/usr/bin/env python3
"""Peer: the clamped frictionless punch stiffness k_sn with CalculiX ccx (Debian package
calculix-ccx, its default direct solver SPOOLES; PaStiX when the build has it and --solver
pastix is given) on the same .msh as the validation crate's FEM.

Writes an .inp deck (C3D10: corners, then edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4, which is meshio's
tetra10 order), the boundary conditions of validation's punch problem A (punch_scaling --clamped-only)

  punch disk (z = 0, r < a):  u_z = -delta (frictionless);  far field r = R: u = 0;
  x = 0: u_x = 0;  y = 0: u_y = 0  (quarter symmetry)

and reads the total reaction of the punch node set (*NODE PRINT, TOTALS=ONLY) from the .dat
file: k = 4 |RF_z| / delta. The wall time and peak memory are those of the ccx process alone
(deck writing excluded), measured with /usr/bin/time -v.

Usage: compare-ccx.py MESH.msh [--solver spooles|pastix] [--workdir DIR]. Prints one JSON object.
"""
import argparse
import json
import os
import re
import subprocess
import tempfile
import time

import meshio
import numpy as np

# ccx rejects elements with a Jacobian below an absolute threshold (≈ 1e-20), which the
# sub-micrometre elements near the punch edge fall under in metres: the deck is written in mm,
# N and MPa (lengths × 1e3, moduli × 1e-6), and k converted back to N/m.
MM_PER_M = 1e3

# meshio stores tetra10 in VTK order: corners, edges (0,1), (1,2), (2,0), (0,3), (1,3), (2,3),
# which is ccx's C3D10 order. ccx position k takes meshio node MESHIO_TO_CCX[k].
MESHIO_TO_CCX = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]


def write_deck(path, mesh_path, g, nu, solver):
    raw = meshio.read(mesh_path)
    pts = raw.points * MM_PER_M
    tets = np.concatenate([c.data for c in raw.cells if c.type == "tetra10"])
    used = np.unique(tets)
    size = np.max(np.linalg.norm(pts[used], axis=1))
    tol = 1e-9 * size
    punch_cells = [raw.cells[i].data[idx] for name, sets in raw.cell_sets.items() if name == "punch"
                   for i, idx in enumerate(sets) if idx is not None and len(idx) > 0]
    punch = np.unique(np.concatenate([c.ravel() for c in punch_cells]))
    a = float(np.max(np.hypot(pts[punch, 0], pts[punch, 1])))
    p = pts[used]
    r = np.linalg.norm(p, axis=1)
    far = used[np.abs(r - size) < 1e-6 * size]
    x0 = used[np.abs(p[:, 0]) < tol]
    y0 = used[np.abs(p[:, 1]) < tol]
    delta = 1e-3 * a
    e_mod = 2 * g * (1 + nu) / MM_PER_M ** 2
    with open(path, "w") as f:
        f.write("*NODE\n")
        for n in used:
            f.write(f"{n + 1},{pts[n, 0]:.12e},{pts[n, 1]:.12e},{pts[n, 2]:.12e}\n")
        f.write("*ELEMENT,TYPE=C3D10,ELSET=EALL\n")
        for e, t in enumerate(tets):
            f.write(f"{e + 1}," + ",".join(str(t[k] + 1) for k in MESHIO_TO_CCX) + "\n")

        def nset(name, nodes):
            f.write(f"*NSET,NSET={name}\n")
            for i in range(0, len(nodes), 16):
                f.write(",".join(str(n + 1) for n in nodes[i:i + 16]) + "\n")

        nset("PUNCH", punch)
        nset("FAR", far)
        nset("XZERO", x0)
        nset("YZERO", y0)
        f.write(f"*MATERIAL,NAME=M\n*ELASTIC\n{e_mod:.12e},{nu}\n*SOLID SECTION,ELSET=EALL,MATERIAL=M\n")
        f.write(f"*STEP\n*STATIC,SOLVER={solver.upper()}\n*BOUNDARY\nFAR,1,3,0.\nXZERO,1,1,0.\nYZERO,2,2,0.\n")
        f.write(f"PUNCH,3,3,{-delta:.12e}\n")
        f.write("*NODE PRINT,NSET=PUNCH,TOTALS=ONLY\nRF\n*END STEP\n")
    fixed = len(far) * 3 + len(x0) + len(y0) + len(punch)
    return a, delta, len(used), fixed


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mesh")
    parser.add_argument("--shear-modulus", type=float, default=67.0e9)
    parser.add_argument("--poisson", type=float, default=0.25)
    parser.add_argument("--solver", default="spooles", choices=["spooles", "pastix"])
    parser.add_argument("--workdir", default=None)
    args = parser.parse_args()
    work = args.workdir or tempfile.mkdtemp(prefix="ccx-punch-")
    os.makedirs(work, exist_ok=True)
    deck = os.path.join(work, "punch.inp")
    a, delta, nodes, fixed_estimate = write_deck(deck, args.mesh, args.shear_modulus, args.poisson,
                                                 args.solver)
    t0 = time.perf_counter()
    run = subprocess.run(["/usr/bin/time", "-v", "ccx", "-i", "punch"], cwd=work,
                         capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if run.returncode != 0:
        raise SystemExit(f"ccx failed ({run.returncode}): {run.stdout[-2000:]}{run.stderr[-2000:]}")
    peak_kb = float(re.search(r"Maximum resident set size \(kbytes\): (\d+)", run.stderr).group(1))
    dat = open(os.path.join(work, "punch.dat")).read()
    totals = re.findall(r"total force.*?\n\s*\n?\s*([-+0-9.Ee]+)\s+([-+0-9.Ee]+)\s+([-+0-9.Ee]+)",
                        dat, flags=re.S)
    if not totals:
        raise SystemExit(f"no reaction totals in {work}/punch.dat")
    rf_z = float(totals[-1][2])
    a /= MM_PER_M
    k = 4.0 * abs(rf_z) / delta * MM_PER_M
    g, nu = args.shear_modulus, args.poisson
    print(json.dumps({
        "code": f"CalculiX ccx ({args.solver})",
        "mesh": args.mesh,
        "nodes": nodes,
        "k_sn_clamped_n_per_m": k,
        "k_sn_clamped_over_analytic": k / (4 * g * a / (1 - nu)),
        "total_s": wall,
        "peak_rss_mb": peak_kb / 1024.0,
        "workdir": work,
    }))


if __name__ == "__main__":
    main()
