//! One solved surface wave: partial-wave amplitudes, surface ratios, depth profiles, power flux.
//!
//! Formula: with the surface vector U₀ (null vector of the boundary matrix) the partial-wave
//! amplitudes are a = A⁻¹U₀, normalised so that u_z(0) = u₃(0) = 1. At depth d = −x₃ ≥ 0 the field is
//! U(d) = Σₙ aₙAₙ exp(j k pₙ d) (times exp(j(ωt − k x₁))), with Im pₙ > 0 so that it decays. The
//! time-averaged Poynting flux along x₁ per unit beam width (B. A. Auld, *Acoustic Fields and Waves
//! in Solids* I, eq. 10.60: P = −½ Re(T·v*) + ½ Re(φ (jωD)*)) is, integrated over depth in closed form,
//!   P/|u_z|² = ½ ω Re Σₘₙ conj(aₘAₘ)·(aₙFₙ) · j/(pₙ − conj(pₘ)),
//! with F = (Q + pR)A the x₁-plane traction (T₁₁, T₁₂, T₁₃, D₁) over −jk; the J ≤ 3 terms are the
//! mechanical part, J = 4 the electrical part in the crystal. Above a free surface the vacuum
//! potential φ₀e^{−kz} carries −¼ ω ε0 |φ₀|² (the quasi-static vacuum flux, against the wave); the
//! total is the sum of the three. The result is proportional to ω and independent of k.
//!
//! Range of validity: a lossless surface wave below the limiting velocity, small amplitudes
//! (linear theory), quasi-static electric field.

use crate::error::{Surface, WaveError};
use crate::material::VACUUM_PERMITTIVITY_F_PER_M;
use crate::stroh::{C64, PartialWaves, Scales};
use nalgebra::{Matrix4, Vector4};
use std::f64::consts::PI;

/// Smallest |u_z|/|u| at the surface for which a mode is normalised to u_z (dimensionless).
const MIN_NORMAL_FRACTION: f64 = 1e-6;

/// One decaying partial wave of a solved mode, in physical units normalised to u_z(0) = 1.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PartialWave {
    /// Depth ratio p (complex, Im p > 0): the wave varies as exp(j(ωt − k x₁ + k p d)) with depth d.
    /// Stored as [Re p, Im p].
    pub depth_ratio: [f64; 2],
    /// (u_x, u_y, u_z) of this partial wave at the surface per unit u_z(0), as [re, im] pairs.
    pub displacement: [[f64; 2]; 3],
    /// Its electric potential at the surface per unit u_z(0) (V/m), as [re, im].
    pub potential_v_per_m: [f64; 2],
}

impl PartialWave {
    /// p as a complex number.
    pub fn p(&self) -> C64 {
        C64::new(self.depth_ratio[0], self.depth_ratio[1])
    }

    /// (u_x, u_y, u_z, φ [V/m]) at the surface as complex numbers.
    pub fn fields(&self) -> [C64; 4] {
        let c = |v: [f64; 2]| C64::new(v[0], v[1]);
        [
            c(self.displacement[0]),
            c(self.displacement[1]),
            c(self.displacement[2]),
            c(self.potential_v_per_m),
        ]
    }
}

/// Time-averaged power flux along the propagation direction per unit beam width, per |u_z|² at the
/// surface and per hertz: P = (this) · f · |u_z|² in W/m.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PowerFlux {
    /// −½ Re(T·v*) integrated over depth (W/m per m² per Hz).
    pub mechanical_w_per_m_per_m2_per_hz: f64,
    /// ½ Re(φ (jωD)*) integrated over the crystal's depth (W/m per m² per Hz).
    pub electrical_crystal_w_per_m_per_m2_per_hz: f64,
    /// ½ Re(φ (jωD)*) integrated over the vacuum above a free surface (W/m per m² per Hz; ≤ 0).
    pub electrical_vacuum_w_per_m_per_m2_per_hz: f64,
}

impl PowerFlux {
    /// Sum of the three parts (W/m per m² per Hz).
    pub fn total_w_per_m_per_m2_per_hz(&self) -> f64 {
        self.mechanical_w_per_m_per_m2_per_hz
            + self.electrical_crystal_w_per_m_per_m2_per_hz
            + self.electrical_vacuum_w_per_m_per_m2_per_hz
    }
}

/// Complex fields at one depth, normalised to u_z(0) = 1 (see [`SurfaceMode::fields_at_depth`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fields {
    /// Displacement along propagation, per unit u_z(0).
    pub ux: C64,
    /// Displacement across the beam (in the surface plane), per unit u_z(0).
    pub uy: C64,
    /// Displacement along the outward normal, per unit u_z(0).
    pub uz: C64,
    /// Electric potential per metre of u_z(0) (V/m).
    pub phi_v_per_m: C64,
}

/// One sample of a depth profile, serialisable: complex values as [re, im].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct DepthSample {
    /// Depth below the surface in wavelengths (≥ 0).
    pub depth_wavelengths: f64,
    /// u_x / u_z(0).
    pub ux: [f64; 2],
    /// u_y / u_z(0).
    pub uy: [f64; 2],
    /// u_z / u_z(0).
    pub uz: [f64; 2],
    /// φ / u_z(0) (V/m).
    pub phi_v_per_m: [f64; 2],
}

/// A surface wave on one electrical boundary condition.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SurfaceMode {
    /// Free or metallized.
    pub surface: Surface,
    /// Phase velocity (m/s).
    pub phase_velocity_m_per_s: f64,
    /// |u_x / u_z| at the surface.
    pub ux_over_uz_abs: f64,
    /// arg(u_x / u_z) at the surface (degrees, in (−180, 180]); +90° is a retrograde orbit for a
    /// wave travelling along +x with z the outward normal.
    pub ux_over_uz_phase_deg: f64,
    /// |u_y / u_z| at the surface (zero when the sagittal plane decouples).
    pub uy_over_uz_abs: f64,
    /// |φ / u_z| at the surface (V/m; zero on a metallized surface).
    pub potential_over_uz_v_per_m: f64,
    /// Power flux per width per |u_z|² per hertz.
    pub power_flux: PowerFlux,
    /// The four partial waves.
    pub partial_waves: [PartialWave; 4],
}

impl SurfaceMode {
    /// Builds the mode from the partial waves at its velocity and its surface vector U₀ (scaled).
    pub(crate) fn new(
        surface: Surface,
        velocity_m_per_s: f64,
        waves: &PartialWaves,
        surface_vector: Vector4<C64>,
        scales: &Scales,
        context: &str,
    ) -> Result<Self, WaveError> {
        let u_norm = surface_vector.fixed_rows::<3>(0).norm();
        let normal_fraction = surface_vector[2].norm() / u_norm;
        if normal_fraction.is_nan() || normal_fraction <= MIN_NORMAL_FRACTION {
            return Err(WaveError::NoNormalDisplacement {
                cut: context.into(),
                surface,
                velocity_m_per_s,
                normal_fraction,
            });
        }
        let u0 = surface_vector / surface_vector[2];
        let amplitudes =
            waves
                .a
                .try_inverse()
                .map(|inv| inv * u0)
                .ok_or(WaveError::PartialWaves {
                    cut: context.into(),
                    velocity_m_per_s,
                    reason: "the partial-wave displacements are linearly dependent",
                })?;
        let weighted = |m: &Matrix4<C64>| Matrix4::from_fn(|j, n| m[(j, n)] * amplitudes[n]);
        let (u, f) = (weighted(&waves.a), weighted(&waves.f));
        let potential_scale = scales.potential_v_per_m();
        let phi0 = u0[3] * potential_scale;
        let ratio = u0[0];
        Ok(Self {
            surface,
            phase_velocity_m_per_s: velocity_m_per_s,
            ux_over_uz_abs: ratio.norm(),
            ux_over_uz_phase_deg: ratio.arg().to_degrees(),
            uy_over_uz_abs: u0[1].norm(),
            potential_over_uz_v_per_m: phi0.norm(),
            power_flux: power_flux(&waves.p, &u, &f, scales, phi0.norm()),
            partial_waves: std::array::from_fn(|n| {
                partial_wave(waves.p[n], &u, n, potential_scale)
            }),
        })
    }

    /// Complex fields at `depth_wavelengths` (≥ 0) below the surface, per unit u_z(0).
    pub fn fields_at_depth(&self, depth_wavelengths: f64) -> Fields {
        let mut sum = [C64::new(0.0, 0.0); 4];
        for wave in &self.partial_waves {
            let phase = (C64::new(0.0, 2.0 * PI * depth_wavelengths) * wave.p()).exp();
            for (s, field) in sum.iter_mut().zip(wave.fields()) {
                *s += field * phase;
            }
        }
        Fields {
            ux: sum[0],
            uy: sum[1],
            uz: sum[2],
            phi_v_per_m: sum[3],
        }
    }

    /// The fields sampled at the given depths (wavelengths).
    pub fn depth_profile(&self, depths_wavelengths: &[f64]) -> Vec<DepthSample> {
        let pair = |c: C64| [c.re, c.im];
        depths_wavelengths
            .iter()
            .map(|&d| {
                let f = self.fields_at_depth(d);
                DepthSample {
                    depth_wavelengths: d,
                    ux: pair(f.ux),
                    uy: pair(f.uy),
                    uz: pair(f.uz),
                    phi_v_per_m: pair(f.phi_v_per_m),
                }
            })
            .collect()
    }

    /// Total power per unit beam width (W/m) at normal surface amplitude `amplitude_uz_m` (m, ≥ 0)
    /// and frequency `frequency_hz` (Hz, > 0).
    pub fn power_per_width_w_per_m(
        &self,
        amplitude_uz_m: f64,
        frequency_hz: f64,
    ) -> Result<f64, WaveError> {
        let check = |name, value: f64, ok: bool, requirement| {
            if ok {
                Ok(())
            } else {
                Err(WaveError::InvalidArgument {
                    function: "power_per_width_w_per_m",
                    name,
                    value,
                    requirement,
                })
            }
        };
        check(
            "amplitude_uz_m",
            amplitude_uz_m,
            amplitude_uz_m.is_finite() && amplitude_uz_m >= 0.0,
            "finite and non-negative",
        )?;
        check(
            "frequency_hz",
            frequency_hz,
            frequency_hz.is_finite() && frequency_hz > 0.0,
            "finite and positive",
        )?;
        Ok(self.power_flux.total_w_per_m_per_m2_per_hz()
            * frequency_hz
            * amplitude_uz_m
            * amplitude_uz_m)
    }
}

/// The closed-form depth integral of the Poynting flux (module formula), per hertz.
fn power_flux(
    p: &[C64; 4],
    u: &Matrix4<C64>,
    f: &Matrix4<C64>,
    scales: &Scales,
    phi0_v_per_m: f64,
) -> PowerFlux {
    let (mut mechanical, mut electrical) = (0.0, 0.0);
    for m in 0..4 {
        for n in 0..4 {
            let kernel = C64::new(0.0, 1.0) / (p[n] - p[m].conj());
            let term = |j: usize| (u[(j, m)].conj() * f[(j, n)] * kernel).re;
            mechanical += (0..3).map(term).sum::<f64>();
            electrical += term(3);
        }
    }
    // ½ ω (…) · c_ref per |u_z|², with ω = 2π f.
    let per_hz = PI * scales.stiffness_pa;
    PowerFlux {
        mechanical_w_per_m_per_m2_per_hz: per_hz * mechanical,
        electrical_crystal_w_per_m_per_m2_per_hz: per_hz * electrical,
        electrical_vacuum_w_per_m_per_m2_per_hz: -0.5
            * PI
            * VACUUM_PERMITTIVITY_F_PER_M
            * phi0_v_per_m
            * phi0_v_per_m,
    }
}

fn partial_wave(p: C64, u: &Matrix4<C64>, n: usize, potential_scale: f64) -> PartialWave {
    let pair = |c: C64| [c.re, c.im];
    PartialWave {
        depth_ratio: pair(p),
        displacement: [pair(u[(0, n)]), pair(u[(1, n)]), pair(u[(2, n)])],
        potential_v_per_m: pair(u[(3, n)] * potential_scale),
    }
}
