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

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::mesh_cache::{MeshCache, PunchMeshParameters};
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

    /// h_e / a on a level between two of the sequence: ℓ = n + f (0 ≤ f < 1) gives
    /// h_e(n) / r^f, so that whole levels keep the bits of [`Self::h_edge`]. For meshes of a
    /// chosen size in the same family (the peer benchmark's ≥ 1M-unknown point is level 4.2).
    pub fn h_edge_between(&self, level: f64) -> f64 {
        let whole = level.floor();
        self.h_edge(whole as usize) / self.refinement_ratio.powf(level - whole)
    }

    /// Growth g on `level`: g₀ · (h_e(ℓ)/h_e(0))^(1/(2p)), rounded to [`GROWTH_DECIMALS`].
    pub fn growth(&self, level: usize) -> f64 {
        self.growth_for_edge(self.h_edge(level))
    }

    /// Growth g that goes with edge size `h_edge_over_a` in this family (same rule and rounding
    /// as [`Self::growth`]).
    fn growth_for_edge(&self, h_edge_over_a: f64) -> f64 {
        let exponent = 1.0 / (2.0 * f64::from(self.order));
        let g = self.growth * (h_edge_over_a / self.h_edge_over_a).powf(exponent);
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

    /// As [`Self::parameters`] on a level between two of the sequence ([`Self::h_edge_between`]);
    /// whole levels give the parameters of [`Self::parameters`]. `level` must be finite and ≥ 0.
    pub fn parameters_between(
        &self,
        level: f64,
        radius_m: f64,
        symmetry: MeshSymmetry,
    ) -> Result<PunchMeshParameters, String> {
        if !(level.is_finite() && level >= 0.0) {
            return Err(format!(
                "mesh family level must be a finite number ≥ 0, got {level}"
            ));
        }
        let h_edge_over_a = self.h_edge_between(level);
        Ok(PunchMeshParameters {
            h_edge_over_a,
            growth: self.growth_for_edge(h_edge_over_a),
            ..self.parameters(0, radius_m, symmetry)
        })
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

/// Punch radius a of the benchmark meshes (m): 10 µm.
pub const BENCHMARK_RADIUS_M: f64 = 10e-6;

/// The quarter Tet10 punch mesh (a = [`BENCHMARK_RADIUS_M`]) of `level` of [`MeshFamily::tet10`],
/// a whole level or one between two ("4.2"), from the default mesh cache (gmsh meshes it if it is
/// missing): the meshes of the peer benchmark (`scripts/compare-peers.sh`) and of the
/// `punch_scaling` and `punch_operator` examples. `level` is the command-line text.
pub fn benchmark_punch_mesh(level: &str) -> Result<PathBuf, String> {
    let value: f64 = level
        .parse()
        .map_err(|_| format!("--level: `{level}` is not a number"))?;
    let parameters =
        MeshFamily::tet10().parameters_between(value, BENCHMARK_RADIUS_M, MeshSymmetry::Quarter)?;
    MeshCache::default()
        .punch_mesh(&parameters)
        .map_err(|e| e.to_string())
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
    fn whole_levels_between_give_the_levels_and_a_fraction_lies_between_them() {
        let f = MeshFamily::tet10();
        for level in 0..6 {
            let between = f
                .parameters_between(level as f64, 10e-6, MeshSymmetry::Quarter)
                .unwrap();
            assert_eq!(
                between,
                f.parameters(level, 10e-6, MeshSymmetry::Quarter),
                "level {level}"
            );
        }
        let p = f
            .parameters_between(4.2, 10e-6, MeshSymmetry::Quarter)
            .unwrap();
        assert!(
            p.h_edge_over_a < f.h_edge(4) && p.h_edge_over_a > f.h_edge(5),
            "h_e of 4.2"
        );
        assert!(
            (p.h_edge_over_a - 0.0025 / 2f64.powf(0.2)).abs() < 1e-15,
            "h_e of 4.2"
        );
        assert!(
            p.growth < f.growth(4) && p.growth > f.growth(5),
            "growth of 4.2"
        );
        for bad in [-0.5, f64::NAN, f64::INFINITY] {
            assert!(
                f.parameters_between(bad, 10e-6, MeshSymmetry::Quarter)
                    .is_err(),
                "{bad}"
            );
        }
    }

    #[test]
    fn tet4_levels_shrink_growth_by_the_square_root_of_two() {
        let f = MeshFamily::tet4();
        assert_eq!(f.growth(2), 0.15, "growth on level 2");
    }
}
