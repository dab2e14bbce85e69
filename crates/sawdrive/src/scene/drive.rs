//! From volts to the wave: `wave.drive_voltage` on the `[stator.idt]` transducer, through the
//! interdigital-transducer model of crate `saw-wave` (`saw_wave::idt`), gives the scene's normal
//! amplitude, the electrical input power and the acoustic power launched towards the slider.
//!
//! Formula (crates/saw-wave/src/idt/mod.rs, items 1–8): f₀ = v_f/λ₀, λ₀ = 2(w + g); the
//! delta-function radiation admittance with Smith's G_a0 = 8K²f₀C_sWN_p², C_T = N_pC_sW from the
//! cut's ε∞; an ideal voltage source of peak V at the bus bars; P_in = ½Re(V·I*) = P_ac + P_Ω,
//! half of P_ac each way; |u_z| = √(P/(W·Π(f))) with Π the cut's power per beam width per |u_z|²
//! (the same flux `sawdrive wave` and the energy-conserving wave use). Sources: Smith et al.
//! 1969; Hartmann, Bell & Rosenfeld 1973; Morgan 2007 ch. 5, 8; Lakin 1974 (finger resistance).
//! Energy balance: P_in = 2P + P_Ω, and P, the power per direction, is what the wave of
//! amplitude |u_z| carries in a beam of the aperture's width; only that one direction drives the
//! slider, so mechanical output ≤ P ≤ ½P_in. Range of validity: N_p·K² ≪ 1 (reflections and
//! regeneration inside the transducer left out), near synchronism, no bulk waves, mass loading
//! or diffraction; outside it the model's caveats become scene warnings naming the key to
//! change (`stator.idt.finger_pairs`, `wave.frequency`, `stator.idt.metallisation`).

use std::sync::Mutex;

use motor::Transducer;
use saw_wave::idt::Caveat;
use saw_wave::{Cut, ElectrodeMetal, Idt, IdtResponse, IdtSubstrate, Metallisation};
use serde::Serialize;
use stick_slip::Warning;

use super::SceneError;
use super::file::{IdtFile, WaveFile};

/// The transducer's drive as the resolved scene carries it (SI); `sawdrive scene --resolve`
/// and `sawdrive wave` show it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Drive {
    /// Peak drive voltage V₀₋ₚ (`wave.drive_voltage`).
    pub drive_voltage_peak_v: f64,
    /// The transducer's geometry (`[stator.idt]`).
    pub transducer: Transducer,
    /// The finger film (`stator.idt.metallisation`), if given.
    pub metallisation: Option<FingerFilm>,
    /// Synchronous frequency f₀ = v_f/λ₀ (Hz).
    pub synchronous_frequency_hz: f64,
    /// (f − f₀)/f₀ at the scene's frequency.
    pub relative_detuning: f64,
    /// N_p·K²: the size of the reflections the model leaves out (trusted ≤ 0.1).
    pub np_k2: f64,
    /// Static capacitance C_T (F).
    pub capacitance_f: f64,
    /// Radiation conductance G_a at the scene's frequency (S).
    pub radiation_conductance_s: f64,
    /// Peak current from the source (A).
    pub current_peak_a: f64,
    /// Electrical input power P_in = ½Re(V·I*) (W).
    pub electrical_input_power_w: f64,
    /// Acoustic power launched each way, P = ½P_ac (W); one direction drives the slider.
    pub acoustic_power_per_direction_w: f64,
    /// Power heating the fingers (W).
    pub ohmic_power_w: f64,
    /// The launched wave's normal amplitude |u_z| (m): the scene's `wave.normal_amplitude_m`.
    pub normal_amplitude_m: f64,
    /// |u_z| the same voltage would launch at f₀ (m).
    pub normal_amplitude_at_synchronism_m: f64,
    /// The model's full response (admittance, powers, amplitudes, caveats): `sawdrive wave
    /// --json` prints it; the resolved scene keeps the figures above.
    #[serde(skip)]
    pub response: IdtResponse,
}

/// The finger film as resolved.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FingerFilm {
    /// The metal's name as given.
    pub metal: String,
    /// Its resistivity (Ω·m).
    pub resistivity_ohm_m: f64,
    /// Film thickness (m).
    pub thickness_m: f64,
}

fn invalid(field: &str, message: impl Into<String>) -> SceneError {
    SceneError::Invalid {
        field: field.to_owned(),
        message: message.into(),
    }
}

/// A length of the transducer: finite and > 0, else refused naming `field`.
fn positive_length(field: &str, value: f64) -> Result<f64, SceneError> {
    if value.is_finite() && value > 0.0 && value.is_normal() {
        Ok(value)
    } else {
        Err(invalid(
            field,
            format!("must be a finite length > 0, got {value:e} m"),
        ))
    }
}

/// The `saw_wave` transducer of `[stator.idt]`, every value checked at the edge (errors name the
/// scene key), and its film for the report.
fn transducer(file: &IdtFile) -> Result<(Idt, Transducer, Option<FingerFilm>), SceneError> {
    if file.finger_pairs == 0 {
        return Err(invalid(
            "stator.idt.finger_pairs",
            "need at least one finger pair",
        ));
    }
    let geometry = Transducer {
        finger_pairs: file.finger_pairs,
        finger_width_m: positive_length("stator.idt.finger_width", file.finger_width.0)?,
        gap_m: positive_length("stator.idt.gap", file.gap.0)?,
        aperture_m: positive_length("stator.idt.aperture", file.aperture.0)?,
    };
    let film = file
        .metallisation
        .as_ref()
        .map(|m| {
            let metal = ElectrodeMetal::from_name(&m.metal).ok_or_else(|| {
                invalid(
                    "stator.idt.metallisation.metal",
                    format!(
                        "unknown metal \"{}\": use one of {}",
                        m.metal,
                        ElectrodeMetal::KNOWN_NAMES.join(", ")
                    ),
                )
            })?;
            let thickness_m = positive_length("stator.idt.metallisation.thickness", m.thickness.0)?;
            Ok::<_, SceneError>((
                Metallisation { metal, thickness_m },
                FingerFilm {
                    metal: m.metal.trim().to_ascii_lowercase(),
                    resistivity_ohm_m: metal.resistivity_ohm_m(),
                    thickness_m,
                },
            ))
        })
        .transpose()?;
    let idt = Idt {
        finger_pairs: geometry.finger_pairs,
        finger_width_m: geometry.finger_width_m,
        gap_m: geometry.gap_m,
        aperture_m: geometry.aperture_m,
        metallisation: film.as_ref().map(|(m, _)| *m),
    };
    Ok((idt, geometry, film.map(|(_, f)| f)))
}

/// Substrates of this process, by crystal and Euler angles (a sweep resolves a scene many
/// times; the cut's wave is solved once).
type SolvedSubstrate = (String, [u64; 3], IdtSubstrate);
static SUBSTRATES: Mutex<Vec<SolvedSubstrate>> = Mutex::new(Vec::new());

/// What the transducer needs from `cut` (solved once per process); an error names `stator.cut`.
fn substrate(cut: &Cut) -> Result<IdtSubstrate, SceneError> {
    let e = cut.euler;
    let key = (
        cut.material.name.clone(),
        [e.phi_deg, e.theta_deg, e.psi_deg].map(f64::to_bits),
    );
    let cached = SUBSTRATES.lock().ok().and_then(|solved| {
        solved
            .iter()
            .find(|(name, bits, _)| (name, bits) == (&key.0, &key.1))
            .map(|(_, _, s)| s.clone())
    });
    if let Some(substrate) = cached {
        return Ok(substrate);
    }
    let substrate =
        IdtSubstrate::from_cut(cut).map_err(|e| invalid("stator.cut", e.to_string()))?;
    if let Ok(mut solved) = SUBSTRATES.lock() {
        solved.push((key.0, key.1, substrate.clone()));
    }
    Ok(substrate)
}

/// The scene key a caveat asks to change.
fn caveat_key(caveat: &Caveat) -> &'static str {
    match caveat {
        Caveat::StrongCoupling { .. } => "stator.idt.finger_pairs",
        Caveat::Detuned { .. } | Caveat::FarFromSynchronism { .. } => "wave.frequency",
        Caveat::LongFingers { .. } => "stator.idt.metallisation",
    }
}

/// Which of the two routes a scene takes to its amplitude.
enum Route<'a> {
    /// `wave.normal_amplitude` (m).
    Amplitude(f64),
    /// `wave.drive_voltage` (V) on `[stator.idt]`.
    Drive(f64, &'a IdtFile),
}

/// The route of `wave` with `idt`, or the refusal of a contradictory or incomplete pair.
fn route<'a>(wave: &WaveFile, idt: Option<&'a IdtFile>) -> Result<Route<'a>, SceneError> {
    match (wave.normal_amplitude, wave.drive_voltage, idt) {
        (Some(_), Some(_), _) => Err(invalid(
            "wave.normal_amplitude, wave.drive_voltage",
            "give one: the amplitude directly, or the drive voltage of the [stator.idt] \
                 transducer that launches it",
        )),
        (None, None, _) => Err(invalid(
            "wave.normal_amplitude",
            "missing: give wave.normal_amplitude, or wave.drive_voltage with [stator.idt]",
        )),
        (Some(a), None, None) => {
            super::positive::positive("wave.normal_amplitude", a.0).map(Route::Amplitude)
        }
        (Some(_), None, Some(_)) => Err(invalid(
            "stator.idt",
            "describes the transducer that turns wave.drive_voltage into the amplitude, and \
                 wave.normal_amplitude is given instead: give wave.drive_voltage or remove \
                 [stator.idt]",
        )),
        (None, Some(_), None) => Err(invalid(
            "wave.drive_voltage",
            "needs the transducer it drives: add a [stator.idt] section (finger_pairs, \
                 finger_width, gap, aperture), or give wave.normal_amplitude instead",
        )),
        (None, Some(v), Some(idt)) => Ok(Route::Drive(v.0, idt)),
    }
}

/// The normal amplitude of the scene's wave (m) and, with a drive voltage, the drive; the
/// transducer model's caveats are pushed onto `warnings`. Rules: `wave.normal_amplitude` or
/// `wave.drive_voltage` (both: refused naming both); a drive voltage needs `[stator.idt]`, and
/// `[stator.idt]` a drive voltage (it would change nothing); a drive voltage and a given beam
/// width `wave.aperture` other than the transducer's aperture are refused (the beam is the
/// transducer's).
pub fn normal_amplitude(
    wave: &WaveFile,
    idt: Option<&IdtFile>,
    cut: &Cut,
    frequency_hz: f64,
    warnings: &mut Vec<Warning>,
) -> Result<(f64, Option<Drive>), SceneError> {
    let (volts, idt) = match route(wave, idt)? {
        Route::Amplitude(a) => return Ok((a, None)),
        Route::Drive(volts, idt) => (volts, idt),
    };
    let volts = super::positive::positive("wave.drive_voltage", volts)?;
    let (model, transducer, metallisation) = transducer(idt)?;
    if let Some(beam) = wave.aperture
        && beam.0 != transducer.aperture_m
    {
        return Err(invalid(
            "wave.aperture",
            format!(
                "the beam is the transducer's: wave.aperture = {} m differs from \
                 stator.idt.aperture = {} m; give the same width or leave wave.aperture out",
                beam.0, transducer.aperture_m
            ),
        ));
    }
    let substrate = substrate(cut)?;
    let response = model
        .drive(&substrate, volts, frequency_hz)
        .map_err(|e| invalid("stator.idt", e.to_string()))?;
    let amplitude = super::positive::positive("wave.drive_voltage", response.amplitude_uz_m)?;
    let a = &response.admittance;
    warnings.extend(
        a.caveats
            .iter()
            .map(|c| Warning::new(caveat_key(c), format!("transducer model: {c}"))),
    );
    let drive = Drive {
        drive_voltage_peak_v: volts,
        transducer,
        metallisation,
        synchronous_frequency_hz: a.synchronous_frequency_hz,
        relative_detuning: a.relative_detuning,
        np_k2: a.np_k2,
        capacitance_f: a.capacitance_f,
        radiation_conductance_s: a.radiation_conductance_s,
        current_peak_a: response.current_peak_a,
        electrical_input_power_w: response.input_power_w,
        acoustic_power_per_direction_w: response.acoustic_power_per_direction_w,
        ohmic_power_w: response.ohmic_power_w,
        normal_amplitude_m: amplitude,
        normal_amplitude_at_synchronism_m: response.amplitude_uz_at_synchronism_m,
        response,
    };
    Ok((amplitude, Some(drive)))
}
