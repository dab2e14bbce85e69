//! From drive voltage to wave amplitude: a uniform single-electrode interdigital transducer (IDT)
//! on the crystal cut of a [`RayleighWave`](crate::RayleighWave).
//!
//! **Geometry.** 2N_p fingers of width w separated by gaps g, alternately connected to the two bus
//! bars, overlapping over the aperture W. Electrode pitch p_e = w + g, transducer period
//! λ₀ = 2p_e (one finger pair), metallisation ratio η = w/p_e.
//!
//! **Formulas** (SI; V is the *peak* voltage of the drive, V₀₋ₚ; phasors are peak phasors, so a
//! time-averaged power is ½Re(V·I*)):
//! 1. Synchronous frequency f₀ = v_f/λ₀ with v_f the free-surface velocity of the crate's wave
//!    (the wave outside the transducer); f₀,met = v_m/λ₀ is reported beside it, since the wave
//!    under a metallised fraction η of the surface travels between the two.
//! 2. Effective permittivity ε∞ = ε₀ + ε_p, ε_p = √(ε^T₁₁ε^T₃₃ − (ε^T₁₃)²) in the wave frame
//!    (x₁ propagation, x₃ surface normal), with the constant-stress permittivity
//!    ε^T = ε^S + e·s^E·eᵀ (s^E = (c^E)⁻¹; IEEE Std 176-1987) rotated to the cut. Source:
//!    D. P. Morgan, *Surface Acoustic Wave Devices*, 2nd ed. (Elsevier 2007), ch. 3 (effective
//!    permittivity, its value for large slowness). The clamped form from ε^S is reported too: it
//!    bounds ε∞ from below.
//! 3. Static capacitance per finger pair per metre of aperture
//!    C_s = ε∞·K(sin(πη/2))/K(cos(πη/2)), K the complete elliptic integral of the first kind
//!    (C_s = ε∞ at η = ½), and C_T = N_p·C_s·W. Source: the conformal map of the periodic strip
//!    array (H. Engan, *IEEE Trans. Electron Devices* ED-16, 1014 (1969); Morgan 2007 ch. 5). The
//!    end fingers' fringe fields are left out (≈ 1/(2N_p) of C_T).
//! 4. Radiation admittance, delta-function (impulse) model: one source per electrode at
//!    x_n = n·p_e with polarity (−1)ⁿ, n = 0…M−1, M = 2N_p. Each source launches waves both ways
//!    with wavenumber k = 2πf/v_f, and Y_a = G_a + jB_a = (G_a0/M²)·Σₙ Σₘ (−1)ⁿ⁺ᵐ e^{−jk|x_n−x_m|}.
//!    With δ = π(f − f₀)/f₀ the double sum has the closed forms
//!    G_a = G_a0·sin²(Mδ/2)/(M² sin²(δ/2)) and
//!    B_a = −G_a0·(M sin δ − sin Mδ)/(2M² sin²(δ/2)), which for N_p ≫ 1 become Smith's
//!    G_a0·(sin X/X)² and G_a0·(sin 2X − 2X)/(2X²) with X = N_p·δ (zeros of G_a at
//!    f₀(1 ± 1/N_p) in both forms). The synchronous conductance is
//!    G_a0 = 8K²f₀C_sWN_p² with K² = 2(v_f − v_m)/v_f from the crate's wave. Sources:
//!    W. R. Smith et al., *IEEE Trans. MTT* 17, 856 (1969) (crossed-field model);
//!    C. S. Hartmann, D. T. Bell, R. C. Rosenfeld, *IEEE Trans. MTT* 21, 162 (1973) (impulse
//!    model); Morgan 2007 ch. 5 and 8; S. Datta, *Surface Acoustic Wave Devices* (1986).
//!    The constant 8 is these models' own; analyses that resolve the charge on each finger change
//!    it by a factor of order one, which is the model's uncertainty beside that of K² and ε∞.
//! 5. Finger resistance (optional [`Metallisation`]): one finger R_f = ρW/(w·h); the current
//!    falls linearly from the bus bar to the finger tip, so each finger acts as R_f/3, N_p fingers
//!    of a comb are in parallel and the two combs in series: R_s = 2R_f/(3N_p). Source:
//!    K. M. Lakin, *IEEE Trans. MTT* 22, 418 (1974), the lumped limit of the distributed RC line,
//!    valid for ωR_f·C_T/N_p ≪ 1 (checked, [`Caveat::LongFingers`]).
//! 6. Circuit: an ideal voltage source of peak V at the bus bars, Z = R_s + 1/Y_t with
//!    Y_t = G_a + j(B_a + ωC_T); I = V/Z, transducer voltage V_t = I/Y_t. A lossless matching
//!    network in front of an ideal source changes the current drawn but not V_t nor the real
//!    power. For a Z₀ = 50 Ω amplifier driving the IDT without matching, the forward power that
//!    puts V on the IDT is P_fwd = |V|²/(2Z₀|1 + Γ|²), Γ = (Z − Z₀)/(Z + Z₀).
//! 7. Powers: P_in = ½Re(V·I*) = P_ac + P_Ω with P_ac = ½|V_t|²G_a (both directions),
//!    P_Ω = ½|I|²R_s; per direction P = P_ac/2 = ¼|V_t|²G_a (the transducer is symmetric). Only
//!    one direction drives the slider: the other is lost (or absorbed) at the stator's end.
//! 8. Amplitude: |u_z| = √(P / (W·Π(f))), Π(f) = (P/(f|u_z|²))·f the crate's power per beam
//!    width per |u_z|² (`PowerFlux::total_w_per_m_per_m2_per_hz` × f); |u_x| from the surface
//!    ratio and the tangential surface speed ω|u_x|.
//!
//! **Energy balance**: P_in = P_ac + P_Ω to rounding; P_ac = 2P, each direction's P carried by the
//! wave of amplitude |u_z| (the crate's Poynting flux); the reactive power ½Im(V·I*) is stored
//! and returned each cycle. With the Z₀ source, P_fwd(1 − |Γ|²) = P_in.
//!
//! **Validity.** Weak coupling, and no interaction of the wave with the transducer it crosses:
//! the model leaves out electrode reflections and regeneration (re-radiation by the charges the
//! wave induces), which for a single-electrode IDT add up coherently at f₀ (Bragg condition,
//! λ₀/2 spacing). Their size is N_p·K²: a reflection of order K² per electrode over 2N_p
//! electrodes, and the radiation Q, ωC_T/G_a0 = π/(4N_pK²). The model is trusted for
//! N_p·K² ≤ [`WEAK_COUPLING_LIMIT`]; above it the results carry [`Caveat::StrongCoupling`] and
//! their error is of order one (20 pairs on 128° Y-X LiNbO3: N_p·K² ≈ 1.1). Also outside the
//! model: bulk-wave radiation, mass loading and stored energy of the electrodes (velocity shift
//! under the IDT), propagation loss, beam diffraction (Fresnel length W²/λ₀), the power-flow angle,
//! harmonics (the element factor is left out; trusted for |f/f₀ − 1| ≤
//! [`SYNCHRONISM_RANGE`]), bus-bar resistance, and heating.

mod response;
mod substrate;

pub use response::{Caveat, IdtAdmittance, IdtResponse, radiation_admittance_ratio};
pub use substrate::{IdtSubstrate, complete_elliptic_k};

use crate::error::WaveError;

/// Largest N_p·K² for which reflections and regeneration inside the transducer are treated as
/// negligible (dimensionless). Above it every result carries [`Caveat::StrongCoupling`].
pub const WEAK_COUPLING_LIMIT: f64 = 0.1;

/// Largest |f/f₀ − 1| for which the delta-function model (no element factor) is trusted.
pub const SYNCHRONISM_RANGE: f64 = 0.5;

/// Largest ωR_f·C_T/N_p (finger RC phase) for which the lumped finger resistance 2R_f/(3N_p) holds.
pub const LUMPED_FINGER_LIMIT: f64 = 0.1;

/// Conductance ratio G_a(f)/G_a0 below which a drive is reported as detuned ([`Caveat::Detuned`]):
/// the half-power point of the conductance.
pub const DETUNED_CONDUCTANCE_RATIO: f64 = 0.5;

/// Characteristic impedance of the amplifier and cable for the forward-power figure (Ω).
pub const REFERENCE_IMPEDANCE_OHM: f64 = 50.0;

/// A uniform single-electrode interdigital transducer. Fields map one-to-one to the scene table
/// `[stator.idt]` (`finger_pairs`, `finger_width`, `gap`, `aperture`, `metallisation`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Idt {
    /// Number of finger pairs N_p (2N_p fingers), ≥ 1.
    pub finger_pairs: u32,
    /// Finger width w (m), > 0.
    pub finger_width_m: f64,
    /// Gap between neighbouring fingers g (m), > 0.
    pub gap_m: f64,
    /// Acoustic aperture W, the fingers' overlap (m), > 0.
    pub aperture_m: f64,
    /// The finger film, for the finger resistance; `None` for perfectly conducting fingers.
    pub metallisation: Option<Metallisation>,
}

/// The metal film of the fingers. Maps to the scene table `[stator.idt.metallisation]`
/// (`metal`, `thickness`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Metallisation {
    /// The conductor.
    pub metal: ElectrodeMetal,
    /// Film thickness h (m), > 0.
    pub thickness_m: f64,
}

/// Electrode metals with their bulk resistivity at 20 °C (thin films are more resistive; give
/// [`ElectrodeMetal::Other`] with a measured value when it is known).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum ElectrodeMetal {
    /// Aluminium, 2.65·10⁻⁸ Ω·m.
    Aluminium,
    /// Chromium, 1.25·10⁻⁷ Ω·m.
    Chromium,
    /// Gold, 2.44·10⁻⁸ Ω·m.
    Gold,
    /// Copper, 1.68·10⁻⁸ Ω·m.
    Copper,
    /// Any conductor of the given resistivity.
    Other {
        /// Resistivity ρ (Ω·m), > 0.
        resistivity_ohm_m: f64,
    },
}

impl ElectrodeMetal {
    /// Names accepted by [`ElectrodeMetal::from_name`].
    pub const KNOWN_NAMES: [&'static str; 4] = ["aluminium", "chromium", "gold", "copper"];

    /// Resistivity ρ (Ω·m). Bulk values at 20 °C: CRC *Handbook of Chemistry and Physics*,
    /// "Electrical resistivity of pure metals".
    pub fn resistivity_ohm_m(&self) -> f64 {
        match self {
            ElectrodeMetal::Aluminium => 2.65e-8,
            ElectrodeMetal::Chromium => 1.25e-7,
            ElectrodeMetal::Gold => 2.44e-8,
            ElectrodeMetal::Copper => 1.68e-8,
            ElectrodeMetal::Other { resistivity_ohm_m } => *resistivity_ohm_m,
        }
    }

    /// A named metal (`aluminium`/`aluminum`/`al`, `chromium`/`cr`, `gold`/`au`, `copper`/`cu`;
    /// case-insensitive), or `None`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name.trim().to_ascii_lowercase().as_str() {
            "aluminium" | "aluminum" | "al" => Some(ElectrodeMetal::Aluminium),
            "chromium" | "cr" => Some(ElectrodeMetal::Chromium),
            "gold" | "au" => Some(ElectrodeMetal::Gold),
            "copper" | "cu" => Some(ElectrodeMetal::Copper),
            _ => None,
        }
    }
}

/// `Ok` if `value` is finite and positive, else the named error.
pub(crate) fn require_positive(field: &'static str, value: f64) -> Result<(), WaveError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(WaveError::InvalidIdt {
            field,
            value,
            requirement: "finite and positive",
        })
    }
}

impl Idt {
    /// Checks every field: at least one finger pair; width, gap and aperture finite and positive;
    /// the metallisation's thickness and resistivity finite and positive.
    pub fn validate(&self) -> Result<(), WaveError> {
        if self.finger_pairs == 0 {
            return Err(WaveError::InvalidIdt {
                field: "finger_pairs",
                value: 0.0,
                requirement: "at least one finger pair",
            });
        }
        require_positive("finger_width_m", self.finger_width_m)?;
        require_positive("gap_m", self.gap_m)?;
        require_positive("aperture_m", self.aperture_m)?;
        if let Some(film) = &self.metallisation {
            require_positive("metallisation.thickness_m", film.thickness_m)?;
            require_positive(
                "metallisation.resistivity_ohm_m",
                film.metal.resistivity_ohm_m(),
            )?;
        }
        Ok(())
    }

    /// Electrode pitch p_e = w + g (m).
    pub fn electrode_pitch_m(&self) -> f64 {
        self.finger_width_m + self.gap_m
    }

    /// Transducer period λ₀ = 2(w + g) (m): the wavelength at synchronism.
    pub fn period_m(&self) -> f64 {
        2.0 * self.electrode_pitch_m()
    }

    /// Metallisation ratio η = w/(w + g).
    pub fn metallisation_ratio(&self) -> f64 {
        self.finger_width_m / self.electrode_pitch_m()
    }

    /// Series resistance of the fingers R_s = 2R_f/(3N_p), R_f = ρW/(w·h) (Ω); 0 without a
    /// metallisation.
    pub fn series_resistance_ohm(&self) -> f64 {
        self.finger_resistance_ohm() * 2.0 / (3.0 * f64::from(self.finger_pairs))
    }

    /// Resistance of one finger from bus bar to tip, R_f = ρW/(w·h) (Ω); 0 without a
    /// metallisation.
    pub fn finger_resistance_ohm(&self) -> f64 {
        self.metallisation.map_or(0.0, |film| {
            film.metal.resistivity_ohm_m() * self.aperture_m
                / (self.finger_width_m * film.thickness_m)
        })
    }
}
