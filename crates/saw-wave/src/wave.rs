//! The Rayleigh wave of a crystal cut on the electrically free and the metallized surface.
//!
//! Formula: v_free and v_met are the slowest sign changes of the real boundary determinants below
//! the limiting velocity ([`crate::boundary`], [`crate::search`]); the coupling coefficient is
//! K² = 2(v_free − v_met)/v_free (the Ingebrigtsen approximation of the electromechanical
//! coupling of a SAW transducer). Source: K. A. Ingebrigtsen, *J. Appl. Phys.* 40, 2681 (1969);
//! D. P. Morgan, *Surface Acoustic Wave Devices* (Elsevier 2007), ch. 2. Range of validity: a
//! non-leaky surface wave with a normal displacement component on both surfaces.

use crate::boundary::BoundaryMatrices;
use crate::cut::Cut;
use crate::error::{Surface, WaveError};
use crate::mode::{DepthSample, PowerFlux, SurfaceMode};
use crate::search::{SignChange, brent, limiting_velocity, scan_velocities};
use crate::stroh::StrohSystem;

/// The solved surface wave of one cut. The top-level ratios and power refer to the free surface.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RayleighWave {
    /// The cut: name, material and Euler angles.
    pub cut: String,
    /// Phase velocity on the electrically free surface (m/s).
    pub phase_velocity_free_m_per_s: f64,
    /// Phase velocity on the metallized (shorted) surface (m/s).
    pub phase_velocity_metallized_m_per_s: f64,
    /// K² = 2(v_free − v_met)/v_free.
    pub coupling_k2: f64,
    /// Lowest velocity at which a partial wave stops decaying (m/s).
    pub limiting_velocity_m_per_s: f64,
    /// |u_x / u_z| at the free surface.
    pub surface_ux_over_uz_abs: f64,
    /// arg(u_x / u_z) at the free surface (degrees; +90° = retrograde orbit).
    pub surface_ux_over_uz_phase_deg: f64,
    /// Power flux of the free-surface wave per width per |u_z|² per hertz.
    pub power_flux: PowerFlux,
    /// The free-surface wave.
    pub free: SurfaceMode,
    /// The metallized-surface wave.
    pub metallized: SurfaceMode,
}

impl Cut {
    /// Solves the cut's Rayleigh wave (free and metallized surface).
    pub fn solve(&self) -> Result<RayleighWave, WaveError> {
        RayleighWave::solve(self)
    }
}

impl RayleighWave {
    /// Solves both boundary conditions of the cut.
    pub fn solve(cut: &Cut) -> Result<Self, WaveError> {
        check_angles(cut)?;
        cut.material.validate()?;
        let label = cut.label();
        let system = StrohSystem::new(&cut.rotated_material())
            .ok_or_else(|| failure(&label, 0.0, "the x3-plane stiffness block T is singular"))?;
        let v_ref = system.scales.velocity_m_per_s;
        let limiting = limiting_velocity(&system).map_err(|reason| failure(&label, 0.0, reason))?;
        let (free, metallized) = scan(&system, limiting, &label)?;
        let no_wave = |surface| WaveError::NoSurfaceWave {
            cut: label.clone(),
            surface,
            limiting_velocity_m_per_s: limiting * v_ref,
        };
        let free = free.ok_or_else(|| no_wave(Surface::Free))?;
        let metallized = metallized.ok_or_else(|| no_wave(Surface::Metallized))?;
        let free = build_mode(&system, Surface::Free, free, &label)?;
        let metallized = build_mode(&system, Surface::Metallized, metallized, &label)?;
        let (v_free, v_met) = (
            free.phase_velocity_m_per_s,
            metallized.phase_velocity_m_per_s,
        );
        Ok(Self {
            cut: label,
            phase_velocity_free_m_per_s: v_free,
            phase_velocity_metallized_m_per_s: v_met,
            coupling_k2: 2.0 * (v_free - v_met) / v_free,
            limiting_velocity_m_per_s: limiting * v_ref,
            surface_ux_over_uz_abs: free.ux_over_uz_abs,
            surface_ux_over_uz_phase_deg: free.ux_over_uz_phase_deg,
            power_flux: free.power_flux,
            free,
            metallized,
        })
    }

    /// Power per unit beam width (W/m) of the free-surface wave at normal amplitude
    /// `amplitude_uz_m` (m) and frequency `frequency_hz` (Hz).
    pub fn power_per_width_w_per_m(
        &self,
        amplitude_uz_m: f64,
        frequency_hz: f64,
    ) -> Result<f64, WaveError> {
        self.free
            .power_per_width_w_per_m(amplitude_uz_m, frequency_hz)
    }

    /// Depth profile of the free-surface wave (u_x, u_y, u_z, φ per unit u_z(0)) at depths in
    /// wavelengths.
    pub fn depth_profile(&self, depths_wavelengths: &[f64]) -> Vec<DepthSample> {
        self.free.depth_profile(depths_wavelengths)
    }
}

fn failure(label: &str, velocity_m_per_s: f64, reason: &'static str) -> WaveError {
    WaveError::PartialWaves {
        cut: label.to_owned(),
        velocity_m_per_s,
        reason,
    }
}

fn check_angles(cut: &Cut) -> Result<(), WaveError> {
    let e = &cut.euler;
    for (quantity, value) in [
        ("Euler angle phi", e.phi_deg),
        ("Euler angle theta", e.theta_deg),
        ("Euler angle psi", e.psi_deg),
    ] {
        if !value.is_finite() {
            return Err(WaveError::NonFinite {
                context: cut.name.clone(),
                quantity: quantity.into(),
                value,
            });
        }
    }
    Ok(())
}

/// Boundary matrices at scaled velocity v (both conditions share the partial waves).
fn boundary(system: &StrohSystem, v: f64, label: &str) -> Result<BoundaryMatrices, WaveError> {
    let v_si = v * system.scales.velocity_m_per_s;
    let waves = system
        .partial_waves(v)
        .map_err(|reason| failure(label, v_si, reason))?
        .ok_or_else(|| {
            failure(
                label,
                v_si,
                "a partial wave does not decay below the limiting velocity",
            )
        })?;
    BoundaryMatrices::new(&waves, system.vacuum_permittivity).ok_or_else(|| {
        failure(
            label,
            v_si,
            "the partial-wave displacements are linearly dependent",
        )
    })
}

/// Scans both determinants and refines the first sign change of each (scaled velocities).
fn scan(
    system: &StrohSystem,
    limiting: f64,
    label: &str,
) -> Result<(Option<f64>, Option<f64>), WaveError> {
    let (mut free, mut metallized) = (SignChange::default(), SignChange::default());
    for v in scan_velocities(limiting) {
        let b = boundary(system, v, label)?;
        free.push(v, b.free_determinant());
        metallized.push(v, b.metallized_determinant());
        if free.bracket.is_some() && metallized.bracket.is_some() {
            break;
        }
    }
    let refine = |bracket: Option<_>, det: fn(&BoundaryMatrices) -> f64| {
        bracket
            .map(|b| brent(|v| boundary(system, v, label).map(|m| det(&m)), b))
            .transpose()
    };
    Ok((
        refine(free.bracket, BoundaryMatrices::free_determinant)?,
        refine(metallized.bracket, BoundaryMatrices::metallized_determinant)?,
    ))
}

fn build_mode(
    system: &StrohSystem,
    surface: Surface,
    v: f64,
    label: &str,
) -> Result<SurfaceMode, WaveError> {
    let v_si = v * system.scales.velocity_m_per_s;
    let waves = system
        .partial_waves(v)
        .map_err(|reason| failure(label, v_si, reason))?
        .ok_or_else(|| failure(label, v_si, "a partial wave does not decay at the root"))?;
    let matrices = BoundaryMatrices::new(&waves, system.vacuum_permittivity).ok_or_else(|| {
        failure(
            label,
            v_si,
            "the partial-wave displacements are linearly dependent",
        )
    })?;
    let vector = match surface {
        Surface::Free => matrices.free_surface_vector(),
        Surface::Metallized => matrices.metallized_surface_vector(),
    }
    .ok_or_else(|| {
        failure(
            label,
            v_si,
            "the SVD of the boundary matrix returned no singular vectors",
        )
    })?;
    SurfaceMode::new(surface, v_si, &waves, vector, &system.scales, label)
}
