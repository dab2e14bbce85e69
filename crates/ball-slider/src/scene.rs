//! The input of the ball model, one field per scene key (SI), and its validation.
//!
//! Intended scene mapping (`slider.shape = "ball"`): `slider.ball_diameter` →
//! [`BallSlider::diameter_m`], `slider.material` (or `slider.ball_material`) →
//! [`BallSlider::material`], `slider.mass` → [`BallSlider::moving_mass_kg`] (absent: the ball's
//! own mass), `wave.*` → [`BallScene::wave`], `stator.material` → [`BallScene::stator`],
//! `friction.mu` → [`BallScene::friction_coefficient`] (μ_static must equal μ_kinetic),
//! `load.preload` → [`BallScene::preload_n`], `load.external` → [`BallScene::external_load_n`],
//! `model.ball.steps_per_period`, `model.curve_points` → [`Numerics`].

use std::f64::consts::PI;

use contact_springs::Material;
use motor::{Motor, Wave};
use serde::{Deserialize, Serialize};

use crate::dynamics::WaveShare;
use crate::error::{BallError, Result, material, non_negative, positive};

/// Young's modulus of the default ball steel (Pa): hardened bearing steel (AISI 52100 /
/// SUJ2, the steel of precision balls), handbook value 208–210 GPa. Default 210e9.
pub const STEEL_YOUNGS_MODULUS_PA: f64 = 210e9;
/// Poisson's ratio of the default ball steel. Default 0.30.
pub const STEEL_POISSON_RATIO: f64 = 0.30;
/// Density of the default ball steel (kg/m³); 52100 is 7810–7830. Default 7810.
pub const STEEL_DENSITY_KG_PER_M3: f64 = 7810.0;

/// Bearing steel (AISI 52100): E = 210 GPa, ν = 0.30, ρ = 7810 kg/m³ (G = 80.8 GPa).
/// `contact-springs` should own this next to silicon and LiNbO3.
pub fn bearing_steel() -> Material {
    Material {
        name: "steel".into(),
        shear_modulus_pa: STEEL_YOUNGS_MODULUS_PA / (2.0 * (1.0 + STEEL_POISSON_RATIO)),
        poisson_ratio: STEEL_POISSON_RATIO,
        density_kg_per_m3: STEEL_DENSITY_KG_PER_M3,
    }
}

/// The ball: its size, material and the mass that moves with it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BallSlider {
    /// Ball diameter d (m) (`slider.ball_diameter`).
    pub diameter_m: f64,
    /// Ball material (`slider.material`).
    pub material: Material,
    /// Moving mass (kg): a holder's mass plus the ball's; `None` is the ball's own ρπd³/6
    /// (`slider.mass`).
    #[serde(default)]
    pub moving_mass_kg: Option<f64>,
}

impl BallSlider {
    /// A steel ball of diameter d moving alone.
    pub fn steel(diameter_m: f64) -> Self {
        Self {
            diameter_m,
            material: bearing_steel(),
            moving_mass_kg: None,
        }
    }

    /// Radius d/2 (m).
    pub fn radius_m(&self) -> f64 {
        0.5 * self.diameter_m
    }

    /// The moving mass (kg): given, or ρπd³/6.
    pub fn mass_kg(&self) -> f64 {
        self.moving_mass_kg
            .unwrap_or_else(|| self.material.density_kg_per_m3 * PI * self.diameter_m.powi(3) / 6.0)
    }
}

/// Numerical settings (defaults in [`Numerics::default`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Numerics {
    /// Time steps per (Doppler-shifted) wave period; raised automatically where the
    /// ball–contact resonance needs it (ω_c Δt ≤ [`crate::dynamics::MAX_RESONANCE_STEP`]).
    pub steps_per_period: usize,
    /// Springs of the MDR bed over the largest contact radius.
    pub springs: usize,
    /// Points of the speed–thrust curve (stall to no load).
    pub curve_points: usize,
    /// Wave periods of the free-ball run that confirms each curve point (0: no confirmation).
    pub free_periods: usize,
    /// Relative speed drift between the two halves of the free run below which the point is
    /// steady.
    pub steady_tolerance: f64,
}

impl Default for Numerics {
    fn default() -> Self {
        Self {
            steps_per_period: 128,
            springs: 200,
            curve_points: 21,
            free_periods: 100,
            steady_tolerance: 1e-3,
        }
    }
}

/// A ball slider on the stator's Rayleigh wave.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BallScene {
    /// The stator's wave (stick-slip's and motor's `Wave`; continuous, no decay).
    pub wave: Wave,
    /// Stator material.
    pub stator: Material,
    /// The ball.
    pub ball: BallSlider,
    /// Coulomb friction coefficient μ ball–stator (static = kinetic, Mindlin's assumption).
    pub friction_coefficient: f64,
    /// Preload pressing the ball on the stator (N).
    pub preload_n: f64,
    /// External load opposing the drive (N).
    #[serde(default)]
    pub external_load_n: f64,
    /// Numerical settings.
    #[serde(default)]
    pub numerics: Numerics,
    /// The energy-conserving wave at the contact: the wave power crossing it (`None`: the
    /// constant amplitude A₀; [`crate::dynamics::attenuation`]).
    #[serde(default)]
    pub wave_share: Option<WaveShare>,
}

/// Ball diameter of the default scene (m): a 2 mm precision ball (crate README: why).
pub const DEFAULT_BALL_DIAMETER_M: f64 = 2e-3;
/// Preload of the default scene (N): where a smooth 2 mm ball on the 20 nm wave drives
/// (its static approach comparable to the wave amplitude; crate README).
pub const DEFAULT_PRELOAD_N: f64 = 0.02;

impl BallScene {
    /// The paper's wave, stator and μ with a steel ball of diameter d at preload P.
    pub fn paper_wave(diameter_m: f64, preload_n: f64) -> Self {
        let motor = Motor::paper();
        Self {
            wave: motor.wave,
            stator: motor.stator,
            ball: BallSlider::steel(diameter_m),
            friction_coefficient: motor.friction.mu_static,
            preload_n,
            external_load_n: 0.0,
            numerics: Numerics::default(),
            wave_share: None,
        }
    }

    /// The default study scene: 2 mm steel ball, 20 mN, the paper's wave.
    pub fn default_ball() -> Self {
        Self::paper_wave(DEFAULT_BALL_DIAMETER_M, DEFAULT_PRELOAD_N)
    }

    /// The motor's wave, stator, friction and load with this ball as its slider. Refuses a
    /// motor whose static and kinetic friction differ (Mindlin's theory has one μ).
    pub fn for_motor(motor: &Motor, ball: BallSlider) -> Result<Self> {
        if motor.friction.mu_static != motor.friction.mu_kinetic {
            return Err(BallError::InvalidParameter {
                field: "friction.mu_kinetic",
                value: motor.friction.mu_kinetic,
                requirement: "must equal friction.mu_static for the ball (Mindlin's theory has one μ)",
            });
        }
        let scene = Self {
            wave: motor.wave.clone(),
            stator: motor.stator.clone(),
            ball,
            friction_coefficient: motor.friction.mu_static,
            preload_n: motor.load.preload_n,
            external_load_n: motor.load.external_load_n,
            numerics: Numerics::default(),
            wave_share: None,
        };
        scene.validate()?;
        Ok(scene)
    }

    /// The same scene at another wave amplitude, A_t/A_n kept (the wave share too).
    pub fn with_normal_amplitude(mut self, amplitude_m: f64) -> Self {
        let ratio = self.wave.tangential_amplitude_m / self.wave.normal_amplitude_m;
        self.wave.normal_amplitude_m = amplitude_m;
        self.wave.tangential_amplitude_m = ratio * amplitude_m;
        self
    }

    /// Refuse bad input, naming the field.
    pub fn validate(&self) -> Result<()> {
        positive("ball.diameter_m", self.ball.diameter_m)?;
        material("ball.material", &self.ball.material)?;
        if let Some(m) = self.ball.moving_mass_kg {
            positive("ball.moving_mass_kg", m)?;
        }
        material("stator", &self.stator)?;
        positive("friction_coefficient", self.friction_coefficient)?;
        positive("preload_n", self.preload_n)?;
        non_negative("external_load_n", self.external_load_n)?;
        self.validate_wave()?;
        self.validate_numerics()
    }

    fn validate_wave(&self) -> Result<()> {
        let w = &self.wave;
        positive("wave.frequency_hz", w.frequency_hz)?;
        positive("wave.normal_amplitude_m", w.normal_amplitude_m)?;
        non_negative("wave.tangential_amplitude_m", w.tangential_amplitude_m)?;
        positive("wave.phase_velocity_m_per_s", w.phase_velocity_m_per_s)?;
        if w.decay_length_m.is_some() {
            return Err(BallError::UnsupportedWave {
                field: "wave.decay_length_m",
                reason: "the ball model takes a wave of constant amplitude (one contact point)",
            });
        }
        if w.burst_periods.is_some() {
            return Err(BallError::UnsupportedWave {
                field: "wave.burst_periods",
                reason: "the ball model computes the periodic steady state of a continuous wave",
            });
        }
        if let Some(share) = &self.wave_share {
            positive("wave_share.power_in_w", share.power_in_w)?;
            if !(share.tolerance > 0.0 && share.tolerance < 1e-2) {
                return Err(BallError::InvalidParameter {
                    field: "wave_share.tolerance",
                    value: share.tolerance,
                    requirement: "must lie in (0, 1e-2)",
                });
            }
        }
        Ok(())
    }

    fn validate_numerics(&self) -> Result<()> {
        let n = &self.numerics;
        if n.steps_per_period < 8 {
            return Err(BallError::InvalidParameter {
                field: "numerics.steps_per_period",
                value: n.steps_per_period as f64,
                requirement: "must be at least 8",
            });
        }
        if n.springs < 4 {
            return Err(BallError::InvalidParameter {
                field: "numerics.springs",
                value: n.springs as f64,
                requirement: "must be at least 4",
            });
        }
        if n.curve_points < 2 {
            return Err(BallError::InvalidParameter {
                field: "numerics.curve_points",
                value: n.curve_points as f64,
                requirement: "must be at least 2",
            });
        }
        positive("numerics.steady_tolerance", n.steady_tolerance)?;
        Ok(())
    }
}
