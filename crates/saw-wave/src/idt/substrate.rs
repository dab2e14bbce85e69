//! What a transducer needs from its crystal cut: velocities, K², effective permittivity, power flux.
//!
//! Formula: ε^T = ε^S + e·s^E·eᵀ with s^E = (c^E)⁻¹ (IEEE Std 176-1987, the constant-stress
//! permittivity), in the wave frame of the cut; ε∞ = ε₀ + √(ε₁₁ε₃₃ − ε₁₃²) (D. P. Morgan,
//! *Surface Acoustic Wave Devices*, 2nd ed. 2007, ch. 3). The complete elliptic integral of the
//! first kind by the arithmetic–geometric mean, K(k) = π/(2·AGM(1, √(1 − k²)))
//! (Abramowitz & Stegun 17.6). Range of validity: a solved, non-leaky Rayleigh wave of the same
//! cut; 0 ≤ k < 1.

use crate::cut::Cut;
use crate::error::WaveError;
use crate::material::VACUUM_PERMITTIVITY_F_PER_M;
use crate::wave::RayleighWave;

/// Relative tolerance at which the arithmetic–geometric mean stops.
const AGM_TOLERANCE: f64 = 1e-16;
/// Iteration cap of the arithmetic–geometric mean (it converges quadratically: < 10 are used).
const AGM_MAX_ITERATIONS: usize = 60;

/// The substrate of a transducer: one cut and its solved Rayleigh wave.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct IdtSubstrate {
    /// The cut's label (name, material, Euler angles).
    pub cut: String,
    /// Free-surface phase velocity v_f (m/s).
    pub phase_velocity_free_m_per_s: f64,
    /// Metallized-surface phase velocity v_m (m/s).
    pub phase_velocity_metallized_m_per_s: f64,
    /// K² = 2(v_f − v_m)/v_f.
    pub coupling_k2: f64,
    /// Constant-stress permittivity ε^T in the wave frame (F/m; x₁ propagation, x₃ normal).
    pub permittivity_stress_free_f_per_m: [[f64; 3]; 3],
    /// ε∞ = ε₀ + √(ε^T₁₁ε^T₃₃ − (ε^T₁₃)²) (F/m): the one used.
    pub effective_permittivity_f_per_m: f64,
    /// The same from the clamped ε^S (F/m): a lower bound, reported for comparison.
    pub effective_permittivity_clamped_f_per_m: f64,
    /// Power of the free-surface wave per beam width per |u_z|² per hertz (J/m³).
    pub power_per_width_per_uz2_per_hz_j_per_m3: f64,
    /// |u_x/u_z| at the free surface.
    pub surface_ux_over_uz_abs: f64,
}

impl IdtSubstrate {
    /// The substrate of `cut`, whose Rayleigh wave is `wave` (from `cut.solve()`).
    pub fn new(cut: &Cut, wave: &RayleighWave) -> Result<Self, WaveError> {
        if cut.label() != wave.cut {
            return Err(WaveError::MismatchedWave {
                cut: cut.label(),
                wave_cut: wave.cut.clone(),
            });
        }
        let rotated = cut.rotated_material();
        let stress_free = rotated.permittivity_stress_free_f_per_m().ok_or_else(|| {
            WaveError::NotPositiveDefinite {
                material: rotated.name.clone(),
                tensor: "stiffness",
                smallest_eigenvalue: 0.0,
            }
        })?;
        Ok(Self {
            cut: wave.cut.clone(),
            phase_velocity_free_m_per_s: wave.phase_velocity_free_m_per_s,
            phase_velocity_metallized_m_per_s: wave.phase_velocity_metallized_m_per_s,
            coupling_k2: wave.coupling_k2,
            permittivity_stress_free_f_per_m: stress_free,
            effective_permittivity_f_per_m: effective_permittivity(&stress_free),
            effective_permittivity_clamped_f_per_m: effective_permittivity(
                &rotated.permittivity_f_per_m,
            ),
            power_per_width_per_uz2_per_hz_j_per_m3: wave.power_flux.total_w_per_m_per_m2_per_hz(),
            surface_ux_over_uz_abs: wave.surface_ux_over_uz_abs,
        })
    }

    /// Solves `cut` and builds its substrate.
    pub fn from_cut(cut: &Cut) -> Result<Self, WaveError> {
        Self::new(cut, &cut.solve()?)
    }
}

/// ε₀ + √(ε₁₁ε₃₃ − ε₁₃²): the sagittal-plane (x₁, x₃) permittivity of the crystal plus vacuum.
fn effective_permittivity(eps: &[[f64; 3]; 3]) -> f64 {
    let det = eps[0][0] * eps[2][2] - eps[0][2] * eps[2][0];
    VACUUM_PERMITTIVITY_F_PER_M + det.sqrt()
}

/// Complete elliptic integral of the first kind K(k) = ∫₀^{π/2} dθ/√(1 − k² sin²θ), modulus k
/// (not the parameter m = k²), for 0 ≤ |k| < 1; `f64::INFINITY` at |k| = 1 and NaN beyond.
pub fn complete_elliptic_k(k: f64) -> f64 {
    if k.is_nan() || k.abs() > 1.0 {
        return f64::NAN;
    }
    let (mut a, mut b) = (1.0_f64, (1.0 - k * k).sqrt());
    if b == 0.0 {
        return f64::INFINITY;
    }
    for _ in 0..AGM_MAX_ITERATIONS {
        if (a - b).abs() <= AGM_TOLERANCE * a {
            break;
        }
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::FRAC_PI_2 / a
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;

    #[test]
    fn elliptic_k_matches_tabulated_values() {
        // Abramowitz & Stegun Table 17.1: K(0) = π/2, K(sin 45°) = 1.8540746773013719,
        // K(sin 30°) = 1.6857503548125961.
        assert!((complete_elliptic_k(0.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let k45 = complete_elliptic_k(std::f64::consts::FRAC_1_SQRT_2);
        assert!(
            (k45 - 1.854_074_677_301_371_9).abs() < 1e-14,
            "K(sin 45°) = {k45}"
        );
        let k30 = complete_elliptic_k(0.5);
        assert!(
            (k30 - 1.685_750_354_812_596).abs() < 1e-14,
            "K(sin 30°) = {k30}"
        );
        assert!(complete_elliptic_k(1.0).is_infinite());
        assert!(complete_elliptic_k(1.5).is_nan());
    }

    #[test]
    fn non_piezoelectric_solid_has_equal_clamped_and_free_permittivity() {
        let m = Material::isotropic("test solid", 100e9, 80e9, 7800.0, 4.5).unwrap();
        let free = m.permittivity_stress_free_f_per_m().unwrap();
        assert_eq!(free, m.permittivity_f_per_m);
        let expected = VACUUM_PERMITTIVITY_F_PER_M * 5.5;
        assert!((effective_permittivity(&free) / expected - 1.0).abs() < 1e-15);
    }
}
