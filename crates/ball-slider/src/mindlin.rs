//! Cattaneo–Mindlin partial slip of a Hertz contact under a tangential force Q at constant
//! normal force N, and the Mindlin–Deresiewicz hysteresis loop under an oscillating Q.
//!
//! Model (R. D. Mindlin, J. Appl. Mech. 16, 259 (1949); R. D. Mindlin & H. Deresiewicz,
//! J. Appl. Mech. 20, 327 (1953); K. L. Johnson, *Contact Mechanics*, 1985, §7.2 and §7.4):
//! * effective shear modulus 1/G* = (2 − ν₁)/G₁ + (2 − ν₂)/G₂ (both bodies);
//! * traction q(r) = μp₀√(1 − r²/a²) − (c/a) μp₀√(1 − r²/c²) (second term for r < c);
//! * stick radius c = a (1 − Q/μN)^{1/3};
//! * tangential compliance (rigid-body displacement of the stick zone)
//!   δ_t(Q) = 3μN/(16G*a) [1 − (1 − Q/μN)^{2/3}], initial stiffness 8G*a;
//! * Mindlin–Deresiewicz (Masing) rules for reversals at ±Q*: unloading from +Q*
//!   δ_U(Q) = δ_t(Q*) − 2δ_t((Q* − Q)/2), reloading from −Q* δ_L(Q) = −δ_U(−Q);
//! * energy dissipated per cycle of amplitude Q* (the area of the loop, ∮Q dδ_t):
//!   W = 9μ²N²/(10aG*) · {1 − (1 − q)^{5/3} − (5q/6)[1 + (1 − q)^{2/3}]}, q = Q*/μN.
//!   (For small q, W ≈ Q*³/(36 μN a G*), Mindlin's cubic law.) The bracket's last factor is
//!   1 **+** (1 − q)^{2/3}: with 1 − (1 − q)^{2/3} the loop energy would not vanish like q³ at
//!   small amplitude, and the test `loop_energy_matches_integral_of_q_d_delta_around_the_loop`
//!   (∮Q dδ by quadrature, 1e-8) fails for it.
//!
//! Equation numbers as recalled from the 1985 edition (not checked against a copy: every
//! expression is verified independently in the tests): c (7.41), δ_t (7.42), the loop
//! branches (7.58)–(7.59), W (7.60).
//!
//! Validity: as for [`crate::hertz`], plus a constant friction coefficient (static =
//! kinetic), constant N during the tangential loading, and uncoupled normal and tangential
//! problems (Dundurs β = 0; Goodman's approximation). Q → μN: c → 0, the tangent stiffness
//! → 0 and the contact slides (full slip); Q ≥ μN is refused.

use std::f64::consts::PI;

use contact_springs::Material;

use crate::error::{BallError, Result, positive};
use crate::hertz::HertzContact;

/// G* of both bodies: 1/G* = (2 − ν₁)/G₁ + (2 − ν₂)/G₂ (Pa).
pub fn effective_shear_modulus_pa(a: &Material, b: &Material) -> f64 {
    let term = |m: &Material| (2.0 - m.poisson_ratio) / m.shear_modulus_pa;
    1.0 / (term(a) + term(b))
}

/// A Hertz contact with Coulomb friction μ under tangential load.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct MindlinContact {
    /// The normal contact.
    pub hertz: HertzContact,
    /// Friction coefficient μ (> 0).
    pub friction_coefficient: f64,
    /// Effective shear modulus G* (Pa).
    pub effective_shear_modulus_pa: f64,
}

impl MindlinContact {
    /// The contact; refuses μ ≤ 0 and G* ≤ 0.
    pub fn new(hertz: HertzContact, friction_coefficient: f64, shear_pa: f64) -> Result<Self> {
        Ok(Self {
            hertz,
            friction_coefficient: positive("friction coefficient μ", friction_coefficient)?,
            effective_shear_modulus_pa: positive("effective shear modulus G* (Pa)", shear_pa)?,
        })
    }

    /// μN (N).
    pub fn friction_limit_n(&self) -> f64 {
        self.friction_coefficient * self.hertz.normal_force_n
    }

    /// Displacement scale 3μN/(16G*a) (m): δ_t at the onset of full slip.
    pub fn full_slip_displacement_m(&self) -> f64 {
        3.0 * self.friction_limit_n()
            / (16.0 * self.effective_shear_modulus_pa * self.hertz.contact_radius_m)
    }

    /// Initial tangential stiffness 8G*a (N/m).
    pub fn initial_tangential_stiffness_n_per_m(&self) -> f64 {
        8.0 * self.effective_shear_modulus_pa * self.hertz.contact_radius_m
    }

    fn ratio(&self, q_n: f64) -> Result<f64> {
        let limit = self.friction_limit_n();
        if !q_n.is_finite() || q_n.abs() >= limit {
            return Err(BallError::TangentialLoadBeyondFriction {
                load_n: q_n,
                limit_n: limit,
            });
        }
        Ok(q_n / limit)
    }

    /// Stick radius c = a(1 − |Q|/μN)^{1/3} (m).
    pub fn stick_radius_m(&self, q_n: f64) -> Result<f64> {
        let q = self.ratio(q_n)?.abs();
        Ok(self.hertz.contact_radius_m * (1.0 - q).cbrt())
    }

    /// Monotonic loading from zero: δ_t(Q) = 3μN/(16G*a)[1 − (1 − |Q|/μN)^{2/3}], odd in Q (m).
    /// Q = ±μN is accepted here (the full-slip displacement, its limit).
    pub fn compliance_m(&self, q_n: f64) -> Result<f64> {
        let limit = self.friction_limit_n();
        if !q_n.is_finite() || q_n.abs() > limit {
            return Err(BallError::TangentialLoadBeyondFriction {
                load_n: q_n,
                limit_n: limit,
            });
        }
        let q = (q_n / limit).abs();
        Ok(q_n.signum() * self.full_slip_displacement_m() * (1.0 - (1.0 - q).powf(2.0 / 3.0)))
    }

    /// Tangent stiffness dQ/dδ_t of the monotonic curve = 8G*a (1 − |Q|/μN)^{1/3} (N/m);
    /// zero at full slip.
    pub fn tangent_stiffness_n_per_m(&self, q_n: f64) -> Result<f64> {
        let q = (q_n / self.friction_limit_n()).abs();
        if !q_n.is_finite() || q > 1.0 {
            return Err(BallError::TangentialLoadBeyondFriction {
                load_n: q_n,
                limit_n: self.friction_limit_n(),
            });
        }
        Ok(self.initial_tangential_stiffness_n_per_m() * (1.0 - q).cbrt())
    }

    /// The Cattaneo traction q(r) at tangential load Q (Pa).
    pub fn traction_pa(&self, r_m: f64, q_n: f64) -> Result<f64> {
        let c = self.stick_radius_m(q_n)?;
        let a = self.hertz.contact_radius_m;
        let mu_p0 = self.friction_coefficient * self.hertz.peak_pressure_pa;
        let outer = (1.0 - (r_m / a).powi(2)).max(0.0).sqrt();
        let inner = (1.0 - (r_m / c).powi(2)).max(0.0).sqrt();
        Ok(q_n.signum() * mu_p0 * (outer - c / a * inner))
    }

    /// Unloading branch from +Q*: δ_U(Q) = δ_t(Q*) − 2δ_t((Q* − Q)/2), −Q* ≤ Q ≤ Q* (m).
    pub fn unloading_m(&self, q_star_n: f64, q_n: f64) -> Result<f64> {
        Ok(self.compliance_m(q_star_n)? - 2.0 * self.compliance_m(0.5 * (q_star_n - q_n))?)
    }

    /// Reloading branch from −Q*: δ_L(Q) = −δ_t(Q*) + 2δ_t((Q* + Q)/2) (m).
    pub fn reloading_m(&self, q_star_n: f64, q_n: f64) -> Result<f64> {
        Ok(-self.compliance_m(q_star_n)? + 2.0 * self.compliance_m(0.5 * (q_star_n + q_n))?)
    }

    /// Energy dissipated per cycle of ±Q* (J), Q* ≤ μN.
    pub fn loop_energy_j(&self, q_star_n: f64) -> Result<f64> {
        let limit = self.friction_limit_n();
        if !q_star_n.is_finite() || q_star_n < 0.0 || q_star_n > limit {
            return Err(BallError::TangentialLoadBeyondFriction {
                load_n: q_star_n,
                limit_n: limit,
            });
        }
        let q = q_star_n / limit;
        let s = 1.0 - q;
        let bracket = 1.0 - s.powf(5.0 / 3.0) - 5.0 * q / 6.0 * (1.0 + s.powf(2.0 / 3.0));
        let scale = 9.0 * limit * limit
            / (10.0 * self.hertz.contact_radius_m * self.effective_shear_modulus_pa);
        // For small q the bracket's terms cancel to O(q³): use its series
        // 5q³/162 · (1 + 2q/3 + 7q²/15 + O(q³)).
        if q < 1e-3 {
            return Ok(scale
                * (5.0 * q.powi(3) / 162.0)
                * (1.0 + 2.0 * q / 3.0 + 7.0 * q * q / 15.0));
        }
        Ok(scale * bracket)
    }

    /// Total tangential force ∫q dA of the traction distribution, 2π∫q r dr in closed form
    /// (= Q by construction; a consistency measure).
    pub fn traction_resultant_closed_form_n(&self, q_n: f64) -> Result<f64> {
        let c = self.stick_radius_m(q_n)?;
        let a = self.hertz.contact_radius_m;
        let mu_p0 = self.friction_coefficient * self.hertz.peak_pressure_pa;
        Ok(q_n.signum() * mu_p0 * 2.0 * PI / 3.0 * (a * a - c * c * c / a))
    }
}
