#!/usr/bin/env python3
"""Peer comparison: the frictionless normal punch stiffness k_sn with scikit-fem on a sawdrive
punch mesh (quarter model, meshes/punch.geo with sym=2), for the comparison with the validation
crate's FEM on the *same* .msh file, the same elements (isoparametric Tet10 = skfem MeshTet2 +
ElementTetP2, or Tet4 = MeshTet1 + ElementTetP1) and the same boundary conditions:

  punch disk (z = 0, r < a):  u_z = -delta, u_x and u_y free  (frictionless)
  far field (r = R):          u = 0                             (clamped)
  x = 0: u_x = 0;  y = 0: u_y = 0                               (quarter symmetry)

Stiffness = 4 x (sum of the reactions K u over the punch u_z dofs) / delta. Timings are wall
times of scikit-fem's own pipeline: basis, assembly, condense + solve (default direct solver:
scipy.sparse.linalg.spsolve, SuperLU) -- the established open code as a user runs it.

Usage: compare-skfem.py MESH.msh [--shear-modulus 67e9] [--poisson 0.25]
Prints one JSON object. Run through scripts/compare-skfem.sh for the side-by-side comparison.
"""
import argparse
import json
import resource
import time

import meshio
import numpy as np
import skfem
from skfem import Basis, ElementTetP1, ElementTetP2, ElementVector, MeshTet2, asm, condense, solve
from skfem.models.elasticity import linear_elasticity


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mesh")
    parser.add_argument("--shear-modulus", type=float, default=67.0e9, help="G in Pa (LiNbO3: 67 GPa)")
    parser.add_argument("--poisson", type=float, default=0.25, help="Poisson ratio (LiNbO3: 0.25)")
    args = parser.parse_args()

    t0 = time.perf_counter()
    mesh = skfem.Mesh.load(args.mesh)
    t_load = time.perf_counter() - t0

    size = np.max(np.linalg.norm(mesh.p, axis=0))  # truncation radius R
    tol = 1e-9 * size

    def on_top(x):
        return np.abs(x[2]) < tol

    # Punch radius a: the largest distance from the axis of the nodes of the "punch" physical
    # group (scikit-fem does not attach gmsh's quadratic boundary groups, so read them with meshio).
    raw = meshio.read(args.mesh)
    punch_cells = [raw.cells[i].data[idx] for name, sets in raw.cell_sets.items() if name == "punch"
                   for i, idx in enumerate(sets) if idx is not None and len(idx) > 0]
    if not punch_cells:
        raise SystemExit(f"{args.mesh}: no 'punch' physical group")
    punch_nodes = np.unique(np.concatenate([c.ravel() for c in punch_cells]))
    a = float(np.max(np.hypot(raw.points[punch_nodes, 0], raw.points[punch_nodes, 1])))
    mid = mesh.p[:, mesh.facets].mean(axis=1)
    boundary = mesh.boundary_facets()
    bx = mid[:, boundary]
    is_top = on_top(bx)
    punch = boundary[is_top & (np.hypot(bx[0], bx[1]) < a * (1 + 1e-9))]
    sym_x0 = boundary[np.abs(bx[0]) < tol]
    sym_y0 = boundary[np.abs(bx[1]) < tol]
    far = boundary[~is_top & (np.abs(bx[0]) >= tol) & (np.abs(bx[1]) >= tol)]

    t1 = time.perf_counter()
    element = ElementTetP2() if isinstance(mesh, MeshTet2) else ElementTetP1()
    basis = Basis(mesh, ElementVector(element))
    t_basis = time.perf_counter() - t1

    g, nu = args.shear_modulus, args.poisson
    lam = 2 * g * nu / (1 - 2 * nu)
    t2 = time.perf_counter()
    stiffness = asm(linear_elasticity(lam, g), basis)
    t_assembly = time.perf_counter() - t2

    delta = 1e-3 * a
    punch_z = basis.get_dofs(punch).all("u^3")
    fixed = np.unique(np.concatenate([
        basis.get_dofs(far).all(),
        basis.get_dofs(sym_x0).all("u^1"),
        basis.get_dofs(sym_y0).all("u^2"),
        punch_z,
    ]))
    u = np.zeros(basis.N)
    u[punch_z] = -delta
    t3 = time.perf_counter()
    u = solve(*condense(stiffness, x=u, D=fixed))
    t_solve = time.perf_counter() - t3

    reaction = stiffness @ u
    force = -4.0 * reaction[punch_z].sum()
    k = force / delta
    analytic = 4 * g * a / (1 - nu)
    print(json.dumps({
        "code": f"scikit-fem {skfem.__version__}",
        "mesh": args.mesh,
        "element": type(element).__name__,
        "unknowns": int(basis.N - fixed.size),
        "radius_m": float(a),
        "truncation_ratio": float(size / a),
        "k_sn_clamped_n_per_m": float(k),
        "k_sn_clamped_over_analytic": float(k / analytic),
        "load_s": t_load,
        "basis_s": t_basis,
        "assembly_s": t_assembly,
        "condense_solve_s": t_solve,
        "total_s": t_basis + t_assembly + t_solve,
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
    }))


if __name__ == "__main__":
    main()
