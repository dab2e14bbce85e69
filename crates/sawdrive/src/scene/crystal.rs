//! The stator's crystal cut (`stator.cut`) and its Rayleigh wave, solved by crate `saw-wave`:
//! the values `wave.phase_velocity = "auto"` and `wave.tangential_* = "auto"` take, and the
//! check of given values against them.
//!
//! Formula: the free-surface phase velocity, |u_x/u_z| at the free surface and the power per
//! unit beam width P = (P/(f|u_z|²))·f·A_n² of the anisotropic partial-wave solution
//! (`saw_wave::RayleighWave`, crates/saw-wave/README.md). Range of validity: the crate's (a
//! non-leaky surface wave of a lossless crystal, small amplitudes).

use std::sync::Mutex;

use saw_wave::{Cut, EulerAngles, Material as Crystal, WaveError, materials};
use serde::Serialize;
use stick_slip::Warning;

use super::SceneError;
use super::file::{CutSpec, MaterialSpec};
use motor::StatorCut;

/// A given wave value (`wave.phase_velocity`, the tangential/normal amplitude ratio) that
/// differs from the stator cut's by more than this fraction is reported as a warning.
pub const CUT_MISMATCH_WARNING_FRACTION: f64 = 0.02;

/// The Rayleigh wave of the stator's cut: the numbers the scene and `sawdrive wave` use.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CrystalWave {
    /// Phase velocity on the electrically free surface (m/s).
    pub phase_velocity_free_m_per_s: f64,
    /// Phase velocity on the metallized surface (m/s).
    pub phase_velocity_metallized_m_per_s: f64,
    /// K² = 2(v_free − v_met)/v_free.
    pub coupling_k2: f64,
    /// |u_x/u_z| at the free surface: the tangential/normal amplitude ratio of the orbit.
    pub displacement_ratio_ux_over_uz: f64,
    /// arg(u_x/u_z) at the free surface (degrees; +90°: retrograde orbit).
    pub displacement_phase_ux_over_uz_deg: f64,
    /// Power per unit beam width per hertz per |u_z|² (J/m³): P/width = this · f · A_n².
    pub power_per_width_per_hz_per_m2_j_per_m3: f64,
}

impl CrystalWave {
    /// Power carried per unit beam width (W/m) at normal amplitude `amplitude_uz_m` (m) and
    /// frequency `frequency_hz` (Hz).
    pub fn power_per_width_w_per_m(&self, amplitude_uz_m: f64, frequency_hz: f64) -> f64 {
        self.power_per_width_per_hz_per_m2_j_per_m3 * frequency_hz * amplitude_uz_m * amplitude_uz_m
    }
}

/// A crystal of `stator.cut = { crystal, euler }`: its name and the constructor of its
/// constant set.
type NamedCrystal = (&'static str, fn() -> Crystal);

/// The crystals of `stator.cut = { crystal, euler }`.
const CRYSTALS: [NamedCrystal; 3] = [
    ("linbo3", materials::lithium_niobate_kovacs_1990),
    ("linbo3-warner", materials::lithium_niobate_warner_1967),
    ("quartz", materials::quartz_bechmann_1958),
];

fn invalid(message: impl Into<String>) -> SceneError {
    SceneError::Invalid {
        field: "stator.cut".into(),
        message: message.into(),
    }
}

/// The `saw_wave` cut of a scene's `stator.cut`; `stator_material` gives the default crystal
/// of Euler angles (`linbo3` when the stator is LiNbO3).
pub fn wave_cut(spec: &CutSpec, stator_material: &MaterialSpec) -> Result<Cut, SceneError> {
    match spec {
        CutSpec::Named(name) => Cut::from_name(name).map_err(|e| invalid(e.to_string())),
        CutSpec::Euler(e) => {
            let crystal = match (&e.crystal, stator_material) {
                (Some(c), _) => c.trim().to_ascii_lowercase(),
                (None, MaterialSpec::Named(m))
                    if contact_springs::Material::named(m).is_some_and(|m| {
                        m.name == contact_springs::Material::lithium_niobate().name
                    }) =>
                {
                    "linbo3".to_owned()
                }
                (None, _) => {
                    return Err(invalid(
                        "Euler angles need the crystal: give crystal = \"linbo3\", \"linbo3-warner\" or \"quartz\"",
                    ));
                }
            };
            let material = CRYSTALS
                .iter()
                .find(|(name, _)| *name == crystal)
                .map(|(_, material)| material())
                .ok_or_else(|| {
                    let names: Vec<_> = CRYSTALS.iter().map(|(n, _)| format!("\"{n}\"")).collect();
                    invalid(format!(
                        "unknown crystal \"{crystal}\": use {}",
                        names.join(", ")
                    ))
                })?;
            let [phi, theta, psi] = e.euler;
            Ok(Cut::new(
                format!("{crystal} euler"),
                material,
                EulerAngles::new(phi, theta, psi),
            ))
        }
    }
}

/// Solved cuts of this process, by crystal and Euler angles: a scene resolves many times (a
/// sweep's points), the wave of a cut once.
type Solved = (String, [u64; 3], Result<CrystalWave, WaveError>);
static SOLVED: Mutex<Vec<Solved>> = Mutex::new(Vec::new());

/// The description of `cut` for the motor and its solved wave; an error names `stator.cut`.
pub fn solve(cut: &Cut) -> Result<(StatorCut, CrystalWave), SceneError> {
    let e = cut.euler;
    let euler_deg = [e.phi_deg, e.theta_deg, e.psi_deg];
    let key = (cut.material.name.clone(), euler_deg.map(f64::to_bits));
    let cached = SOLVED.lock().ok().and_then(|solved| {
        solved
            .iter()
            .find(|(name, bits, _)| (name, bits) == (&key.0, &key.1))
            .map(|(_, _, wave)| wave.clone())
    });
    let wave = cached.unwrap_or_else(|| {
        let wave = cut.solve().map(|w| CrystalWave {
            phase_velocity_free_m_per_s: w.phase_velocity_free_m_per_s,
            phase_velocity_metallized_m_per_s: w.phase_velocity_metallized_m_per_s,
            coupling_k2: w.coupling_k2,
            displacement_ratio_ux_over_uz: w.surface_ux_over_uz_abs,
            displacement_phase_ux_over_uz_deg: w.surface_ux_over_uz_phase_deg,
            power_per_width_per_hz_per_m2_j_per_m3: w.power_flux.total_w_per_m_per_m2_per_hz(),
        });
        if let Ok(mut solved) = SOLVED.lock() {
            solved.push((key.0, key.1, wave.clone()));
        }
        wave
    });
    let wave = wave.map_err(|e| invalid(e.to_string()))?;
    let description = StatorCut {
        name: cut.name.clone(),
        crystal: cut.material.name.clone(),
        euler_deg,
    };
    Ok((description, wave))
}

/// A warning when `given` differs from the cut's value `of_cut` by more than
/// [`CUT_MISMATCH_WARNING_FRACTION`]; `what` names the quantity, `shown` formats a value.
pub fn mismatch(
    key: &str,
    what: &str,
    given: f64,
    of_cut: f64,
    cut: &str,
    shown: impl Fn(f64) -> String,
) -> Option<Warning> {
    let difference = given / of_cut - 1.0;
    (difference.abs() > CUT_MISMATCH_WARNING_FRACTION).then(|| {
        Warning::new(
            key,
            format!(
                "the given {what} {} differs by {:+.1} % from the {} of the stator's cut {cut} \
                 (more than {} %): give \"auto\" to use the cut's value, or check stator.cut",
                shown(given),
                100.0 * difference,
                shown(of_cut),
                100.0 * CUT_MISMATCH_WARNING_FRACTION
            ),
        )
    })
}

/// A warning when a built-in `stator.material` is not the crystal of `stator.cut` (the contact
/// springs then use another substrate's elastic constants than the wave's). A material given
/// by its constants is the user's statement of the crystal's isotropic equivalent: no warning.
pub fn material_mismatch(cut: &Cut, stator_material: &MaterialSpec) -> Option<Warning> {
    let MaterialSpec::Named(name) = stator_material else {
        return None;
    };
    let stator = contact_springs::Material::named(name)?;
    let lithium_niobate = contact_springs::Material::lithium_niobate().name;
    let same = stator.name == lithium_niobate && cut.material.name.starts_with("LiNbO3");
    (!same).then(|| {
        Warning::new(
            "stator.material",
            format!(
                "\"{name}\" is not the crystal of stator.cut {} ({}): the contact springs use \
                 {name}'s elastic constants, the wave the cut's; give stator.material as a table \
                 of the crystal's isotropic constants",
                cut.name, cut.material.name
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::super::{Scene, SceneError, load_scene_text};
    use super::*;

    fn scene(overrides: &[&str]) -> Result<Scene, SceneError> {
        let overrides: Vec<String> = overrides.iter().map(|s| (*s).to_owned()).collect();
        load_scene_text(None, &overrides)
    }

    fn field_error(overrides: &[&str]) -> (String, String) {
        match scene(overrides) {
            Err(SceneError::Invalid { field, message }) => (field, message),
            other => panic!("{overrides:?} should be refused naming a key, got {other:?}"),
        }
    }

    #[test]
    fn the_stator_cut_reaches_the_motor_and_its_wave() {
        let s = scene(&["stator.cut=yz-linbo3", "wave.phase_velocity=auto"]).unwrap();
        assert_eq!(s.motor.stator_cut.name, "yz-linbo3");
        assert_eq!(s.motor.stator_cut.euler_deg, [0.0, 90.0, 90.0]);
        assert_eq!(s.motor.stator_cut.crystal, "LiNbO3 (Kovacs et al. 1990)");
        let v = s.crystal_wave.phase_velocity_free_m_per_s;
        assert!((v / 3495.0 - 1.0).abs() < 1e-3, "Y-Z free velocity {v}");
        assert_eq!(
            s.motor.wave.phase_velocity_m_per_s, v,
            "auto: the cut's velocity"
        );
        assert_eq!(s.phase_velocity_source, "cut");
    }

    #[test]
    fn the_default_scene_keeps_its_given_wave_within_two_percent_of_the_cut() {
        let s = scene(&[]).unwrap();
        assert_eq!(s.motor.stator_cut, StatorCut::paper());
        assert_eq!(
            s.motor.wave.phase_velocity_m_per_s, 3979.0,
            "given, unchanged"
        );
        assert_eq!(s.motor.wave.crest_speed_m_per_s(), 1.1, "given, unchanged");
        assert_eq!(s.motor.wave.aperture_m, 9e-3);
        assert_eq!(
            (
                s.phase_velocity_source.as_str(),
                s.tangential_amplitude_source.as_str()
            ),
            ("given", "given")
        );
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
        // 3979 m/s against the cut's 3995.6 m/s: −0.4 %; A_t/A_n 0.911 against 0.898: +1.4 %.
        let w = &s.crystal_wave;
        let velocity = 3979.0 / w.phase_velocity_free_m_per_s - 1.0;
        assert!((-0.005..-0.003).contains(&velocity), "{velocity}");
        let wave = &s.motor.wave;
        let ratio =
            wave.tangential_amplitude_m / wave.normal_amplitude_m / w.displacement_ratio_ux_over_uz
                - 1.0;
        assert!((0.010..0.020).contains(&ratio), "{ratio}");
    }

    #[test]
    fn auto_tangential_amplitude_is_the_cut_ratio_times_the_normal_amplitude() {
        for key in [
            "wave.tangential_amplitude=auto",
            "wave.tangential_velocity=auto",
        ] {
            let s = scene(&[key, "wave.normal_amplitude=10nm"]).unwrap();
            let expected = s.crystal_wave.displacement_ratio_ux_over_uz * 10e-9;
            assert_eq!(s.motor.wave.tangential_amplitude_m, expected, "{key}");
            assert_eq!(s.tangential_amplitude_source, "cut", "{key}");
        }
    }

    #[test]
    fn a_given_value_more_than_two_percent_off_the_cut_is_a_warning_naming_its_key() {
        let s = scene(&["wave.phase_velocity=3800m/s"]).unwrap();
        assert_eq!(s.motor.wave.phase_velocity_m_per_s, 3800.0, "kept as given");
        assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
        assert_eq!(s.warnings[0].parameter, "wave.phase_velocity");
        assert!(
            s.warnings[0].message.contains("-4.9 %"),
            "{}",
            s.warnings[0].message
        );
        let s = scene(&["wave.tangential_amplitude=10nm"]).unwrap();
        assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
        assert_eq!(s.warnings[0].parameter, "wave.tangential_amplitude");
    }

    #[test]
    fn a_beam_narrower_than_the_post_array_is_a_warning_and_a_non_positive_one_refused() {
        let s = scene(&["wave.aperture=3mm"]).unwrap();
        assert_eq!(s.motor.wave.aperture_m, 3e-3);
        assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
        assert_eq!(s.warnings[0].parameter, "wave.aperture");
        for bad in ["wave.aperture=0mm", "wave.aperture=-9mm"] {
            assert_eq!(field_error(&[bad]).0, "wave.aperture", "{bad}");
        }
    }

    #[test]
    fn euler_angles_of_a_named_cut_give_its_wave() {
        let named = scene(&[]).unwrap();
        let euler = scene(&["stator.cut={ euler = [0, 38, 0] }"]).unwrap();
        assert_eq!(
            euler.crystal_wave, named.crystal_wave,
            "LiNbO3 stator: Kovacs constants"
        );
        assert_eq!(euler.motor.stator_cut.euler_deg, [0.0, 38.0, 0.0]);
        let quartz =
            scene(&["stator.cut={ crystal = \"quartz\", euler = [0, 132.75, 0] }"]).unwrap();
        let st_x = scene(&["stator.cut=st-x-quartz"]).unwrap();
        assert_eq!(quartz.crystal_wave, st_x.crystal_wave);
        assert_eq!(
            st_x.warnings[0].parameter, "stator.material",
            "a LiNbO3 stator under a quartz cut is reported"
        );
    }

    #[test]
    fn bad_cuts_are_refused_naming_stator_cut() {
        let (field, message) = field_error(&["stator.cut=36yx-litao3"]);
        assert_eq!(field, "stator.cut");
        for name in Cut::KNOWN_NAMES {
            assert!(message.contains(name), "{message} lists {name}");
        }
        // LiNbO3 at (0°, −30°, 90°): the wave is leaky (crates/saw-wave tests).
        let (field, message) = field_error(&["stator.cut={ euler = [0, -30, 90] }"]);
        assert_eq!(field, "stator.cut");
        assert!(message.contains("no surface wave"), "{message}");
        let (field, message) =
            field_error(&["stator.material=si", "stator.cut={ euler = [0, 38, 0] }"]);
        assert_eq!(field, "stator.cut");
        assert!(message.contains("crystal"), "{message}");
        let (field, message) =
            field_error(&["stator.cut={ crystal = \"gan\", euler = [0, 0, 0] }"]);
        assert_eq!(
            (field.as_str(), message.contains("quartz")),
            ("stator.cut", true)
        );
    }
}
