//! Element kernels: geometry checks, stiffness matrices, strains.
//!
//! Kernels write into caller-supplied fixed-size nalgebra buffers (`SMatrix<f64, 12, 12>` for
//! Tet4, `SMatrix<f64, 30, 30>` for Tet10). Element DOFs are ordered node by node:
//! `[u0x, u0y, u0z, u1x, …]`.

use nalgebra::{Matrix3, SMatrix, Vector3};

use crate::material::{LameParameters, Material, VoigtStiffness};
use crate::quadrature::{TetRule, tet_degree1, tet_degree2, tet_degree5};
use crate::shape::{TET10_EDGES, Tet4, Tet10, TetShape};

/// Smallest admissible shape quality (see [`shape_quality`]) of an element's vertex
/// tetrahedron; below it the element is rejected as degenerate. Dimensionless; default 1e-8.
pub const MIN_SHAPE_QUALITY: f64 = 1e-8;

/// Shape quality below which an element is flagged as poorly shaped (sliver, needle) in a
/// [`crate::model::QualityReport`] but still accepted. Dimensionless; default 0.05.
pub const POOR_SHAPE_QUALITY: f64 = 0.05;

/// Relative distance (to the edge length) from the edge midpoint beyond which a Tet10
/// mid-edge node makes the element "curved" and selects the degree-5 quadrature rule.
/// Dimensionless; default 1e-10.
pub const CURVED_EDGE_TOLERANCE: f64 = 1e-10;

/// Constitutive law prepared for the kernels (avoids re-rotating anisotropic tensors).
/// One value per material, so the size difference of the variants does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Constitutive {
    /// Isotropic: uses the closed-form Lamé kernel.
    Isotropic(LameParameters),
    /// General anisotropic Voigt stiffness (Pa).
    Anisotropic(VoigtStiffness),
}

impl Constitutive {
    /// The Voigt stiffness (Pa).
    pub fn voigt_stiffness(&self) -> VoigtStiffness {
        match self {
            Constitutive::Isotropic(l) => l.voigt_stiffness(),
            Constitutive::Anisotropic(c) => *c,
        }
    }
}

impl From<&Material> for Constitutive {
    fn from(value: &Material) -> Self {
        match value {
            Material::Isotropic(l) => Constitutive::Isotropic(*l),
            Material::Cubic(c) => Constitutive::Anisotropic(c.voigt_stiffness()),
        }
    }
}

/// Why an element's geometry was rejected (the caller adds the element index).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GeometryDefect {
    /// det J < 0 at `reference_point`.
    Inverted {
        /// Jacobian determinant found.
        det_jacobian: f64,
        /// Where.
        reference_point: [f64; 3],
    },
    /// Shape quality below [`MIN_SHAPE_QUALITY`] (or det J = 0).
    Degenerate {
        /// Quality of the vertex tetrahedron.
        quality: f64,
    },
}

/// Signed shape quality of a tetrahedron: q = 6√2 V / ℓ_rms³, with V the signed volume and
/// ℓ_rms the root-mean-square edge length. q = 1 for the regular tetrahedron, → 0 for slivers
/// and needles, negative when inverted.
pub fn shape_quality(v: &[[f64; 3]; 4]) -> f64 {
    let p: Vec<Vector3<f64>> = v.iter().map(|x| Vector3::from(*x)).collect();
    let volume = (p[1] - p[0]).cross(&(p[2] - p[0])).dot(&(p[3] - p[0])) / 6.0;
    let mut sum_sq = 0.0;
    for i in 0..4 {
        for j in (i + 1)..4 {
            sum_sq += (p[i] - p[j]).norm_squared();
        }
    }
    let l_rms = (sum_sq / 6.0).sqrt();
    if l_rms == 0.0 {
        return 0.0;
    }
    6.0 * std::f64::consts::SQRT_2 * volume / l_rms.powi(3)
}

/// Jacobian J_ij = ∂x_i/∂ξ_j = Σ_a x_a,i ∂N_a/∂ξ_j.
fn jacobian<const N: usize>(coords: &[[f64; 3]; N], dref: &[[f64; 3]; N]) -> Matrix3<f64> {
    let mut j = Matrix3::zeros();
    for a in 0..N {
        for r in 0..3 {
            for c in 0..3 {
                j[(r, c)] += coords[a][r] * dref[a][c];
            }
        }
    }
    j
}

/// Whether all Tet10 mid-edge nodes sit at their edge midpoints (within
/// [`CURVED_EDGE_TOLERANCE`] relative to the edge length).
pub fn is_straight_sided(coords: &[[f64; 3]; 10]) -> bool {
    TET10_EDGES.iter().enumerate().all(|(k, &(a, b))| {
        let xa = Vector3::from(coords[a]);
        let xb = Vector3::from(coords[b]);
        let mid = 0.5 * (xa + xb);
        (Vector3::from(coords[4 + k]) - mid).norm() <= CURVED_EDGE_TOLERANCE * (xb - xa).norm()
    })
}

/// Stiffness quadrature for a Tet10: the exact 4-point rule when straight-sided, the 14-point
/// degree-5 rule when curved.
pub fn tet10_stiffness_rule(coords: &[[f64; 3]; 10]) -> &'static TetRule {
    if is_straight_sided(coords) {
        tet_degree2()
    } else {
        tet_degree5()
    }
}

/// Checks the geometry of an `N`-node element: vertex-tetrahedron quality, then (for curved
/// Tet10) det J > 0 at the stiffness quadrature points, vertices and mid-edge nodes.
pub fn check_geometry<const N: usize, S: TetShape<N>>(
    coords: &[[f64; 3]; N],
    curved: bool,
) -> Result<f64, GeometryDefect> {
    let vertices = [coords[0], coords[1], coords[2], coords[3]];
    let q = shape_quality(&vertices);
    if q.abs() < MIN_SHAPE_QUALITY || !q.is_finite() {
        return Err(GeometryDefect::Degenerate { quality: q });
    }
    if q < 0.0 {
        let dref = S::reference_gradients([0.25; 3]);
        return Err(GeometryDefect::Inverted {
            det_jacobian: jacobian(coords, &dref).determinant(),
            reference_point: [0.25; 3],
        });
    }
    if curved {
        let nodes = S::reference_nodes();
        for xi in tet_degree5().points.iter().chain(nodes.iter()) {
            let det = jacobian(coords, &S::reference_gradients(*xi)).determinant();
            if det <= 0.0 {
                return Err(GeometryDefect::Inverted {
                    det_jacobian: det,
                    reference_point: *xi,
                });
            }
        }
    }
    Ok(q)
}

/// Physical shape-function gradients ∇N_a = J⁻ᵀ ∂N_a/∂ξ and det J at reference point `xi`.
/// Returns `None` when det J ≤ 0.
pub fn physical_gradients<const N: usize, S: TetShape<N>>(
    coords: &[[f64; 3]; N],
    xi: [f64; 3],
) -> Option<([[f64; 3]; N], f64)> {
    let dref = S::reference_gradients(xi);
    let j = jacobian(coords, &dref);
    let det = j.determinant();
    if det <= 0.0 || !det.is_finite() {
        return None;
    }
    let jinv_t = j.try_inverse()?.transpose();
    let mut g = [[0.0; 3]; N];
    for a in 0..N {
        let v = jinv_t * Vector3::from(dref[a]);
        g[a] = [v[0], v[1], v[2]];
    }
    Some((g, det))
}

/// Adds `weight · Bᵀ C B` for the gradients `g` into `out` (upper and lower parts).
fn add_point_stiffness<const N: usize, const D: usize>(
    out: &mut SMatrix<f64, D, D>,
    g: &[[f64; 3]; N],
    law: &Constitutive,
    weight: f64,
) {
    match law {
        Constitutive::Isotropic(LameParameters { mu, lambda }) => {
            // K_ab,ij = λ g_a,i g_b,j + μ g_a,j g_b,i + μ δ_ij (g_a · g_b).
            for a in 0..N {
                for b in a..N {
                    let ga = &g[a];
                    let gb = &g[b];
                    let dot = ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2];
                    for i in 0..3 {
                        for j in 0..3 {
                            let mut v = lambda * ga[i] * gb[j] + mu * ga[j] * gb[i];
                            if i == j {
                                v += mu * dot;
                            }
                            out[(3 * a + i, 3 * b + j)] += weight * v;
                        }
                    }
                }
            }
        }
        Constitutive::Anisotropic(c) => add_anisotropic_point_stiffness(out, g, c, weight),
    }
}

/// Rows of the Voigt strain (xx, yy, zz, yz, xz, xy; engineering shear) that displacement
/// component i of a node feeds, with the gradient component multiplying it: B_a(p, i) = g_a[k]
/// for (p, k) in `VOIGT_NONZEROS[i]`, zero elsewhere (3 of 6 rows per column).
const VOIGT_NONZEROS: [[(usize, usize); 3]; 3] = [
    [(0, 0), (4, 2), (5, 1)],
    [(1, 1), (3, 2), (5, 0)],
    [(2, 2), (3, 1), (4, 0)],
];

/// Anisotropic kernel: K_ab = w B_aᵀ (C B_b) using B's sparsity (3 nonzeros per column):
/// C B_b is 6×3 from 3 columns of C each (54 multiply-adds per node), then each 3×3 block
/// takes 27 (against 108 + 54 for dense 6×6·6×3 and 3×6·6×3 products).
fn add_anisotropic_point_stiffness<const N: usize, const D: usize>(
    out: &mut SMatrix<f64, D, D>,
    g: &[[f64; 3]; N],
    c: &VoigtStiffness,
    weight: f64,
) {
    // cb[b][j][p] = w (C B_b)(p, j).
    let cb: [[[f64; 6]; 3]; N] = std::array::from_fn(|b| {
        std::array::from_fn(|j| {
            let [(p0, k0), (p1, k1), (p2, k2)] = VOIGT_NONZEROS[j];
            let (v0, v1, v2) = (weight * g[b][k0], weight * g[b][k1], weight * g[b][k2]);
            std::array::from_fn(|p| c[(p, p0)] * v0 + c[(p, p1)] * v1 + c[(p, p2)] * v2)
        })
    });
    for b in 0..N {
        for a in 0..=b {
            for (i, nonzeros) in VOIGT_NONZEROS.iter().enumerate() {
                let [(p0, k0), (p1, k1), (p2, k2)] = *nonzeros;
                let (u0, u1, u2) = (g[a][k0], g[a][k1], g[a][k2]);
                for j in 0..3 {
                    let col = &cb[b][j];
                    out[(3 * a + i, 3 * b + j)] += u0 * col[p0] + u1 * col[p1] + u2 * col[p2];
                }
            }
        }
    }
}

/// Element stiffness K_e = Σ_q w_q det J_q Bᵀ C B of an `N`-node tetrahedron (`D = 3N`),
/// written into `out` (overwritten). Fails if det J ≤ 0 at a quadrature point.
pub fn assemble_element_matrix_into<const N: usize, const D: usize, S: TetShape<N>>(
    out: &mut SMatrix<f64, D, D>,
    coords: &[[f64; 3]; N],
    law: &Constitutive,
    rule: &TetRule,
) -> Result<(), GeometryDefect> {
    assert!(
        D == 3 * N,
        "element matrix size D = {D} must equal 3 × nodes = {}",
        3 * N
    );
    out.fill(0.0);
    for (xi, w) in rule.points.iter().zip(&rule.weights) {
        let Some((g, det)) = physical_gradients::<N, S>(coords, *xi) else {
            let det = jacobian(coords, &S::reference_gradients(*xi)).determinant();
            return Err(GeometryDefect::Inverted {
                det_jacobian: det,
                reference_point: *xi,
            });
        };
        add_point_stiffness(out, &g, law, w * det);
    }
    // Mirror the upper triangle (the kernels fill a ≤ b node blocks only).
    for c in 0..D {
        for r in (c + 1)..D {
            out[(r, c)] = out[(c, r)];
        }
    }
    Ok(())
}

/// Tet4 stiffness (12×12) with the exact 1-point rule.
pub fn tet4_stiffness_into(
    out: &mut SMatrix<f64, 12, 12>,
    coords: &[[f64; 3]; 4],
    law: &Constitutive,
) -> Result<(), GeometryDefect> {
    assemble_element_matrix_into::<4, 12, Tet4>(out, coords, law, tet_degree1())
}

/// Tet10 stiffness (30×30); rule chosen by [`tet10_stiffness_rule`].
pub fn tet10_stiffness_into(
    out: &mut SMatrix<f64, 30, 30>,
    coords: &[[f64; 3]; 10],
    law: &Constitutive,
) -> Result<(), GeometryDefect> {
    assemble_element_matrix_into::<10, 30, Tet10>(out, coords, law, tet10_stiffness_rule(coords))
}

/// Small strain (Voigt, engineering shear) of an element at reference point `xi`, from nodal
/// displacements `u` (m). `None` if det J ≤ 0 there.
pub fn element_strain<const N: usize, S: TetShape<N>>(
    coords: &[[f64; 3]; N],
    u: &[[f64; 3]; N],
    xi: [f64; 3],
) -> Option<[f64; 6]> {
    let (g, _) = physical_gradients::<N, S>(coords, xi)?;
    Some(voigt_strain(&displacement_gradient(u, &g)))
}

/// Displacement gradient H = Σ_a u_a ⊗ g_a (`h[i][j]` = ∂u_i/∂x_j) from nodal displacements `u`
/// and shape-function gradients `g` (physical, or reference for H_ξ).
pub fn displacement_gradient<const N: usize>(
    u: &[[f64; 3]; N],
    g: &[[f64; 3]; N],
) -> [[f64; 3]; 3] {
    let mut h = [[0.0; 3]; 3];
    for (ua, ga) in u.iter().zip(g) {
        for i in 0..3 {
            for j in 0..3 {
                h[i][j] += ua[i] * ga[j];
            }
        }
    }
    h
}

/// Small strain in Voigt order (xx, yy, zz, yz, xz, xy; engineering shear) of the displacement
/// gradient `h` (`h[i][j]` = ∂u_i/∂x_j).
pub fn voigt_strain(h: &[[f64; 3]; 3]) -> [f64; 6] {
    [
        h[0][0],
        h[1][1],
        h[2][2],
        h[1][2] + h[2][1],
        h[0][2] + h[2][0],
        h[0][1] + h[1][0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::CubicCrystal;

    fn distorted_tet10() -> [[f64; 3]; 10] {
        let v = [
            [0.1, 0.0, 0.05],
            [1.2, 0.1, 0.0],
            [0.2, 0.9, 0.1],
            [0.0, 0.2, 1.1],
        ];
        let mut x = [[0.0; 3]; 10];
        x[..4].copy_from_slice(&v);
        for (k, &(a, b)) in TET10_EDGES.iter().enumerate() {
            for j in 0..3 {
                x[4 + k][j] = 0.5 * (v[a][j] + v[b][j]);
            }
        }
        x
    }

    #[test]
    fn element_stiffness_is_symmetric_for_isotropic_and_rotated_cubic_material() {
        let x = distorted_tet10();
        let laws = [
            Constitutive::Isotropic(LameParameters::from_young_poisson(200e9, 0.3).unwrap()),
            Constitutive::from(&Material::Cubic(
                CubicCrystal::new(165.7e9, 63.9e9, 79.6e9, CubicCrystal::rotation_about_z(0.3))
                    .unwrap(),
            )),
        ];
        for law in laws {
            let mut k = SMatrix::<f64, 30, 30>::zeros();
            tet10_stiffness_into(&mut k, &x, &law).unwrap();
            let asym = (k - k.transpose()).amax() / k.amax();
            assert!(
                asym < 1e-14,
                "element stiffness asymmetry |K - K^T|/|K| = {asym}"
            );
        }
    }

    #[test]
    fn isotropic_fast_kernel_matches_general_voigt_kernel() {
        let x = distorted_tet10();
        let lame = LameParameters::from_young_poisson(70e9, 0.33).unwrap();
        let mut k_iso = SMatrix::<f64, 30, 30>::zeros();
        let mut k_gen = SMatrix::<f64, 30, 30>::zeros();
        tet10_stiffness_into(&mut k_iso, &x, &Constitutive::Isotropic(lame)).unwrap();
        tet10_stiffness_into(
            &mut k_gen,
            &x,
            &Constitutive::Anisotropic(lame.voigt_stiffness()),
        )
        .unwrap();
        let diff = (k_iso - k_gen).amax() / k_iso.amax();
        assert!(
            diff < 1e-13,
            "isotropic vs Voigt element stiffness relative difference = {diff}"
        );
    }

    #[test]
    fn geometry_check_flags_inverted_and_flat_tetrahedra() {
        let good = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        assert!(
            check_geometry::<4, Tet4>(&good, false).is_ok(),
            "reference tet must pass the geometry check"
        );
        let inverted = [good[1], good[0], good[2], good[3]];
        assert!(
            matches!(
                check_geometry::<4, Tet4>(&inverted, false),
                Err(GeometryDefect::Inverted { .. })
            ),
            "swapping two vertices must give an inverted element"
        );
        let flat = [good[0], good[1], good[2], [0.3, 0.3, 0.0]];
        assert!(
            matches!(
                check_geometry::<4, Tet4>(&flat, false),
                Err(GeometryDefect::Degenerate { .. })
            ),
            "a coplanar tet must be degenerate"
        );
        let regular = [
            [1.0, 1.0, 1.0],
            [1.0, -1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0],
        ];
        let q = shape_quality(&regular).abs();
        assert!(
            (q - 1.0).abs() < 1e-14,
            "shape quality of the regular tetrahedron = {q}, expected 1"
        );
    }
}
