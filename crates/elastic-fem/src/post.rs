//! Post-processing: strains and stresses per element, von Mises, nodal averages, strain
//! energy, reactions. Displacements are full vectors `u` (m) with DOF `3 n + c`.

use rayon::prelude::*;

use crate::element::element_strain;
use crate::error::{FemError, FemResult};
use crate::model::{Connectivity, Model};
use crate::shape::{Tet4, Tet10, TetShape};
use crate::sparse::SymmetricMatrix;

pub use crate::material::von_mises;

/// Strain and stress at one point of an element (Voigt `[xx, yy, zz, yz, xz, xy]`,
/// engineering shear strain).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointStress {
    /// Small strain (dimensionless).
    pub strain: [f64; 6],
    /// Cauchy stress (Pa).
    pub stress_pa: [f64; 6],
}

impl PointStress {
    /// von Mises stress (Pa).
    pub fn von_mises_pa(&self) -> f64 {
        von_mises(&self.stress_pa)
    }
}

fn check_u(model: &Model, u: &[f64]) -> FemResult<()> {
    if u.len() != model.dof_count() {
        return Err(FemError::DimensionMismatch {
            what: "displacement vector",
            expected: model.dof_count(),
            found: u.len(),
        });
    }
    Ok(())
}

fn point_stress<const N: usize, S: TetShape<N>>(
    model: &Model,
    e: usize,
    nodes: &[usize; N],
    u: &[f64],
    xi: [f64; 3],
) -> PointStress {
    let x = model.element_coords(nodes);
    let ue: [[f64; 3]; N] = nodes.map(|n| [u[3 * n], u[3 * n + 1], u[3 * n + 2]]);
    // Geometry was validated at model construction: det J > 0 at the points used here.
    let strain = element_strain::<N, S>(&x, &ue, xi).unwrap_or([f64::NAN; 6]);
    let c = model.constitutive_of(e).voigt_stiffness();
    let s = c * nalgebra::Vector6::from(strain);
    PointStress {
        strain,
        stress_pa: [s[0], s[1], s[2], s[3], s[4], s[5]],
    }
}

/// Strain and stress of element `e` at reference point `xi`.
pub fn element_stress_at(
    model: &Model,
    u: &[f64],
    e: usize,
    xi: [f64; 3],
) -> FemResult<PointStress> {
    check_u(model, u)?;
    Ok(match model.connectivity() {
        Connectivity::Tet4(c) => point_stress::<4, Tet4>(model, e, &c[e], u, xi),
        Connectivity::Tet10(c) => point_stress::<10, Tet10>(model, e, &c[e], u, xi),
    })
}

/// Strain and stress at every element centroid (ξ = (¼, ¼, ¼)).
pub fn centroid_stresses(model: &Model, u: &[f64]) -> FemResult<Vec<PointStress>> {
    check_u(model, u)?;
    Ok(match model.connectivity() {
        Connectivity::Tet4(c) => c
            .par_iter()
            .enumerate()
            .map(|(e, el)| point_stress::<4, Tet4>(model, e, el, u, [0.25; 3]))
            .collect(),
        Connectivity::Tet10(c) => c
            .par_iter()
            .enumerate()
            .map(|(e, el)| point_stress::<10, Tet10>(model, e, el, u, [0.25; 3]))
            .collect(),
    })
}

/// Nodal stress (Pa): for each node, the volume-weighted average over the elements around it
/// of each element's stress evaluated at that node. Nodes in no element get zeros.
pub fn nodal_averaged_stress(model: &Model, u: &[f64]) -> FemResult<Vec<[f64; 6]>> {
    check_u(model, u)?;
    let mut sum = vec![[0.0; 6]; model.node_count()];
    let mut weight = vec![0.0; model.node_count()];
    fn accumulate<const N: usize, S: TetShape<N>>(
        model: &Model,
        conn: &[[usize; N]],
        u: &[f64],
        sum: &mut [[f64; 6]],
        weight: &mut [f64],
    ) {
        let refs = S::reference_nodes();
        for (e, el) in conn.iter().enumerate() {
            let x = model.element_coords(el);
            let volume = crate::element::physical_gradients::<N, S>(&x, [0.25; 3])
                .map_or(0.0, |(_, det)| det / 6.0);
            for (a, &n) in el.iter().enumerate() {
                let s = point_stress::<N, S>(model, e, el, u, refs[a]);
                for k in 0..6 {
                    sum[n][k] += volume * s.stress_pa[k];
                }
                weight[n] += volume;
            }
        }
    }
    match model.connectivity() {
        Connectivity::Tet4(c) => accumulate::<4, Tet4>(model, c, u, &mut sum, &mut weight),
        Connectivity::Tet10(c) => accumulate::<10, Tet10>(model, c, u, &mut sum, &mut weight),
    }
    Ok(sum
        .into_iter()
        .zip(weight)
        .map(|(s, w)| if w > 0.0 { s.map(|v| v / w) } else { [0.0; 6] })
        .collect())
}

/// Strain energy ½ uᵀ K u (J).
pub fn strain_energy(stiffness: &SymmetricMatrix, u: &[f64]) -> FemResult<f64> {
    if u.len() != stiffness.dim() {
        return Err(FemError::DimensionMismatch {
            what: "displacement vector",
            expected: stiffness.dim(),
            found: u.len(),
        });
    }
    Ok(0.5 * stiffness.quadratic_form(u))
}

/// Reaction forces r = K u − f (N): the forces the constraints exert on the body; zero up to
/// round-off at unconstrained DOFs.
pub fn reaction_forces(stiffness: &SymmetricMatrix, u: &[f64], f: &[f64]) -> FemResult<Vec<f64>> {
    if u.len() != stiffness.dim() || f.len() != stiffness.dim() {
        return Err(FemError::DimensionMismatch {
            what: "displacement / load vector",
            expected: stiffness.dim(),
            found: u.len().min(f.len()),
        });
    }
    let mut r = vec![0.0; u.len()];
    stiffness.mul_vec(u, &mut r);
    r.iter_mut().zip(f).for_each(|(a, b)| *a -= b);
    Ok(r)
}
