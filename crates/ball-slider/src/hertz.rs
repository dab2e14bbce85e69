//! Hertz contact of an elastic sphere on an elastic flat (frictionless, dissimilar bodies).
//!
//! Model (K. L. Johnson, *Contact Mechanics*, CUP 1985, §3.4 and §4.2; H. Hertz 1882):
//! * effective modulus 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂;
//! * contact radius a = (3 N R / 4E*)^{1/3}, approach δ = a²/R,
//!   N = (4/3) E* √R δ^{3/2};
//! * pressure p(r) = p₀ √(1 − r²/a²), p₀ = 3N/(2πa²) = 2aE*/(πR);
//! * normal stiffness k_n = dN/dδ = 2aE* = 3N/(2δ);
//! * stored elastic energy U(δ) = (8/15) E* √R δ^{5/2} (∫N dδ).
//!
//! Equation numbers as recalled from the 1985 edition (no copy was available to check them;
//! every expression is verified independently in the tests): E* (4.14), a (4.22), δ (4.23),
//! p₀ (4.24), the pressure distribution (3.39)–(4.21).
//!
//! Validity: linear elasticity with small strains (a ≪ R, here a/R ~ 10⁻²), both bodies
//! half-spaces near the contact (a ≪ the ball's radius and the stator's 1 mm thickness),
//! frictionless normal contact. For dissimilar bodies the normal pressure also drives
//! tangential surface displacements that differ between the bodies; Hertz theory (and the
//! Cattaneo–Mindlin theory built on it) neglects this coupling, which is measured by Dundurs'
//! second constant β ([`dundurs_beta`]): exact for β = 0. Steel on LiNbO3 gives β ≈ −0.063
//! (see the crate README for its consequence).

use contact_springs::Material;

use crate::error::{BallError, Result, positive};

/// E* from both bodies: 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ (Pa).
pub fn effective_modulus_pa(a: &Material, b: &Material) -> f64 {
    let term = |m: &Material| (1.0 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus_pa();
    1.0 / (term(a) + term(b))
}

/// Dundurs' second constant β = ½[(1−2ν₁)/G₁ − (1−2ν₂)/G₂] / [(1−ν₁)/G₁ + (1−ν₂)/G₂]
/// (Johnson 1985, eq. (5.4b) as recalled): the normal–tangential coupling Hertz and Mindlin
/// neglect. Zero for identical bodies or two incompressible ones.
pub fn dundurs_beta(a: &Material, b: &Material) -> f64 {
    let num = (1.0 - 2.0 * a.poisson_ratio) / a.shear_modulus_pa
        - (1.0 - 2.0 * b.poisson_ratio) / b.shear_modulus_pa;
    let den =
        (1.0 - a.poisson_ratio) / a.shear_modulus_pa + (1.0 - b.poisson_ratio) / b.shear_modulus_pa;
    0.5 * num / den
}

/// Normal force N(δ) = (4/3) E* √R δ^{3/2} (N); zero for δ ≤ 0 (contact lost).
pub fn force_at_approach_n(radius_m: f64, effective_modulus_pa: f64, approach_m: f64) -> f64 {
    if approach_m <= 0.0 {
        0.0
    } else {
        4.0 / 3.0 * effective_modulus_pa * radius_m.sqrt() * approach_m.powf(1.5)
    }
}

/// Elastic energy U(δ) = (8/15) E* √R δ^{5/2} (J); zero for δ ≤ 0.
pub fn energy_at_approach_j(radius_m: f64, effective_modulus_pa: f64, approach_m: f64) -> f64 {
    if approach_m <= 0.0 {
        0.0
    } else {
        8.0 / 15.0 * effective_modulus_pa * radius_m.sqrt() * approach_m.powf(2.5)
    }
}

/// The static Hertz contact of a sphere of radius R pressed with N on a flat.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct HertzContact {
    /// Sphere radius R (m).
    pub radius_m: f64,
    /// Effective modulus E* (Pa).
    pub effective_modulus_pa: f64,
    /// Normal force N (N).
    pub normal_force_n: f64,
    /// Contact radius a (m).
    pub contact_radius_m: f64,
    /// Approach (mutual indentation) δ = a²/R (m).
    pub approach_m: f64,
    /// Peak pressure p₀ = 3N/(2πa²) (Pa).
    pub peak_pressure_pa: f64,
    /// Normal stiffness k_n = 2aE* (N/m).
    pub normal_stiffness_n_per_m: f64,
}

impl HertzContact {
    /// The contact at normal force N; refuses non-positive or non-finite inputs.
    pub fn new(radius_m: f64, effective_modulus_pa: f64, normal_force_n: f64) -> Result<Self> {
        let r = positive("ball radius (m)", radius_m)?;
        let e = positive("effective modulus E* (Pa)", effective_modulus_pa)?;
        let n = positive("normal force (N)", normal_force_n)?;
        let a = (3.0 * n * r / (4.0 * e)).cbrt();
        Ok(Self {
            radius_m: r,
            effective_modulus_pa: e,
            normal_force_n: n,
            contact_radius_m: a,
            approach_m: a * a / r,
            peak_pressure_pa: 3.0 * n / (2.0 * std::f64::consts::PI * a * a),
            normal_stiffness_n_per_m: 2.0 * a * e,
        })
    }

    /// The contact at approach δ > 0.
    pub fn at_approach(radius_m: f64, effective_modulus_pa: f64, approach_m: f64) -> Result<Self> {
        let d = positive("approach (m)", approach_m)?;
        let n = force_at_approach_n(radius_m, effective_modulus_pa, d);
        if n <= 0.0 || !n.is_finite() {
            return Err(BallError::InvalidParameter {
                field: "approach (m)",
                value: d,
                requirement: "must give a finite positive force",
            });
        }
        Self::new(radius_m, effective_modulus_pa, n)
    }

    /// Pressure p(r) = p₀ √(1 − r²/a²) inside the contact, 0 outside (Pa).
    pub fn pressure_pa(&self, r_m: f64) -> f64 {
        let s = 1.0 - (r_m / self.contact_radius_m).powi(2);
        if s <= 0.0 {
            0.0
        } else {
            self.peak_pressure_pa * s.sqrt()
        }
    }

    /// Stored elastic energy (8/15) E* √R δ^{5/2} (J).
    pub fn energy_j(&self) -> f64 {
        energy_at_approach_j(self.radius_m, self.effective_modulus_pa, self.approach_m)
    }

    /// a/R: the small-strain measure (Hertz needs a ≪ R).
    pub fn strain_measure(&self) -> f64 {
        self.contact_radius_m / self.radius_m
    }
}
