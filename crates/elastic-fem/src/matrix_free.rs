//! Matrix-free product with the Tet10 stiffness: y = K x = Σ_e A_eᵀ K_e A_e x without K.
//!
//! This is the measured alternative to the assembled matrix of the iterative path (matrix-free
//! or assembled was to be decided by measurement; the numbers and the choice are
//! in this crate's README, "Matrix-free or assembled"). At each quadrature point of an element
//! the product is the classic three steps (Hughes, *The Finite Element Method*, §3.10):
//!
//! - displacement gradient H = Σ_a u_a ⊗ ∇N_a (3 × 3);
//! - stress σ = C : sym(H) (isotropic: λ tr(ε) I + 2 μ ε; otherwise the 6 × 6 Voigt matrix);
//! - y_a += w det J · σ ∇N_a.
//!
//! About 10³ multiply-adds per Tet10 element with 4 points, against ≈ 340 stored entries per
//! element row block of the assembled K (12 bytes each with the column index).
//!
//! Two ways to hold the geometry ([`MatrixFreeGeometry`]):
//! - `Gradients`: w det J and the physical gradients ∇N_a at every quadrature point (124 f64 per
//!   straight-sided element; curved elements keep their 14-point rule);
//! - `Jacobians`: J⁻¹ and w det J per element (10 f64), the reference gradients at the 4 points
//!   being shared; H = (Σ_a u_a ⊗ ∇_ξ N_a) J⁻¹ and y_a += (w det J σ J⁻ᵀ) ∇_ξ N_a. Straight-sided
//!   elements only (J constant per element); a curved element is refused.
//!
//! One thread, elements in mesh order (a measurement instrument; the assembled path is the
//! solver's). Units: x in m gives y in N.

use nalgebra::Matrix3;

use crate::element::{
    Constitutive, displacement_gradient, physical_gradients, tet10_stiffness_rule, voigt_strain,
};
use crate::error::{FemError, FemResult};
use crate::model::{Connectivity, Model};
use crate::quadrature::tet_degree2;
use crate::shape::{Tet10, TetShape};

/// How the element geometry is held between products.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MatrixFreeGeometry {
    /// w det J and ∇N_a at every quadrature point (any Tet10).
    Gradients,
    /// J⁻¹ and the element's w det J; straight-sided Tet10 only.
    Jacobians,
}

/// The element data of one [`MatrixFreeGeometry`].
#[derive(Debug, Clone)]
enum Geometry {
    /// Per quadrature point: (w det J, ∇N_a); `offsets[e]..offsets[e + 1]` are element e's.
    Gradients {
        points: Vec<(f64, [[f64; 3]; 10])>,
        offsets: Vec<usize>,
    },
    /// Per element: J⁻¹ (row-major) and w det J of each of the 4 equal-weight points.
    Jacobians {
        inverse: Vec<[f64; 9]>,
        weight: Vec<f64>,
        reference: Box<[[[f64; 3]; 10]; 4]>,
    },
}

/// K x of a Tet10 model without assembling K.
#[derive(Debug, Clone)]
pub struct MatrixFreeStiffness {
    elements: Vec<[u32; 10]>,
    laws: Vec<Constitutive>,
    law_of: Vec<u32>,
    geometry: Geometry,
    dofs: usize,
}

impl MatrixFreeStiffness {
    /// Prepares the element data of `model` (Tet10 only; `Jacobians` refuses curved elements).
    pub fn new(model: &Model, geometry: MatrixFreeGeometry) -> FemResult<Self> {
        let unsupported = |reason: String| FemError::IterativeUnsupported { reason };
        let Connectivity::Tet10(tets) = model.connectivity() else {
            return Err(unsupported(
                "the matrix-free product is for Tet10 meshes".into(),
            ));
        };
        let n_elements = tets.len();
        let mut laws: Vec<Constitutive> = Vec::new();
        let mut law_of = Vec::with_capacity(n_elements);
        let mut elements = Vec::with_capacity(n_elements);
        for e in 0..n_elements {
            let law = model.constitutive_of(e);
            let index = laws.iter().position(|l| l == law).unwrap_or_else(|| {
                laws.push(*law);
                laws.len() - 1
            });
            law_of.push(index as u32);
            elements.push(tets[e].map(|n| n as u32));
        }
        let geometry = match geometry {
            MatrixFreeGeometry::Gradients => gradients_of(model, tets)?,
            MatrixFreeGeometry::Jacobians => jacobians_of(model, tets).map_err(unsupported)?,
        };
        Ok(Self {
            elements,
            laws,
            law_of,
            geometry,
            dofs: model.dof_count(),
        })
    }

    /// Number of unknowns (3 per node).
    pub fn dim(&self) -> usize {
        self.dofs
    }

    /// Bytes held for the products (connectivity, law indices, geometry).
    pub fn memory_bytes(&self) -> usize {
        let geometry = match &self.geometry {
            Geometry::Gradients { points, offsets } => {
                points.len() * std::mem::size_of::<(f64, [[f64; 3]; 10])>() + offsets.len() * 8
            }
            Geometry::Jacobians {
                inverse, weight, ..
            } => inverse.len() * 72 + weight.len() * 8,
        };
        self.elements.len() * 40 + self.law_of.len() * 4 + geometry
    }

    /// y ← K x (`x`, `y` of length [`Self::dim`]).
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(x.len(), self.dofs, "matrix-free product: x length");
        assert_eq!(y.len(), self.dofs, "matrix-free product: y length");
        y.fill(0.0);
        for (e, nodes) in self.elements.iter().enumerate() {
            let u: [[f64; 3]; 10] = std::array::from_fn(|a| {
                let d = 3 * nodes[a] as usize;
                [x[d], x[d + 1], x[d + 2]]
            });
            let law = &self.laws[self.law_of[e] as usize];
            let ye = match &self.geometry {
                Geometry::Gradients { points, offsets } => {
                    element_product(&u, &points[offsets[e]..offsets[e + 1]], law)
                }
                Geometry::Jacobians {
                    inverse,
                    weight,
                    reference,
                } => element_product_reference(&u, &inverse[e], weight[e], reference, law),
            };
            for (a, &n) in nodes.iter().enumerate() {
                let d = 3 * n as usize;
                for i in 0..3 {
                    y[d + i] += ye[a][i];
                }
            }
        }
    }
}

/// (w det J, ∇N_a) at every stiffness quadrature point of every element.
fn gradients_of(model: &Model, tets: &[[usize; 10]]) -> FemResult<Geometry> {
    let mut points = Vec::new();
    let mut offsets = vec![0];
    for (e, tet) in tets.iter().enumerate() {
        let coords = model.element_coords(tet);
        let rule = tet10_stiffness_rule(&coords);
        for (xi, w) in rule.points.iter().zip(&rule.weights) {
            let (g, det) =
                physical_gradients::<10, Tet10>(&coords, *xi).ok_or(FemError::InvertedElement {
                    element: e,
                    det_jacobian: f64::NAN,
                    reference_point: *xi,
                })?;
            points.push((w * det, g));
        }
        offsets.push(points.len());
    }
    Ok(Geometry::Gradients { points, offsets })
}

/// J⁻¹ and w det J per straight-sided element; the reference gradients at the 4 points.
fn jacobians_of(model: &Model, tets: &[[usize; 10]]) -> Result<Geometry, String> {
    let rule = tet_degree2();
    let reference: [[[f64; 3]; 10]; 4] =
        std::array::from_fn(|q| Tet10::reference_gradients(rule.points[q]));
    let w = rule.weights[0];
    if rule.weights.iter().any(|&wq| wq != w) {
        return Err("the 4-point rule's weights differ (Jacobians needs equal weights)".into());
    }
    let mut inverse = Vec::with_capacity(tets.len());
    let mut weight = Vec::with_capacity(tets.len());
    for (e, tet) in tets.iter().enumerate() {
        if model.is_curved(e) {
            return Err(format!(
                "element {e} is curved: matrix-free `Jacobians` needs straight-sided Tet10 \
                 (use `Gradients`)"
            ));
        }
        let coords = model.element_coords(tet);
        let v = |a: usize| nalgebra::Vector3::from(coords[a]);
        let j = Matrix3::from_columns(&[v(1) - v(0), v(2) - v(0), v(3) - v(0)]);
        let inv = j
            .try_inverse()
            .ok_or_else(|| format!("element {e}: singular Jacobian"))?;
        inverse.push(std::array::from_fn(|k| inv[(k / 3, k % 3)]));
        weight.push(w * j.determinant());
    }
    Ok(Geometry::Jacobians {
        inverse,
        weight,
        reference: Box::new(reference),
    })
}

/// σ = C : sym(H) for the displacement gradient H (h[i][j] = ∂u_i/∂x_j).
fn stress(h: &[[f64; 3]; 3], law: &Constitutive) -> [[f64; 3]; 3] {
    match law {
        Constitutive::Isotropic(l) => {
            let trace = h[0][0] + h[1][1] + h[2][2];
            std::array::from_fn(|i| {
                std::array::from_fn(|j| {
                    let shear = l.mu * (h[i][j] + h[j][i]);
                    if i == j {
                        shear + l.lambda * trace
                    } else {
                        shear
                    }
                })
            })
        }
        Constitutive::Anisotropic(c) => {
            let eps = voigt_strain(h);
            let s: [f64; 6] = std::array::from_fn(|p| (0..6).map(|q| c[(p, q)] * eps[q]).sum());
            [[s[0], s[5], s[4]], [s[5], s[1], s[3]], [s[4], s[3], s[2]]]
        }
    }
}

/// K_e u of one element from its (w det J, ∇N_a) points.
fn element_product(
    u: &[[f64; 3]; 10],
    points: &[(f64, [[f64; 3]; 10])],
    law: &Constitutive,
) -> [[f64; 3]; 10] {
    let mut y = [[0.0; 3]; 10];
    for (wdet, g) in points {
        let h = displacement_gradient(u, g);
        let s = stress(&h, law);
        for (ya, ga) in y.iter_mut().zip(g) {
            for i in 0..3 {
                ya[i] += wdet * (s[i][0] * ga[0] + s[i][1] * ga[1] + s[i][2] * ga[2]);
            }
        }
    }
    y
}

/// K_e u of one straight-sided element from J⁻¹, w det J and the reference gradients.
fn element_product_reference(
    u: &[[f64; 3]; 10],
    inverse: &[f64; 9],
    wdet: f64,
    reference: &[[[f64; 3]; 10]; 4],
    law: &Constitutive,
) -> [[f64; 3]; 10] {
    let jinv = |k: usize, j: usize| inverse[3 * k + j];
    let mut y = [[0.0; 3]; 10];
    for r in reference {
        let hr = displacement_gradient(u, r);
        // H = H_ξ J⁻¹: ∂u_i/∂x_j = Σ_k H_ξ[i][k] (J⁻¹)_kj.
        let h: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..3).map(|k| hr[i][k] * jinv(k, j)).sum())
        });
        let s = stress(&h, law);
        // M = w det J σ J⁻ᵀ: M_ik = w det J Σ_j σ_ij (J⁻¹)_kj; y_a += M ∇_ξ N_a.
        let m: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|k| wdet * (0..3).map(|j| s[i][j] * jinv(k, j)).sum::<f64>())
        });
        for (ya, ra) in y.iter_mut().zip(r) {
            for i in 0..3 {
                ya[i] += m[i][0] * ra[0] + m[i][1] * ra[1] + m[i][2] * ra[2];
            }
        }
    }
    y
}
