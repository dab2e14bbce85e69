//! The transducer's admittance at one frequency and its response to one drive voltage.
//!
//! Formula: items 3–8 of the [`crate::idt`] module doc (delta-function model with Smith's
//! G_a0 = 8K²f₀C_sWN_p², Lakin's finger resistance, an ideal voltage source of peak V, and the
//! crate's power flux for the amplitude). Source: as cited there. Range of validity: N_p·K² ≤
//! [`WEAK_COUPLING_LIMIT`], |f/f₀ − 1| ≤ [`SYNCHRONISM_RANGE`], ωR_f·C_T/N_p ≤
//! [`LUMPED_FINGER_LIMIT`]; outside, the results are returned with a [`Caveat`] naming the limit.

use std::f64::consts::PI;
use std::fmt;

use super::substrate::complete_elliptic_k;
use super::{
    DETUNED_CONDUCTANCE_RATIO, Idt, IdtSubstrate, LUMPED_FINGER_LIMIT, REFERENCE_IMPEDANCE_OHM,
    SYNCHRONISM_RANGE, WEAK_COUPLING_LIMIT, require_positive,
};
use crate::error::WaveError;
use crate::stroh::C64;

/// Below this |x| the difference x − sin x is summed from its Taylor series (no cancellation).
const SERIES_BELOW: f64 = 1.0;

/// A condition under which the numbers are returned but the model is outside its validity.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum Caveat {
    /// N_p·K² above [`WEAK_COUPLING_LIMIT`]: electrode reflections and regeneration inside the
    /// transducer (left out) change G_a, B_a and the amplitude by a factor of order one.
    StrongCoupling {
        /// N_p·K².
        np_k2: f64,
    },
    /// The drive frequency lies where G_a(f) < ½G_a0 (outside the half-power band).
    Detuned {
        /// (f − f₀)/f₀.
        relative_detuning: f64,
        /// G_a(f)/G_a0.
        conductance_ratio: f64,
        /// 1/N_p: the first zeros of G_a lie at f₀(1 ± 1/N_p).
        first_zero_relative: f64,
    },
    /// |f/f₀ − 1| above [`SYNCHRONISM_RANGE`]: harmonics and the element factor are left out.
    FarFromSynchronism {
        /// (f − f₀)/f₀.
        relative_detuning: f64,
    },
    /// ωR_f·C_T/N_p above [`LUMPED_FINGER_LIMIT`]: the fingers are a distributed RC line, not
    /// the lumped 2R_f/(3N_p).
    LongFingers {
        /// ωR_f·C_T/N_p.
        finger_rc_phase: f64,
    },
}

impl fmt::Display for Caveat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Caveat::StrongCoupling { np_k2 } => write!(
                f,
                "N_p·K² = {np_k2:.3} > {WEAK_COUPLING_LIMIT}: electrode reflections and \
                 regeneration inside the transducer, left out of the model, are not small"
            ),
            Caveat::Detuned {
                relative_detuning,
                conductance_ratio,
                first_zero_relative,
            } => write!(
                f,
                "drive {:+.2} % off the synchronous frequency: radiation conductance at \
                 {:.1} % of its peak (first zeros at ±{:.2} %)",
                100.0 * relative_detuning,
                100.0 * conductance_ratio,
                100.0 * first_zero_relative
            ),
            Caveat::FarFromSynchronism { relative_detuning } => write!(
                f,
                "drive {:+.1} % off the synchronous frequency: beyond ±{:.0} % the \
                 delta-function model (no element factor, no harmonics) is not trusted",
                100.0 * relative_detuning,
                100.0 * SYNCHRONISM_RANGE
            ),
            Caveat::LongFingers { finger_rc_phase } => write!(
                f,
                "finger RC phase ωR_f·C_T/N_p = {finger_rc_phase:.3} > {LUMPED_FINGER_LIMIT}: \
                 the lumped finger resistance underestimates the loss"
            ),
        }
    }
}

/// The transducer's electrical admittance at one frequency.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct IdtAdmittance {
    /// Frequency f (Hz).
    pub frequency_hz: f64,
    /// Transducer period λ₀ = 2(w + g) (m).
    pub period_m: f64,
    /// Metallisation ratio η = w/(w + g).
    pub metallisation_ratio: f64,
    /// f₀ = v_f/λ₀ (Hz), free-surface velocity.
    pub synchronous_frequency_hz: f64,
    /// v_m/λ₀ (Hz), metallized-surface velocity.
    pub synchronous_frequency_metallized_hz: f64,
    /// (f − f₀)/f₀.
    pub relative_detuning: f64,
    /// C_s = ε∞·K(sin πη/2)/K(cos πη/2) (F/m, per finger pair per metre of aperture).
    pub capacitance_per_pair_per_length_f_per_m: f64,
    /// C_T = N_p·C_s·W (F).
    pub capacitance_f: f64,
    /// G_a0 = 8K²f₀C_sWN_p² (S).
    pub radiation_conductance_synchronous_s: f64,
    /// G_a(f) (S).
    pub radiation_conductance_s: f64,
    /// B_a(f) (S).
    pub radiation_susceptance_s: f64,
    /// ωC_T (S).
    pub capacitive_susceptance_s: f64,
    /// R_s = 2R_f/(3N_p) (Ω).
    pub series_resistance_ohm: f64,
    /// Z = R_s + 1/(G_a + j(B_a + ωC_T)) as [re, im] (Ω).
    pub impedance_ohm: [f64; 2],
    /// N_p·K², the size of the effects left out (module doc).
    pub np_k2: f64,
    /// Radiation Q at f₀: 2πf₀C_T/G_a0 = π/(4N_pK²).
    pub radiation_q: f64,
    /// Conditions outside the model's validity at this frequency.
    pub caveats: Vec<Caveat>,
}

impl IdtAdmittance {
    /// Z (Ω) as a complex number.
    pub fn impedance(&self) -> C64 {
        C64::new(self.impedance_ohm[0], self.impedance_ohm[1])
    }
}

/// The transducer driven by an ideal voltage source of peak amplitude V at frequency f.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct IdtResponse {
    /// Drive voltage V, peak (V₀₋ₚ).
    pub drive_voltage_peak_v: f64,
    /// The admittance at the drive frequency.
    pub admittance: IdtAdmittance,
    /// |I|, peak current from the source (A).
    pub current_peak_a: f64,
    /// |V_t|, peak voltage across the transducer behind R_s (V).
    pub transducer_voltage_peak_v: f64,
    /// P_in = ½Re(V·I*) (W): the real power the source delivers.
    pub input_power_w: f64,
    /// ½Im(V·I*) (var; negative = capacitive): stored and returned each cycle.
    pub reactive_power_var: f64,
    /// P_ac = ½|V_t|²G_a (W), both directions.
    pub acoustic_power_w: f64,
    /// P = P_ac/2 (W): the wave launched towards the slider.
    pub acoustic_power_per_direction_w: f64,
    /// P_Ω = ½|I|²R_s (W) heating the fingers.
    pub ohmic_power_w: f64,
    /// Forward power of a 50 Ω amplifier without matching network that puts V on the
    /// transducer (W).
    pub forward_power_unmatched_w: f64,
    /// |Γ| = |(Z − Z₀)/(Z + Z₀)| against Z₀ = 50 Ω.
    pub reflection_coefficient_abs: f64,
    /// |u_z| of the launched wave (m).
    pub amplitude_uz_m: f64,
    /// |u_x| of the launched wave (m).
    pub amplitude_ux_m: f64,
    /// ω|u_x|, the peak tangential surface speed (m/s).
    pub surface_speed_x_m_per_s: f64,
    /// |u_z| the same voltage would launch at f₀ (m).
    pub amplitude_uz_at_synchronism_m: f64,
}

impl Idt {
    /// The admittance at `frequency_hz` (Hz, > 0) on `substrate`.
    pub fn admittance(
        &self,
        substrate: &IdtSubstrate,
        frequency_hz: f64,
    ) -> Result<IdtAdmittance, WaveError> {
        self.validate()?;
        require_positive("frequency_hz", frequency_hz)?;
        Ok(self.admittance_unchecked(substrate, frequency_hz))
    }

    /// The response to a drive of peak voltage `drive_voltage_peak_v` (V₀₋ₚ, > 0) at
    /// `frequency_hz` (Hz, > 0) from an ideal voltage source at the bus bars.
    pub fn drive(
        &self,
        substrate: &IdtSubstrate,
        drive_voltage_peak_v: f64,
        frequency_hz: f64,
    ) -> Result<IdtResponse, WaveError> {
        self.validate()?;
        require_positive("drive_voltage_peak_v", drive_voltage_peak_v)?;
        require_positive("frequency_hz", frequency_hz)?;
        let admittance = self.admittance_unchecked(substrate, frequency_hz);
        let at_f0 = self.admittance_unchecked(substrate, admittance.synchronous_frequency_hz);
        let books = Books::new(&admittance, drive_voltage_peak_v);
        let p_dir = 0.5 * books.acoustic_power_w;
        let amplitude_uz_m = self.amplitude_uz_m(substrate, p_dir, frequency_hz);
        let sync_p_dir = 0.5 * Books::new(&at_f0, drive_voltage_peak_v).acoustic_power_w;
        let amplitude_ux_m = substrate.surface_ux_over_uz_abs * amplitude_uz_m;
        Ok(IdtResponse {
            drive_voltage_peak_v,
            current_peak_a: books.current.norm(),
            transducer_voltage_peak_v: books.transducer_voltage.norm(),
            input_power_w: books.input_power_w,
            reactive_power_var: books.reactive_power_var,
            acoustic_power_w: books.acoustic_power_w,
            acoustic_power_per_direction_w: p_dir,
            ohmic_power_w: books.ohmic_power_w,
            forward_power_unmatched_w: books.forward_power_w,
            reflection_coefficient_abs: books.reflection_abs,
            amplitude_uz_m,
            amplitude_ux_m,
            surface_speed_x_m_per_s: 2.0 * PI * frequency_hz * amplitude_ux_m,
            amplitude_uz_at_synchronism_m: self.amplitude_uz_m(
                substrate,
                sync_p_dir,
                at_f0.synchronous_frequency_hz,
            ),
            admittance,
        })
    }

    /// |u_z| = √(P/(W·Π(f))) for a wave of power `power_w` across the aperture.
    fn amplitude_uz_m(&self, substrate: &IdtSubstrate, power_w: f64, frequency_hz: f64) -> f64 {
        let per_width_per_uz2 = substrate.power_per_width_per_uz2_per_hz_j_per_m3 * frequency_hz;
        (power_w / (self.aperture_m * per_width_per_uz2)).sqrt()
    }

    fn admittance_unchecked(&self, substrate: &IdtSubstrate, frequency_hz: f64) -> IdtAdmittance {
        let np = f64::from(self.finger_pairs);
        let period_m = self.period_m();
        let eta = self.metallisation_ratio();
        let f0 = substrate.phase_velocity_free_m_per_s / period_m;
        let detuning = (frequency_hz - f0) / f0;
        let cs = substrate.effective_permittivity_f_per_m
            * complete_elliptic_k((0.5 * PI * eta).sin())
            / complete_elliptic_k((0.5 * PI * eta).cos());
        let capacitance_f = np * cs * self.aperture_m;
        let ga0 = 8.0 * substrate.coupling_k2 * f0 * cs * self.aperture_m * np * np;
        let (g_ratio, b_ratio) = radiation_admittance_ratio(self.finger_pairs, detuning);
        let (ga, ba) = (ga0 * g_ratio, ga0 * b_ratio);
        let omega_c = 2.0 * PI * frequency_hz * capacitance_f;
        let rs = self.series_resistance_ohm();
        let z = C64::new(rs, 0.0) + C64::new(ga, ba + omega_c).inv();
        let np_k2 = np * substrate.coupling_k2;
        let finger_rc_phase = omega_c * self.finger_resistance_ohm() / np;
        IdtAdmittance {
            frequency_hz,
            period_m,
            metallisation_ratio: eta,
            synchronous_frequency_hz: f0,
            synchronous_frequency_metallized_hz: substrate.phase_velocity_metallized_m_per_s
                / period_m,
            relative_detuning: detuning,
            capacitance_per_pair_per_length_f_per_m: cs,
            capacitance_f,
            radiation_conductance_synchronous_s: ga0,
            radiation_conductance_s: ga,
            radiation_susceptance_s: ba,
            capacitive_susceptance_s: omega_c,
            series_resistance_ohm: rs,
            impedance_ohm: [z.re, z.im],
            np_k2,
            radiation_q: 2.0 * PI * f0 * capacitance_f / ga0,
            caveats: caveats(np_k2, detuning, g_ratio, np, finger_rc_phase),
        }
    }
}

fn caveats(
    np_k2: f64,
    relative_detuning: f64,
    conductance_ratio: f64,
    np: f64,
    finger_rc_phase: f64,
) -> Vec<Caveat> {
    let mut caveats = Vec::new();
    if np_k2 > WEAK_COUPLING_LIMIT {
        caveats.push(Caveat::StrongCoupling { np_k2 });
    }
    if conductance_ratio < DETUNED_CONDUCTANCE_RATIO {
        caveats.push(Caveat::Detuned {
            relative_detuning,
            conductance_ratio,
            first_zero_relative: 1.0 / np,
        });
    }
    if relative_detuning.abs() > SYNCHRONISM_RANGE {
        caveats.push(Caveat::FarFromSynchronism { relative_detuning });
    }
    if finger_rc_phase > LUMPED_FINGER_LIMIT {
        caveats.push(Caveat::LongFingers { finger_rc_phase });
    }
    caveats
}

/// The power books of one drive: currents, voltages and powers.
struct Books {
    current: C64,
    transducer_voltage: C64,
    input_power_w: f64,
    reactive_power_var: f64,
    acoustic_power_w: f64,
    ohmic_power_w: f64,
    forward_power_w: f64,
    reflection_abs: f64,
}

impl Books {
    fn new(admittance: &IdtAdmittance, voltage_peak_v: f64) -> Self {
        let v = C64::new(voltage_peak_v, 0.0);
        let y_t = C64::new(
            admittance.radiation_conductance_s,
            admittance.radiation_susceptance_s + admittance.capacitive_susceptance_s,
        );
        let z = admittance.impedance();
        let current = v / z;
        let transducer_voltage = current / y_t;
        let complex_power = 0.5 * v * current.conj();
        let z0 = C64::new(REFERENCE_IMPEDANCE_OHM, 0.0);
        let gamma = (z - z0) / (z + z0);
        Self {
            current,
            transducer_voltage,
            input_power_w: complex_power.re,
            reactive_power_var: complex_power.im,
            acoustic_power_w: 0.5
                * transducer_voltage.norm_sqr()
                * admittance.radiation_conductance_s,
            ohmic_power_w: 0.5 * current.norm_sqr() * admittance.series_resistance_ohm,
            forward_power_w: voltage_peak_v * voltage_peak_v
                / (2.0 * REFERENCE_IMPEDANCE_OHM * (C64::new(1.0, 0.0) + gamma).norm_sqr()),
            reflection_abs: gamma.norm(),
        }
    }
}

/// G_a/G_a0 and B_a/G_a0 of the delta-function model of `finger_pairs` pairs at relative detuning
/// (f − f₀)/f₀: with δ = π(f − f₀)/f₀ and M = 2N_p, sin²(Mδ/2)/(M² sin²(δ/2)) and
/// −(M sin δ − sin Mδ)/(2M² sin²(δ/2)), the closed forms of
/// (1/M²)·Σₙ Σₘ (−1)ⁿ⁺ᵐ e^{−j(π + δ)|n − m|}. Both are 2π-periodic in δ (the model repeats at the
/// odd harmonics) and evaluated without cancellation near δ = 0.
pub fn radiation_admittance_ratio(finger_pairs: u32, relative_detuning: f64) -> (f64, f64) {
    let m = 2.0 * f64::from(finger_pairs);
    let delta = PI * relative_detuning;
    let delta = delta - 2.0 * PI * (delta / (2.0 * PI)).round();
    let half_sin = (0.5 * delta).sin();
    if half_sin == 0.0 {
        return (1.0, 0.0);
    }
    let dirichlet = (0.5 * m * delta).sin() / (m * half_sin);
    let numerator = x_minus_sin(m * delta) - m * x_minus_sin(delta);
    (
        dirichlet * dirichlet,
        -numerator / (2.0 * m * m * half_sin * half_sin),
    )
}

/// x − sin x, from its Taylor series for |x| < [`SERIES_BELOW`] (relative accuracy ~1e-16).
fn x_minus_sin(x: f64) -> f64 {
    if x.abs() >= SERIES_BELOW {
        return x - x.sin();
    }
    // x³/3! − x⁵/5! + x⁷/7! − …
    let x2 = x * x;
    let mut term = x * x2 / 6.0;
    let mut sum = term;
    let mut k = 3.0;
    while term.abs() > 1e-18 * sum.abs() {
        term *= -x2 / ((k + 1.0) * (k + 2.0));
        sum += term;
        k += 2.0;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn x_minus_sin_series_meets_the_direct_form_at_the_switch() {
        for x in [0.999_999, -0.7, 0.3] {
            let series = x_minus_sin(x);
            let direct = x - f64::sin(x);
            assert!(
                (series / direct - 1.0).abs() < 1e-13,
                "x − sin x at {x}: series {series} vs direct {direct}"
            );
        }
        // Deep in the series range: x³/6 to leading order.
        let x: f64 = 1e-6;
        assert!((x_minus_sin(x) / (x * x * x / 6.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn admittance_ratio_is_one_and_zero_at_synchronism() {
        for pairs in [1, 2, 20, 500] {
            assert_eq!(radiation_admittance_ratio(pairs, 0.0), (1.0, 0.0));
            // Near f₀: B_a/G_a0 → −δ(M² − 1)/(3M), M = 2N_p, δ = π(f − f₀)/f₀.
            let (g, b) = radiation_admittance_ratio(pairs, 1e-12);
            let m = 2.0 * f64::from(pairs);
            let slope = -PI * 1e-12 * (m * m - 1.0) / (3.0 * m);
            assert!((g - 1.0).abs() < 1e-12, "Np = {pairs}: G_a/G_a0 = {g}");
            assert!(
                (b / slope - 1.0).abs() < 1e-9,
                "Np = {pairs}: B_a/G_a0 = {b} vs {slope}"
            );
        }
    }
}
