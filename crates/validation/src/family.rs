//! Mesh families of the punch convergence study.
//!
//! `punch.geo` grades the element size linearly from the punch edge: h(d) = h_e + g·d (d the
//! distance to the edge circle). The stiffness error has two parts (measured, see the README):
//! - the edge core, where elements have size h_e, carries an energy error ∝ h_e (the
//!   d^(−1/2) stress singularity caps the local order at 1 for Tet4 and Tet10 alike);
//! - the graded region carries an error ∝ g^(2p) (p = element order).
//!
//! A level halves h_e and shrinks g by 2^(−1/(2p)), so that both parts fall ∝ h_e and the
//! sequence has the single leading order 1 in h_e (Richardson variable). The number of elements
//! grows ∝ 1/(g² h_e): × 2^(1 + 1/p) per level (× 2.8 Tet10, × 4 Tet4).

use serde::{Deserialize, Serialize};

use crate::mesh_cache::PunchMeshParameters;
use crate::punch_mesh::MeshSymmetry;

/// Decimal places kept for the growth factor (so that file names stay short; the growth is not
/// the Richardson variable, its rounding does not matter). Default 4.
pub const GROWTH_DECIMALS: i32 = 4;

/// A sequence of punch meshes refined together in h_e and g.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MeshFamily {
    /// Element order: 1 Tet4, 2 Tet10.
    pub order: u8,
    /// h_e / a on level 0.
    pub h_edge_over_a: f64,
    /// Growth g on level 0.
    pub growth: f64,
    /// Ratio h_e(ℓ) / h_e(ℓ + 1).
    pub refinement_ratio: f64,
    /// R / a.
    pub truncation_ratio: f64,
    /// Size cap / a (0: R/4).
    pub h_max_over_a: f64,
}

impl MeshFamily {
    /// Tet10 family of the springs study: h_e = 0.04 a, g = 0.3 on level 0, R = 100 a.
    pub fn tet10() -> Self {
        Self {
            order: 2,
            h_edge_over_a: 0.04,
            growth: 0.3,
            refinement_ratio: 2.0,
            truncation_ratio: 100.0,
            h_max_over_a: 0.0,
        }
    }

    /// Tet4 family for the work-precision comparison: h_e = 0.02 a, g = 0.3 on level 0, R = 100 a.
    pub fn tet4() -> Self {
        Self {
            order: 1,
            h_edge_over_a: 0.02,
            growth: 0.3,
            refinement_ratio: 2.0,
            truncation_ratio: 100.0,
            h_max_over_a: 0.0,
        }
    }

    /// h_e / a on `level`.
    pub fn h_edge(&self, level: usize) -> f64 {
        self.h_edge_over_a / self.refinement_ratio.powi(level as i32)
    }

    /// Growth g on `level`: g₀ · (h_e(ℓ)/h_e(0))^(1/(2p)), rounded to [`GROWTH_DECIMALS`].
    pub fn growth(&self, level: usize) -> f64 {
        let exponent = 1.0 / (2.0 * f64::from(self.order));
        let g = self.growth * (self.h_edge(level) / self.h_edge_over_a).powf(exponent);
        let scale = 10f64.powi(GROWTH_DECIMALS);
        (g * scale).round() / scale
    }

    /// gmsh parameters of `level` for punch radius `radius_m` and model part `symmetry`.
    pub fn parameters(
        &self,
        level: usize,
        radius_m: f64,
        symmetry: MeshSymmetry,
    ) -> PunchMeshParameters {
        self.with_truncation(level, radius_m, symmetry, self.truncation_ratio)
    }

    /// As [`Self::parameters`] with another R / a (truncation study).
    pub fn with_truncation(
        &self,
        level: usize,
        radius_m: f64,
        symmetry: MeshSymmetry,
        truncation_ratio: f64,
    ) -> PunchMeshParameters {
        PunchMeshParameters {
            radius_m,
            truncation_ratio,
            h_edge_over_a: self.h_edge(level),
            growth: self.growth(level),
            h_max_over_a: self.h_max_over_a,
            symmetry,
            order: self.order,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tet10_levels_halve_the_edge_size_and_shrink_growth_by_the_fourth_root_of_two() {
        let f = MeshFamily::tet10();
        assert_eq!(f.h_edge(2), 0.01, "edge size on level 2 (units of a)");
        assert_eq!(f.growth(1), 0.2523, "growth on level 1");
        assert_eq!(f.growth(2), 0.2121, "growth on level 2");
    }

    #[test]
    fn tet4_levels_shrink_growth_by_the_square_root_of_two() {
        let f = MeshFamily::tet4();
        assert_eq!(f.growth(2), 0.15, "growth on level 2");
    }
}
