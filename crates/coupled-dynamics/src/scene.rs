//! Input of the coupled model (SI).

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};
use stick_slip::Wave;

use crate::error::{CoupledError, Result};

/// Default nominal time steps per wave period (the step is ≤ T/steps). Default 256.
pub const DEFAULT_STEPS_PER_PERIOD: usize = 256;
/// Fewest steps per period accepted: the contact arc of a post must be resolved. Default 16.
pub const MIN_STEPS_PER_PERIOD: usize = 16;
/// Default curve points. Default 50.
pub const DEFAULT_CURVE_POINTS: usize = 50;

/// How the preload is balanced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum PreloadBalance {
    /// Σ N_i(t) = P at every instant; the rigid approach z(t) is an unknown of each step
    /// (the normal problem is static-contact's active-set solver).
    #[default]
    Instant,
    /// One constant approach with the period mean Σ⟨N_i⟩ = P: the lumped model's
    /// `period-mean` vertical model (used to compare with it).
    PeriodMean,
}

/// Direction in which the wave travels; the slider is driven the opposite way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum WaveDirection {
    /// θ = ωt − kx (docs/physics.md's convention): the slider moves along −x.
    #[default]
    PlusX,
    /// θ = ωt + kx, the mirrored wave: the slider moves along +x.
    MinusX,
}

impl WaveDirection {
    /// σ = +1 (along +x) or −1.
    pub fn sign(self) -> f64 {
        match self {
            Self::PlusX => 1.0,
            Self::MinusX => -1.0,
        }
    }
}

/// The coupled scene: the posts of the strip, their compliances, friction, wave, preload.
#[derive(Debug, Clone, PartialEq)]
pub struct CoupledScene {
    /// The travelling wave (continuous, no decay).
    pub wave: Wave,
    /// Post centres x (m), strip order.
    pub post_x_m: Vec<f64>,
    /// Normal tip compliance C_nn (m/N), SPD.
    pub normal_compliance_m_per_n: DMatrix<f64>,
    /// Tangential tip compliance C_tt (m/N), SPD. Normal–tangential cross terms are not part of
    /// the model (Goodman's approximation, see the crate docs).
    pub tangential_compliance_m_per_n: DMatrix<f64>,
    /// Static friction coefficient μ_s.
    pub mu_static: f64,
    /// Kinetic friction coefficient μ_k ≤ μ_s.
    pub mu_kinetic: f64,
    /// Preload of the whole slider (N).
    pub preload_n: f64,
    /// Direction of the wave.
    pub wave_direction: WaveDirection,
    /// Posts of the strip over posts of the slider (1: the strip is the slider). Forces of the
    /// slider = strip forces / share.
    pub strip_share: f64,
    /// Preload balance.
    pub preload_balance: PreloadBalance,
    /// Nominal steps per wave period (time step ≤ T/steps; shortened to divide the
    /// Doppler-shifted period).
    pub steps_per_period: usize,
    /// Phase of the reference point x = 0 at the first grid step (rad): the sampling grid.
    pub start_phase_rad: f64,
    /// Points of the speed–thrust curve.
    pub curve_points: usize,
    /// Natural-residual tolerance of each contact solve (relative). Default 1e-12.
    pub tolerance: f64,
    /// Local wave amplitude at each post over the scene's amplitude, A_i/A₀ (normal and
    /// tangential together, their ratio fixed), one per post in `post_x_m` order; empty: 1 at
    /// every post (the constant-amplitude wave). Set by the energy-conserving wave
    /// ([`crate::attenuation`]); the phase is unchanged (the wave velocity under the slider is
    /// assumed unchanged).
    pub amplitude_scale: Vec<f64>,
}

fn positive(parameter: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(CoupledError::InvalidParameter {
            parameter,
            value,
            requirement: "must be finite and > 0".into(),
        })
    }
}

fn spd(what: &'static str, m: &DMatrix<f64>, n: usize) -> Result<()> {
    if m.nrows() != n || m.ncols() != n {
        return Err(CoupledError::DimensionMismatch {
            what,
            expected: n,
            found: m.nrows().max(m.ncols()),
        });
    }
    let asym = (m - m.transpose()).amax();
    if !m.iter().all(|v| v.is_finite()) || asym > 1e-9 * m.amax() || m.clone().cholesky().is_none()
    {
        return Err(CoupledError::NotPositiveDefinite { what });
    }
    Ok(())
}

impl CoupledScene {
    /// Check every field; errors name it.
    pub fn validate(&self) -> Result<()> {
        self.validate_settings()?;
        let n = self.post_x_m.len();
        spd(
            "normal_compliance_m_per_n",
            &self.normal_compliance_m_per_n,
            n,
        )?;
        spd(
            "tangential_compliance_m_per_n",
            &self.tangential_compliance_m_per_n,
            n,
        )
    }

    /// Check every field but the dense compliances (the whole slider's model brings its own
    /// compliance operators, [`crate::slider`]); errors name the field.
    pub fn validate_settings(&self) -> Result<()> {
        let n = self.post_x_m.len();
        if n == 0 {
            return Err(CoupledError::DimensionMismatch {
                what: "post_x_m",
                expected: 1,
                found: 0,
            });
        }
        if let Some(x) = self.post_x_m.iter().find(|x| !x.is_finite()) {
            return Err(CoupledError::InvalidParameter {
                parameter: "post_x_m",
                value: *x,
                requirement: "must be finite".into(),
            });
        }
        self.validate_wave()?;
        self.validate_friction()?;
        self.validate_counts()?;
        self.validate_profile()
    }

    /// The wave: positive frequency, amplitude and velocity, a tangential amplitude ≥ 0, and
    /// continuous and undamped.
    fn validate_wave(&self) -> Result<()> {
        positive("wave.frequency_hz", self.wave.frequency_hz)?;
        positive("wave.normal_amplitude_m", self.wave.normal_amplitude_m)?;
        positive(
            "wave.phase_velocity_m_per_s",
            self.wave.phase_velocity_m_per_s,
        )?;
        if !(self.wave.tangential_amplitude_m.is_finite()
            && self.wave.tangential_amplitude_m >= 0.0)
        {
            return Err(CoupledError::InvalidParameter {
                parameter: "wave.tangential_amplitude_m",
                value: self.wave.tangential_amplitude_m,
                requirement: "must be finite and ≥ 0".into(),
            });
        }
        if self.wave.decay_length_m.is_some() || self.wave.burst_periods.is_some() {
            return Err(CoupledError::InvalidParameter {
                parameter: "wave.decay_length_m / wave.burst_periods",
                value: f64::NAN,
                requirement: "the coupled periodic steady state needs a continuous, undamped wave"
                    .into(),
            });
        }
        Ok(())
    }

    /// Preload, friction coefficients (μ_s ≥ μ_k > 0) and the strip's share.
    fn validate_friction(&self) -> Result<()> {
        positive("preload_n", self.preload_n)?;
        positive("mu_kinetic", self.mu_kinetic)?;
        if !(self.mu_static >= self.mu_kinetic && self.mu_static.is_finite()) {
            return Err(CoupledError::InvalidParameter {
                parameter: "mu_static",
                value: self.mu_static,
                requirement: format!("must be ≥ mu_kinetic = {}", self.mu_kinetic),
            });
        }
        if !(self.strip_share > 0.0 && self.strip_share <= 1.0) {
            return Err(CoupledError::InvalidParameter {
                parameter: "strip_share",
                value: self.strip_share,
                requirement: "must lie in (0, 1]".into(),
            });
        }
        Ok(())
    }

    /// Steps per period, curve points and the step tolerance.
    fn validate_counts(&self) -> Result<()> {
        if self.steps_per_period < MIN_STEPS_PER_PERIOD {
            return Err(CoupledError::InvalidParameter {
                parameter: "steps_per_period",
                value: self.steps_per_period as f64,
                requirement: format!(
                    "at least {MIN_STEPS_PER_PERIOD}: coarser steps do not resolve the contact events"
                ),
            });
        }
        if self.curve_points < 2 {
            return Err(CoupledError::InvalidParameter {
                parameter: "curve_points",
                value: self.curve_points as f64,
                requirement: "at least 2".into(),
            });
        }
        if !(self.tolerance > 0.0 && self.tolerance < 1e-3) {
            return Err(CoupledError::InvalidParameter {
                parameter: "tolerance",
                value: self.tolerance,
                requirement: "must lie in (0, 1e-3)".into(),
            });
        }
        Ok(())
    }

    /// The amplitude profile (one finite A_i/A₀ ≥ 0 per post, or none) and the start phase.
    fn validate_profile(&self) -> Result<()> {
        let n = self.post_x_m.len();
        if !self.amplitude_scale.is_empty() {
            if self.amplitude_scale.len() != n {
                return Err(CoupledError::DimensionMismatch {
                    what: "amplitude_scale",
                    expected: n,
                    found: self.amplitude_scale.len(),
                });
            }
            if let Some(a) = self
                .amplitude_scale
                .iter()
                .find(|a| !(a.is_finite() && **a >= 0.0))
            {
                return Err(CoupledError::InvalidParameter {
                    parameter: "amplitude_scale",
                    value: *a,
                    requirement: "must be finite and ≥ 0".into(),
                });
            }
        }
        if !self.start_phase_rad.is_finite() {
            return Err(CoupledError::InvalidParameter {
                parameter: "start_phase_rad",
                value: self.start_phase_rad,
                requirement: "must be finite".into(),
            });
        }
        Ok(())
    }

    /// The scene of the static stage's strip: its posts' x, the condensed normal and
    /// tangential tip compliances ([`static_contact::StripModel::tip_compliance`]: the same
    /// factorisation, no second FEM; cross terms dropped, see the crate docs), the strip's share
    /// of the slider (`StaticParams::strip_share`), and the wave, friction and preload of the
    /// dynamic scene; preload balanced at every instant, defaults otherwise. Errors: the tip
    /// compliance could not be formed (named by static-contact), or a field is invalid.
    pub fn from_strip(
        strip: &static_contact::StripModel,
        strip_share: f64,
        wave: Wave,
        mu_static: f64,
        mu_kinetic: f64,
        preload_n: f64,
    ) -> Result<Self> {
        let tips = strip.tip_compliance()?;
        let x = strip.posts.iter().map(|p| p.x_m).collect();
        let mut scene =
            Self::independent_posts(wave, x, 1.0, 1.0, mu_static, mu_kinetic, preload_n);
        scene.normal_compliance_m_per_n = tips.normal_m_per_n;
        scene.tangential_compliance_m_per_n = tips.tangential_m_per_n;
        scene.strip_share = strip_share;
        scene.validate()?;
        Ok(scene)
    }

    /// A scene of independent posts (diagonal compliances 1/k_n, 1/k_t): the lumped model's
    /// Jenkins posts.
    pub fn independent_posts(
        wave: Wave,
        post_x_m: Vec<f64>,
        k_n_n_per_m: f64,
        k_t_n_per_m: f64,
        mu_static: f64,
        mu_kinetic: f64,
        preload_n: f64,
    ) -> Self {
        let n = post_x_m.len();
        Self {
            wave,
            post_x_m,
            normal_compliance_m_per_n: DMatrix::identity(n, n) / k_n_n_per_m,
            tangential_compliance_m_per_n: DMatrix::identity(n, n) / k_t_n_per_m,
            mu_static,
            mu_kinetic,
            preload_n,
            wave_direction: WaveDirection::PlusX,
            strip_share: 1.0,
            preload_balance: PreloadBalance::Instant,
            steps_per_period: DEFAULT_STEPS_PER_PERIOD,
            start_phase_rad: 0.0,
            curve_points: DEFAULT_CURVE_POINTS,
            tolerance: 1e-12,
            amplitude_scale: Vec::new(),
        }
    }
}
