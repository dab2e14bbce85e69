//! One post's contact: series springs k_n, k_t (from Johnson's formulas, computed elsewhere),
//! static and kinetic friction, and an optional post mass (docs/physics.md §3, §5).

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use crate::error::{Result, StickSlipError, Warning, require_non_negative, require_positive};

/// Friction coefficient Si on LiNbO3 assumed by docs/physics.md §1 (dimensionless), from the
/// one copy of the paper's numbers in `motor::paper`.
pub use motor::paper::FRICTION_COEFFICIENT as PAPER_FRICTION_COEFFICIENT;

/// The contact of one post with the stator.
///
/// Normal: N = k_n ⟨w − z_s − g⟩₊. Tangential: a Jenkins element, spring k_t in series with a
/// Coulomb slider: sticking while |F| < μ_static N, sliding at |F| = μ_kinetic N.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PostContact {
    /// Normal contact stiffness of one post k_n = (1/k_pn + 1/k_sn)⁻¹ (N/m).
    pub k_n_n_per_m: f64,
    /// Tangential contact stiffness of one post k_t = (1/k_pt + 1/k_st)⁻¹ (N/m).
    pub k_t_n_per_m: f64,
    /// Static friction coefficient (stick holds while |F| < μ_s N).
    pub mu_static: f64,
    /// Kinetic friction coefficient (|F| = μ_k N while sliding), μ_k ≤ μ_s.
    pub mu_kinetic: f64,
    /// Mass of one post m_p = ρπa²h (kg); needed only by the `post-mass` and
    /// `regularized-explicit` integrators.
    #[serde(default)]
    pub post_mass_kg: Option<f64>,
}

impl PostContact {
    /// Massless posts with one friction coefficient μ = μ_s = μ_k.
    pub fn new(k_n_n_per_m: f64, k_t_n_per_m: f64, mu: f64) -> Self {
        Self {
            k_n_n_per_m,
            k_t_n_per_m,
            mu_static: mu,
            mu_kinetic: mu,
            post_mass_kg: None,
        }
    }

    /// The same contact with a post mass (kg).
    pub fn with_post_mass(mut self, post_mass_kg: f64) -> Self {
        self.post_mass_kg = Some(post_mass_kg);
        self
    }

    /// Mass of a cylindrical post, m_p = ρπa²h (kg).
    pub fn cylinder_mass_kg(density_kg_per_m3: f64, radius_m: f64, height_m: f64) -> f64 {
        density_kg_per_m3 * PI * radius_m * radius_m * height_m
    }

    /// Tangential resonance of the post mass on k_t, √(k_t/m_p)/2π (Hz), if a mass is set.
    pub fn tangential_resonance_hz(&self) -> Option<f64> {
        self.post_mass_kg
            .map(|m| (self.k_t_n_per_m / m).sqrt() / (2.0 * PI))
    }

    /// Normal resonance of the post mass on k_n, √(k_n/m_p)/2π (Hz), if a mass is set.
    pub fn normal_resonance_hz(&self) -> Option<f64> {
        self.post_mass_kg
            .map(|m| (self.k_n_n_per_m / m).sqrt() / (2.0 * PI))
    }

    /// Check the contact parameters.
    pub fn validate(&self) -> Result<Vec<Warning>> {
        let mut warnings = Vec::new();
        require_positive("contact.k_n_n_per_m", self.k_n_n_per_m)?;
        require_positive("contact.k_t_n_per_m", self.k_t_n_per_m)?;
        require_non_negative("contact.mu_static", self.mu_static)?;
        require_non_negative("contact.mu_kinetic", self.mu_kinetic)?;
        if self.mu_kinetic > self.mu_static {
            return Err(StickSlipError::InvalidParameter {
                parameter: "contact.mu_kinetic",
                value: self.mu_kinetic,
                requirement: format!("must not exceed contact.mu_static = {}", self.mu_static),
            });
        }
        if self.mu_static == 0.0 {
            warnings.push(Warning::new(
                "contact.mu_static",
                "zero friction: the motor produces no thrust",
            ));
        }
        if let Some(mass) = self.post_mass_kg {
            require_positive("contact.post_mass_kg", mass)?;
        }
        let ratio = self.k_t_n_per_m / self.k_n_n_per_m;
        if !(0.2..=5.0).contains(&ratio) {
            warnings.push(Warning::new(
                "contact.k_t_n_per_m",
                format!("k_t/k_n = {ratio:.3} is far from the elastic range 0.67–1 of a post on a half-space"),
            ));
        }
        Ok(warnings)
    }
}
