//! The stator's surface wave (docs/physics.md §4): a Rayleigh wave travelling along +x with an
//! elliptical retrograde orbit, w = A_n sin θ, u = A_t cos θ, θ = ωt − kx.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use crate::error::{Result, StickSlipError, Warning, require_non_negative, require_positive};

/// The stator's wave: the motor's description (`motor::Wave`, docs/physics.md §4).
pub use motor::Wave;

/// Fastest bulk wave in LiNbO3 (longitudinal along the crystal Z axis ≈ 7.3 km/s, m/s). No
/// surface or pseudo-surface wave travels faster than the fastest bulk wave: above this the
/// input is refused. Default 7400.
pub const LINBO3_MAX_BULK_SPEED_M_PER_S: f64 = 7400.0;
/// Fastest bulk *shear* wave in LiNbO3 (≈ 4.8 km/s, m/s). A true Rayleigh wave is slower than
/// the slowest shear wave along its path; above this only leaky/longitudinal pseudo-SAWs exist,
/// which is warned about. Default 4800.
pub const LINBO3_MAX_SHEAR_SPEED_M_PER_S: f64 = 4800.0;
/// Largest surface strain k·max(A_n, A_t) accepted (dimensionless). Beyond ~1 % strain a
/// crystal is far outside linear elasticity (LiNbO3 fractures near 0.1–0.3 %). Default 1e-2.
pub const MAX_SURFACE_STRAIN: f64 = 1e-2;
/// Surface strain above which a warning is issued: SAW devices run at ≲ 1e-3 (the paper's
/// wave has 3·10⁻⁴). Default 2e-3.
pub const SURFACE_STRAIN_WARNING: f64 = 2e-3;

/// Bounds a wave must respect; defaults are LiNbO3 (the paper's stator).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WaveLimits {
    /// Refuse a phase velocity above this (m/s): the fastest bulk wave of the stator.
    pub max_phase_velocity_m_per_s: f64,
    /// Warn above this phase velocity (m/s): the fastest bulk shear wave.
    pub shear_speed_warning_m_per_s: f64,
    /// Refuse a surface strain k·max(A_n, A_t) above this.
    pub max_surface_strain: f64,
    /// Warn above this surface strain.
    pub surface_strain_warning: f64,
}

impl Default for WaveLimits {
    fn default() -> Self {
        Self {
            max_phase_velocity_m_per_s: LINBO3_MAX_BULK_SPEED_M_PER_S,
            shear_speed_warning_m_per_s: LINBO3_MAX_SHEAR_SPEED_M_PER_S,
            max_surface_strain: MAX_SURFACE_STRAIN,
            surface_strain_warning: SURFACE_STRAIN_WARNING,
        }
    }
}

/// Check `wave` against `limits`: typed errors for impossible values, warnings for allowed but
/// suspicious ones.
pub fn validate(wave: &Wave, limits: &WaveLimits) -> Result<Vec<Warning>> {
    let mut warnings = Vec::new();
    require_positive("wave.frequency_hz", wave.frequency_hz)?;
    require_positive("wave.normal_amplitude_m", wave.normal_amplitude_m)?;
    require_non_negative("wave.tangential_amplitude_m", wave.tangential_amplitude_m)?;
    require_positive("wave.phase_velocity_m_per_s", wave.phase_velocity_m_per_s)?;
    if let Some(decay) = wave.decay_length_m {
        require_positive("wave.decay_length_m", decay)?;
    }
    if let Some(burst) = wave.burst_periods {
        require_positive("wave.burst_periods", burst)?;
        if (burst - burst.round()).abs() > 1e-9 {
            warnings.push(Warning::new(
                "wave.burst_periods",
                format!("{burst} is not a whole number of periods: the tangential surface velocity jumps at the burst end"),
            ));
        }
    }
    let c = wave.phase_velocity_m_per_s;
    if c > limits.max_phase_velocity_m_per_s {
        return Err(StickSlipError::UnphysicalWave {
            parameter: "wave.phase_velocity_m_per_s",
            value: c,
            limit: limits.max_phase_velocity_m_per_s,
            reason: "faster than the fastest bulk wave of the stator; no surface wave travels faster",
        });
    }
    if c > limits.shear_speed_warning_m_per_s {
        warnings.push(Warning::new(
            "wave.phase_velocity_m_per_s",
            format!(
                "{c} m/s exceeds the fastest bulk shear speed {} m/s: only a leaky pseudo-SAW travels this fast",
                limits.shear_speed_warning_m_per_s
            ),
        ));
    }
    let strain = wave.surface_strain();
    if strain > limits.max_surface_strain {
        return Err(StickSlipError::UnphysicalWave {
            parameter: "wave.normal_amplitude_m / wave.tangential_amplitude_m",
            value: strain,
            limit: limits.max_surface_strain,
            reason: "surface strain k·max(A_n, A_t) (equivalently A_t ω / c) beyond linear elasticity of the stator",
        });
    }
    if strain > limits.surface_strain_warning {
        warnings.push(Warning::new(
            "wave.normal_amplitude_m / wave.tangential_amplitude_m",
            format!(
                "surface strain {strain:.2e} exceeds {:.0e}, far above SAW device practice (crest speed {:.3} m/s)",
                limits.surface_strain_warning,
                wave.crest_speed_m_per_s()
            ),
        ));
    }
    Ok(warnings)
}

/// The wave in the solvers' units (lengths by A_n, time by 1/ω).
pub(crate) fn scaled(wave: &Wave) -> ScaledWave {
    let a_n = wave.normal_amplitude_m;
    ScaledWave {
        tangential_ratio: wave.tangential_amplitude_m / a_n,
        doppler: wave.wavenumber_rad_per_m() * a_n,
        decay_length: wave.decay_length_m.map(|l| l / a_n),
        burst_phase_end: wave.burst_periods.map(|n| 2.0 * PI * n),
    }
}

/// The wave in solver units: length A_n, time 1/ω, so the normal amplitude is 1 and the
/// tangential velocity amplitude is â = A_t/A_n.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ScaledWave {
    /// â = A_t/A_n: tangential displacement (and velocity) amplitude.
    pub tangential_ratio: f64,
    /// κ = k·A_n: phase advance per unit (scaled) slider displacement; θ̇ = 1 − κ v̂.
    pub doppler: f64,
    /// L/A_n, if the wave decays.
    pub decay_length: Option<f64>,
    /// 2πn for an n-period burst.
    pub burst_phase_end: Option<f64>,
}

impl ScaledWave {
    /// Amplitude factor at scaled position x (1 without decay).
    pub fn amplitude_at(&self, x: f64) -> f64 {
        self.decay_length.map_or(1.0, |l| (-x / l).exp())
    }

    /// Whether the wave is on at (unwrapped) phase θ.
    pub fn is_on(&self, theta: f64) -> bool {
        match self.burst_phase_end {
            None => true,
            Some(end) => (0.0..end).contains(&theta),
        }
    }
}
