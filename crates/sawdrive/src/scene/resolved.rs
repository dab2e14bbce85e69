//! The resolved scene: SI units, unit in every field name, every value checked. The motor
//! resolves into the one description every stage shares ([`motor::Motor`]); the settings into
//! the libraries' own choices ([`ModelChoice`], [`IntegratorKind`], [`VerticalModel`],
//! [`StatorModel`]), so that no enum is mirrored here.

use contact_springs::Material;
use motor::{Friction, Imperfections, Load, Motor, PostArray, PreloadMechanism, SliderBody, Wave};
use serde::Serialize;
use static_contact::{FemSolver, StatorModel};
use stick_slip::{IntegratorKind, ModelChoice, VerticalModel, Warning};

use super::crystal::{self, CrystalWave};
use super::drive::{self, Drive};
use super::file::{
    ContactFile, CustomMaterial, FrictionFile, LoadFile, LumpedFile, MaterialSpec, ModelFile,
    PostsFile, SceneFile, StaticFile, WaveFile,
};
use super::positive::positive;
use super::quantity::{AutoOr, EffectiveRatio};
use super::shape;
use super::{SceneError, limits};
use crate::units::{Dimension, format_quantity};

/// One motor and how to simulate it, in SI units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scene {
    pub name: String,
    pub description: String,
    /// The motor (its fields appear at the top level of the scene's JSON).
    #[serde(flatten)]
    pub motor: Motor,
    /// Where `slider.mass_kg` came from: `geometry` (ρ·volume) or `given`.
    pub slider_mass_source: String,
    /// The Rayleigh wave of the stator's cut (`stator.cut`), solved from the crystal constants.
    pub crystal_wave: CrystalWave,
    /// Where `wave.phase_velocity_m_per_s` came from: `cut` (`"auto"`) or `given`.
    pub phase_velocity_source: String,
    /// Where `wave.tangential_amplitude_m` came from: `cut` (`"auto"`: |u_x/u_z| A_n) or `given`.
    pub tangential_amplitude_source: String,
    /// `wave.attenuation`: whether the wave's amplitude falls under the slider as the posts draw
    /// its power (`auto`: when the constant-amplitude posts draw more than 1 % of it at stall).
    pub wave_attenuation: stick_slip::AttenuationSetting,
    /// The transducer's drive (`wave.drive_voltage` on `[stator.idt]`): the voltage, the
    /// amplitude it launches, the electrical input and acoustic powers, f₀ and the detuning.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drive: Option<Drive>,
    /// The ball of `slider.shape = "ball"` (diameter, material, moving mass); `None`: the post
    /// array. With a ball the motor's slider body carries the ball's material and mass, and its
    /// plate and posts are not used.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ball: Option<ball_slider::BallSlider>,
    /// What the scene gives that the program accepts but doubts, each naming its key: a wave
    /// value more than 2 % off the cut's, a beam narrower than the post array, a stator material
    /// that is not the cut's crystal. They reach `summary.json` and `dynamic --json`.
    pub warnings: Vec<Warning>,
    pub contact: Contact,
    pub model: Model,
    #[serde(rename = "static")]
    pub static_fem: StaticSettings,
}

/// Contact reduction: where η comes from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Contact {
    /// η when given; `None` when the static FEM computes it.
    pub effective_ratio: Option<f64>,
    /// `given`, `fem` or `ball` (η = 1: the ball's one contact).
    pub effective_ratio_source: String,
}

/// Which dynamic model runs (`model.dynamics`): a lumped model of `stick_slip`, the coupled
/// model of `coupled_dynamics`, or `auto`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dynamics {
    /// The cheapest model whose estimated error is within `model.lumped_tolerance` of the
    /// coupled one (`coupled_dynamics::choose_model`): the lumped model
    /// (which itself picks the period average or the transient by their effect), or the coupled
    /// model when the lumped one's estimated error exceeds the tolerance.
    Auto,
    /// The lumped model of N_eff = η·N independent posts (`periodic-average`, `transient`).
    Lumped(ModelChoice),
    /// The posts of the static strip with their elastic coupling (`coupled_dynamics`).
    Coupled,
}

impl Dynamics {
    /// Each choice by its scene name.
    pub const NAMES: [(&'static str, Self); 4] = [
        ("auto", Self::Auto),
        (
            "periodic-average",
            Self::Lumped(ModelChoice::PeriodicAverage),
        ),
        ("transient", Self::Lumped(ModelChoice::Transient)),
        ("coupled", Self::Coupled),
    ];

    /// The scene name.
    pub fn name(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|(_, d)| *d == self)
            .map_or("auto", |(name, _)| name)
    }

    /// The lumped model's choice when the lumped model runs: `auto` lets it pick by effect.
    pub fn lumped_choice(self) -> ModelChoice {
        match self {
            Self::Lumped(choice) => choice,
            Self::Auto | Self::Coupled => ModelChoice::Auto,
        }
    }
}

impl Serialize for Dynamics {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

/// Dynamic-model settings.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Model {
    pub dynamics: Dynamics,
    /// `None`: [`coupled_dynamics::DEFAULT_AUTO_TOLERANCE`] (`dynamics = "auto"` only).
    pub lumped_tolerance: Option<f64>,
    /// `None`: [`DEFAULT_COUPLED_STEPS_PER_PERIOD`] (coupled model only).
    pub steps_per_period: Option<u32>,
    pub integrator: IntegratorKind,
    /// `None`: chosen inside the stability limit.
    pub time_step_s: Option<f64>,
    /// `None`: 1e-3 of the crest speed (regularized integrator only).
    pub regularization_velocity_m_per_s: Option<f64>,
    /// `None`: the model's default (50 speeds, or 6 transient loads).
    pub curve_points: Option<u32>,
    /// `None`: [`DEFAULT_TRANSIENT_PERIODS`] (transient only).
    pub periods: Option<u32>,
    /// Vertical slider model; `vertical_damping_ratio = "auto"` gives
    /// [`DEFAULT_VERTICAL_DAMPING_RATIO`] to the dynamic one.
    pub vertical: VerticalModel,
}

/// Time steps per wave period of the coupled model when `model.coupled.steps_per_period = "auto"`.
/// Default 64: on the default slider's strip at 40 N the coupled model's error against 512
/// steps is 2.2e-3 at 32 steps and falls with order ≈ 1.8 (validation/coupled-dynamics), so 64
/// steps keep it near 6e-4, well inside the 2 % that the `auto` choice works to, at a quarter
/// of the library's 256-step cost.
pub const DEFAULT_COUPLED_STEPS_PER_PERIOD: u32 = 64;
/// Wave periods of the transient when `model.transient.periods = "auto"`. Default 1000.
pub const DEFAULT_TRANSIENT_PERIODS: u32 = 1000;
/// Points on the period average's speed–thrust curve when `model.curve_points = "auto"`.
/// Default 50.
pub const DEFAULT_CURVE_POINTS: u32 = 50;
/// Damping ratio of the slider's vertical mode when `model.lumped.vertical_damping_ratio = "auto"`.
/// Default 0.05.
pub const DEFAULT_VERTICAL_DAMPING_RATIO: f64 = 0.05;

/// Which static model computes η (`static.model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StaticModel {
    /// One post row between symmetry planes on a rigid back (static_contact's strip FEM): exact
    /// for identical rows, blind to scatter, tilt, bow, the finite width and a free back.
    Strip,
    /// Every post of the slider (slider_contact), near field calibrated on the strip FEM.
    Slider,
    /// The strip where it is exact, else the slider ([`StaticModel::choose`]).
    Auto,
}

impl StaticModel {
    /// Scene names.
    pub const NAMES: [(&'static str, StaticModel); 3] = [
        ("strip", StaticModel::Strip),
        ("slider", StaticModel::Slider),
        ("auto", StaticModel::Auto),
    ];

    /// The model that runs for `motor` (`Strip` or `Slider`) and why, in one line: `auto`
    /// takes the strip for the ideal motor (identical rows on a rigid back, where it is exact
    /// and its FEM resolves the post itself) and the slider when any imperfection or a free back
    /// makes the strip inexact.
    pub fn choose(self, motor: &Motor) -> (StaticModel, String) {
        match (self, motor.first_non_ideal_key()) {
            (StaticModel::Strip, _) => (StaticModel::Strip, "static.model = \"strip\"".into()),
            (StaticModel::Slider, _) => (StaticModel::Slider, "static.model = \"slider\"".into()),
            (StaticModel::Auto, None) => (
                StaticModel::Strip,
                "static.model = \"auto\": identical rows on a rigid back, where the strip model \
                 is exact"
                    .into(),
            ),
            (StaticModel::Auto, Some(key)) => (
                StaticModel::Slider,
                format!(
                    "static.model = \"auto\": {key} makes the strip model (identical rows on a \
                     rigid back) inexact, the whole slider runs"
                ),
            ),
        }
    }

    /// Its scene name.
    pub fn name(self) -> &'static str {
        match self {
            StaticModel::Strip => "strip",
            StaticModel::Slider => "slider",
            StaticModel::Auto => "auto",
        }
    }
}

/// `static.max_iterations` of the default scene (the strip's active-set limit); the slider
/// model refuses any other value (its CG has its own limit). Default 100.
pub const DEFAULT_STATIC_MAX_ITERATIONS: u32 = 100;

/// Static contact settings.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StaticSettings {
    /// Requested model (`auto` resolved per run by [`StaticModel::choose`]).
    pub model: StaticModel,
    pub phases: u32,
    pub element_order: u32,
    pub mesh: String,
    pub stator: StatorModel,
    pub strip_rows: u32,
    /// `static.tolerance`; `None` = `auto` ([`Self::tolerance_for`]).
    pub tolerance: Option<f64>,
    pub max_iterations: u32,
    /// `static.fem_solver`: the FEM bodies' linear solver (strip and the slider's near field).
    pub fem_solver: FemSolver,
}

/// The values of `static.fem_solver`.
const FEM_SOLVER_NAMES: [(&str, FemSolver); 3] = [
    ("auto", FemSolver::Auto),
    ("direct", FemSolver::Direct),
    ("iterative", FemSolver::Iterative),
];

/// `static.tolerance = "auto"` for the strip: its exact active-set solver reaches this relative
/// complementarity residual at no extra cost (a few pivots), so the strip's η is exact to
/// rounding. Default 1e-10.
pub const STRIP_AUTO_TOLERANCE: f64 = 1e-10;

impl StaticSettings {
    /// The complementarity tolerance of `model`'s contact solver: the scene's `static.tolerance`
    /// if given, else the model's own: `STRIP_AUTO_TOLERANCE` for the strip, the whole slider's
    /// accuracy-derived [`slider_contact::DEFAULT_TOLERANCE`] (its constrained CG pays for every
    /// digit: 1e-10 costs 1.5–1.8× the iterations of 1e-6, which already holds η to 2.3e-7).
    pub fn tolerance_for(&self, model: StaticModel) -> f64 {
        self.tolerance.unwrap_or(match model {
            StaticModel::Slider => slider_contact::DEFAULT_TOLERANCE,
            StaticModel::Strip | StaticModel::Auto => STRIP_AUTO_TOLERANCE,
        })
    }
}

fn invalid(field: &str, message: impl Into<String>) -> SceneError {
    SceneError::Invalid {
        field: field.to_owned(),
        message: message.into(),
    }
}

/// A quantity derived from `field` (ω, λ, pitch, mass, …): refused naming `field` when the
/// product or quotient overflows, underflows or is not positive.
fn derived(field: &str, name: &str, value: f64) -> Result<f64, SceneError> {
    if value.is_finite() && value > 0.0 && value.is_normal() {
        Ok(value)
    } else {
        Err(invalid(
            field,
            format!(
                "the derived {name} = {value:e} is not a finite positive number: the value is out of range"
            ),
        ))
    }
}

fn choice<T: Copy>(field: &str, text: &str, options: &[(&str, T)]) -> Result<T, SceneError> {
    options
        .iter()
        .find(|(name, _)| *name == text)
        .map(|(_, v)| *v)
        .ok_or_else(|| {
            let names: Vec<_> = options.iter().map(|(n, _)| format!("\"{n}\"")).collect();
            invalid(
                field,
                format!("\"{text}\" is not one of {}", names.join(", ")),
            )
        })
}

fn material(field: &str, spec: &MaterialSpec) -> Result<Material, SceneError> {
    match spec {
        MaterialSpec::Named(name) => shape::named_material(field, name).ok_or_else(|| {
            let steel = if field == shape::BALL_MATERIAL_KEY {
                ", \"steel\""
            } else {
                ""
            };
            invalid(
                field,
                format!(
                    "unknown material \"{name}\": use \"si\", \"linbo3\"{steel} or a table of constants"
                ),
            )
        }),
        MaterialSpec::Custom(CustomMaterial {
            name,
            shear_modulus,
            youngs_modulus,
            poisson_ratio,
            density,
        }) => {
            let built = match (shear_modulus, youngs_modulus) {
                (Some(g), None) => Material::from_shear(name, g.0, *poisson_ratio, density.0),
                (None, Some(e)) => Material::from_young(name, e.0, *poisson_ratio, density.0),
                _ => {
                    return Err(invalid(
                        field,
                        "give exactly one of shear_modulus or youngs_modulus",
                    ));
                }
            };
            built.map_err(|e| invalid(field, e.to_string()))
        }
    }
}

/// The imperfections of the scene's slider (`posts.height_scatter`, `posts.scatter_seed`,
/// `posts.height_map`, `slider.tilt_x`, `slider.tilt_y`, `slider.bow`), SI; the height map is
/// read here (every post of the `posts` lattice, finite heights).
fn imperfections(file: &SceneFile, posts: &PostArray) -> Result<Imperfections, SceneError> {
    use slider_contact::HeightMapCsv;
    let p = &file.posts;
    let height_scatter_m = p.height_scatter.0;
    if !(height_scatter_m >= 0.0 && height_scatter_m.is_finite()) {
        return Err(invalid(
            "posts.height_scatter",
            format!(
                "σ of the post-height scatter must be ≥ 0, got {}",
                format_quantity(height_scatter_m, Dimension::Length)
            ),
        ));
    }
    let height_map = p
        .height_map
        .as_deref()
        .map(|path| {
            motor::HeightMap::read_csv(
                std::path::Path::new(path),
                posts.count_x as usize,
                posts.count_y as usize,
            )
            .map_err(slider_error)
        })
        .transpose()?;
    let s = &file.slider;
    Ok(Imperfections {
        height_scatter_m,
        scatter_seed: p.scatter_seed,
        height_map,
        tilt_x_m: s.tilt_x.0,
        tilt_y_m: s.tilt_y.0,
        bow_m: s.bow.0,
    })
}

/// `load.mechanism` with `load.point` ("x, y" lengths from the slider's corner, on the
/// slider `length_m × width_m`).
fn preload_mechanism(
    load: &LoadFile,
    length_m: f64,
    width_m: f64,
) -> Result<PreloadMechanism, SceneError> {
    use slider_contact::MechanismExt;
    let point = load
        .point
        .as_deref()
        .map(|text| {
            let bad = |why: String| {
                invalid(
                    "load.point",
                    format!("\"{text}\": {why} (expected \"x, y\" like \"2.5 mm, 2.5 mm\")"),
                )
            };
            let (x, y) = text
                .split_once(',')
                .ok_or_else(|| bad("two lengths separated by a comma".into()))?;
            let length = |v: &str| {
                crate::units::parse_quantity(v, Dimension::Length).map_err(|e| bad(e.to_string()))
            };
            let (x_m, y_m) = (length(x)?, length(y)?);
            if !((0.0..=length_m).contains(&x_m) && (0.0..=width_m).contains(&y_m)) {
                return Err(bad(format!(
                    "outside the slider [0, {}] × [0, {}] (measured from its corner)",
                    format_quantity(length_m, Dimension::Length),
                    format_quantity(width_m, Dimension::Length)
                )));
            }
            Ok((x_m, y_m))
        })
        .transpose()?;
    PreloadMechanism::parse(&load.mechanism, point).map_err(slider_error)
}

/// The whole-slider library's input errors name scene keys (`load.point`, `posts.height_map`,
/// …): the same one-line error, in the scene's form.
fn slider_error(e: slider_contact::SliderError) -> SceneError {
    match e {
        slider_contact::SliderError::InvalidParameter { field, reason, .. } => {
            invalid(field, reason)
        }
        slider_contact::SliderError::HeightMap { file, detail } => {
            invalid("posts.height_map", format!("{file}: {detail}"))
        }
        other => invalid("static", other.to_string()),
    }
}

/// Refuses what the chosen static model cannot honour: with the strip, any imperfection or a
/// free back (naming the key); with the slider, strip-only settings that would change nothing.
fn check_static_model(
    settings: &StaticSettings,
    motor: &Motor,
    contact: &Contact,
) -> Result<(), SceneError> {
    if let (Some(eta), Some(key)) = (contact.effective_ratio, motor.first_non_ideal_key()) {
        return Err(invalid(
            key,
            format!(
                "acts through the static stage's η, but contact.effective_ratio = {eta} is given: \
                 set effective_ratio = \"fem\" or remove {key}"
            ),
        ));
    }
    match settings.model.choose(motor).0 {
        StaticModel::Strip => match motor.first_non_ideal_key() {
            Some(key) => Err(invalid(
                key,
                "the strip model (static.model = \"strip\") resolves identical rows on a rigid \
                 back and cannot honour it: use static.model = \"slider\" or \"auto\"",
            )),
            None => Ok(()),
        },
        _ if settings.strip_rows != 1 => Err(invalid(
            "static.strip_rows",
            "the slider model calibrates its near field on a one-row strip FEM: use 1",
        )),
        _ if settings.stator != StatorModel::HalfSpace => Err(invalid(
            "static.stator",
            "the slider model's stator is the elastic half-space: use \"half-space\"",
        )),
        _ if settings.max_iterations != DEFAULT_STATIC_MAX_ITERATIONS => Err(invalid(
            "static.max_iterations",
            format!(
                "bounds the strip model's active-set iterations; the slider model's constrained \
                 CG has its own limit ({}): leave it at {DEFAULT_STATIC_MAX_ITERATIONS}",
                slider_contact::solver::DEFAULT_MAX_ITERATIONS
            ),
        )),
        _ => Ok(()),
    }
}

/// With a drive voltage the transducer launches both amplitudes (the tangential one is the
/// cut's |u_x/u_z| times the launched |u_z|): a given tangential value is ambiguous (does it
/// scale with the voltage?) and refused naming its key; `"auto"` or no value is accepted.
fn refuse_tangential_with_drive(w: &WaveFile) -> Result<(), SceneError> {
    let given = [
        (
            "wave.tangential_velocity",
            matches!(w.tangential_velocity, Some(AutoOr::Value(_))),
        ),
        (
            "wave.tangential_amplitude",
            matches!(w.tangential_amplitude, Some(AutoOr::Value(_))),
        ),
    ];
    match given.iter().find(|(_, g)| *g) {
        None => Ok(()),
        Some((key, _)) => Err(invalid(
            key,
            "is set by the transducer with wave.drive_voltage (the cut's |u_x/u_z| times the \
             launched normal amplitude): give \"auto\" or remove it",
        )),
    }
}

/// `[model]` and its sub-tables: the choice, the curve and each model's settings, SI. A
/// sub-table of a model that cannot run is refused naming its key when it gives a value
/// (`"auto"` leaves it to the program): `[model.coupled]` under a lumped `dynamics`,
/// `[model.transient]` under `periodic-average`, `[model.ball]` without a ball (a ball's
/// refusals of the other models' keys are [`shape::check_ball_keys`]).
fn resolve_model(m: &ModelFile, frequency_hz: f64, is_ball: bool) -> Result<Model, SceneError> {
    let dynamics = choice("model.dynamics", &m.dynamics, &Dynamics::NAMES)?;
    let lumped_tolerance = match m.lumped_tolerance {
        AutoOr::Auto => None,
        AutoOr::Value(_) if dynamics != Dynamics::Auto => {
            return Err(invalid(
                "model.lumped_tolerance",
                "applies only to dynamics = \"auto\" (it decides between the lumped and the coupled model); remove it or set it to \"auto\"",
            ));
        }
        AutoOr::Value(t) if !(t > 0.0 && t < 1.0) => {
            return Err(invalid(
                "model.lumped_tolerance",
                format!("must lie in (0, 1), got {t}"),
            ));
        }
        AutoOr::Value(t) => Some(t),
    };
    let steps_per_period = steps_per_period(m, dynamics, is_ball)?;
    let periods = match m.transient.periods {
        AutoOr::Auto => None,
        AutoOr::Value(_) if dynamics == Dynamics::Lumped(ModelChoice::PeriodicAverage) => {
            return Err(invalid(
                "model.transient.periods",
                "is not used: dynamics = \"periodic-average\" simulates no wave periods \
                 (periodic by construction); remove it or set it to \"auto\"",
            ));
        }
        AutoOr::Value(0) => {
            return Err(invalid(
                "model.transient.periods",
                "need at least one wave period",
            ));
        }
        AutoOr::Value(n) => Some(n),
    };
    let curve_points = match m.curve_points {
        AutoOr::Auto => None,
        AutoOr::Value(n) if n < 2 => {
            return Err(invalid(
                "model.curve_points",
                "need at least 2 points on the speed–thrust curve",
            ));
        }
        AutoOr::Value(n) => {
            let max = limits::MAX_CURVE_POINTS;
            limits::at_most("model.curve_points", n.into(), max.into(), "curve points")?;
            Some(n)
        }
    };
    let lumped = resolve_lumped(&m.lumped, frequency_hz)?;
    Ok(Model {
        dynamics,
        lumped_tolerance,
        steps_per_period,
        integrator: lumped.integrator,
        time_step_s: lumped.time_step_s,
        regularization_velocity_m_per_s: lumped.regularization_velocity_m_per_s,
        curve_points,
        periods,
        vertical: lumped.vertical,
    })
}

/// `model.coupled.steps_per_period` (refused under a lumped `dynamics`), or for a ball
/// `model.ball.steps_per_period` (refused for the post array): the one resolved
/// [`Model::steps_per_period`] of the model that steps in time per period.
fn steps_per_period(
    m: &ModelFile,
    dynamics: Dynamics,
    is_ball: bool,
) -> Result<Option<u32>, SceneError> {
    let (key, given) = if is_ball {
        ("model.ball.steps_per_period", m.ball.steps_per_period)
    } else {
        if let AutoOr::Value(_) = m.ball.steps_per_period {
            return Err(invalid(
                "model.ball.steps_per_period",
                "applies only to slider.shape = \"ball\" (the coupled model takes \
                 model.coupled.steps_per_period); remove it or set it to \"auto\"",
            ));
        }
        ("model.coupled.steps_per_period", m.coupled.steps_per_period)
    };
    match given {
        AutoOr::Auto => Ok(None),
        AutoOr::Value(_) if !is_ball && matches!(dynamics, Dynamics::Lumped(_)) => Err(invalid(
            key,
            "applies only to the coupled model (dynamics = \"coupled\" or \"auto\"); the lumped \
             models take model.lumped.time_step",
        )),
        AutoOr::Value(n) => {
            limits::steps_per_period(key, n)?;
            Ok(Some(n))
        }
    }
}

/// The resolved `[model.lumped]` settings.
struct LumpedSettings {
    integrator: IntegratorKind,
    time_step_s: Option<f64>,
    regularization_velocity_m_per_s: Option<f64>,
    vertical: VerticalModel,
}

/// `[model.lumped]`: integrator, its step and regularisation, the vertical slider model.
fn resolve_lumped(l: &LumpedFile, frequency_hz: f64) -> Result<LumpedSettings, SceneError> {
    let integrator = choice(
        "model.lumped.integrator",
        &l.integrator,
        &IntegratorKind::NAMES,
    )?;
    let vertical_dynamic = choice(
        "model.lumped.vertical",
        &l.vertical,
        &[("quasi-static", false), ("dynamic", true)],
    )?;
    let time_step_s = match l.time_step {
        AutoOr::Auto => None,
        AutoOr::Value(t) => {
            let t = positive("model.lumped.time_step", t.0)?;
            limits::time_step(t, frequency_hz)?;
            Some(t)
        }
    };
    let regularization_velocity_m_per_s = match l.regularization_velocity {
        AutoOr::Auto => None,
        AutoOr::Value(_) if integrator != IntegratorKind::Regularized => {
            return Err(invalid(
                "model.lumped.regularization_velocity",
                "applies only to integrator = \"regularized\" (tanh friction); remove it or set it to \"auto\"",
            ));
        }
        AutoOr::Value(v) => Some(positive("model.lumped.regularization_velocity", v.0)?),
    };
    let damping_ratio = match l.vertical_damping_ratio {
        AutoOr::Auto => DEFAULT_VERTICAL_DAMPING_RATIO,
        AutoOr::Value(_) if !vertical_dynamic => {
            return Err(invalid(
                "model.lumped.vertical_damping_ratio",
                "applies only to vertical = \"dynamic\" (the quasi-static slider has no vertical mode); remove it or set it to \"auto\"",
            ));
        }
        AutoOr::Value(zeta) if !(zeta.is_finite() && zeta >= 0.0) => {
            return Err(invalid(
                "model.lumped.vertical_damping_ratio",
                format!("must be ≥ 0, got {zeta}"),
            ));
        }
        AutoOr::Value(zeta) => zeta,
    };
    let vertical = if vertical_dynamic {
        VerticalModel::Dynamic { damping_ratio }
    } else {
        VerticalModel::PeriodMean
    };
    Ok(LumpedSettings {
        integrator,
        time_step_s,
        regularization_velocity_m_per_s,
        vertical,
    })
}

/// The resolved `[wave]` with its stator cut: the motor's wave, the cut's Rayleigh wave, the
/// transducer's drive and where the amplitudes and the velocity came from.
struct WaveParts {
    wave: Wave,
    stator_cut: motor::StatorCut,
    crystal_wave: CrystalWave,
    drive: Option<Drive>,
    phase_velocity_source: &'static str,
    tangential_amplitude_source: &'static str,
}

/// `wave.frequency`: f > 0 with ω = 2πf and the period 1/f finite; returns (f, ω).
fn frequency(w: &WaveFile) -> Result<(f64, f64), SceneError> {
    let frequency_hz = positive("wave.frequency", w.frequency.0)?;
    let omega = derived(
        "wave.frequency",
        "angular frequency ω = 2πf (rad/s)",
        2.0 * std::f64::consts::PI * frequency_hz,
    )?;
    derived("wave.frequency", "wave period 1/f (s)", 1.0 / frequency_hz)?;
    Ok((frequency_hz, omega))
}

/// `wave.tangential_velocity` or `wave.tangential_amplitude` (or the cut's |u_x/u_z| A_n):
/// A_t (m) and its source, `given` or `cut`; a given ratio more than 2 % off the cut's warns.
fn tangential_amplitude(
    w: &WaveFile,
    omega: f64,
    normal_amplitude_m: f64,
    has_drive: bool,
    (stator_cut, crystal_wave): (&motor::StatorCut, &CrystalWave),
    warnings: &mut Vec<Warning>,
) -> Result<(f64, &'static str), SceneError> {
    let (given_m, key) = match (w.tangential_velocity, w.tangential_amplitude) {
        (None, None) if has_drive => (None, "wave.tangential_amplitude"),
        (Some(AutoOr::Auto), None) => (None, "wave.tangential_velocity"),
        (None, Some(AutoOr::Auto)) => (None, "wave.tangential_amplitude"),
        (Some(AutoOr::Value(v)), None) => (
            Some(derived(
                "wave.tangential_velocity",
                "tangential amplitude V_t/ω (m)",
                positive("wave.tangential_velocity", v.0)? / omega,
            )?),
            "wave.tangential_velocity",
        ),
        (None, Some(AutoOr::Value(a))) => (
            Some(positive("wave.tangential_amplitude", a.0)?),
            "wave.tangential_amplitude",
        ),
        _ => {
            return Err(invalid(
                "wave",
                "give exactly one of tangential_velocity or tangential_amplitude",
            ));
        }
    };
    let cut_ratio = crystal_wave.displacement_ratio_ux_over_uz;
    match given_m {
        Some(a) => {
            warnings.extend(crystal::mismatch(
                key,
                "tangential/normal amplitude ratio A_t/A_n",
                a / normal_amplitude_m,
                cut_ratio,
                &stator_cut.name,
                |r| format!("{r:.4}"),
            ));
            Ok((a, "given"))
        }
        None => Ok((
            derived(
                key,
                "tangential amplitude |u_x/u_z| A_n (m)",
                cut_ratio * normal_amplitude_m,
            )?,
            "cut",
        )),
    }
}

/// `wave.phase_velocity` (or the cut's free-surface velocity for `"auto"`) and its source; a
/// value more than 2 % off the cut's warns.
fn phase_velocity(
    w: &WaveFile,
    (stator_cut, crystal_wave): (&motor::StatorCut, &CrystalWave),
    warnings: &mut Vec<Warning>,
) -> Result<(f64, &'static str), SceneError> {
    let cut_velocity = crystal_wave.phase_velocity_free_m_per_s;
    match w.phase_velocity {
        AutoOr::Auto => Ok((cut_velocity, "cut")),
        AutoOr::Value(c) => {
            let c = positive("wave.phase_velocity", c.0)?;
            warnings.extend(crystal::mismatch(
                "wave.phase_velocity",
                "phase velocity",
                c,
                cut_velocity,
                &stator_cut.name,
                |v| format_quantity(v, Dimension::Velocity),
            ));
            Ok((c, "given"))
        }
    }
}

/// The wave along and across the slider: `wave.aperture` (the transducer's with a drive),
/// `wave.decay_length` and `wave.burst_periods`. Returns (aperture, decay length, burst periods).
fn wave_extent(
    w: &WaveFile,
    drive: Option<&Drive>,
) -> Result<(f64, Option<f64>, Option<f64>), SceneError> {
    let aperture_m = match (w.aperture, drive) {
        (_, Some(d)) => d.transducer.aperture_m,
        (Some(a), None) => positive("wave.aperture", a.0)?,
        (None, None) => {
            return Err(invalid(
                "wave.aperture",
                "missing: give the beam's width across y, e.g. \"9 mm\"",
            ));
        }
    };
    let decay_length_m = w
        .decay_length
        .map(|d| positive("wave.decay_length", d.0))
        .transpose()?;
    let burst_periods = w
        .burst_periods
        .map(|b| positive("wave.burst_periods", b))
        .transpose()?;
    Ok((aperture_m, decay_length_m, burst_periods))
}

/// `wave.attenuation = "on"` solves the amplitude along the slider: refused beside a
/// prescribed `wave.decay_length` or `wave.burst_periods`.
fn check_attenuation(
    w: &WaveFile,
    decay_length_m: Option<f64>,
    burst_periods: Option<f64>,
) -> Result<(), SceneError> {
    if w.attenuation != Some(stick_slip::AttenuationSetting::On) {
        return Ok(());
    }
    let given = [
        ("wave.decay_length", decay_length_m.is_some()),
        ("wave.burst_periods", burst_periods.is_some()),
    ];
    match given.iter().find(|(_, g)| *g) {
        None => Ok(()),
        Some((key, _)) => Err(invalid(
            "wave.attenuation",
            format!(
                "\"on\" solves the amplitude along the slider from the wave's power, and \
                 {key} prescribes another (a steady, continuous wave is assumed): remove \
                 {key} or set wave.attenuation = \"off\""
            ),
        )),
    }
}

/// `[wave]` with `stator.cut`, `stator.material` and `[stator.idt]`: the cut's Rayleigh wave,
/// the amplitudes (given or from the drive), the velocity, the beam and the wave's extent.
fn resolve_wave(file: &SceneFile, warnings: &mut Vec<Warning>) -> Result<WaveParts, SceneError> {
    let w = &file.wave;
    let (frequency_hz, omega) = frequency(w)?;
    let cut = crystal::wave_cut(&file.stator.cut, &file.stator.material)?;
    let (stator_cut, crystal_wave) = crystal::solve(&cut)?;
    warnings.extend(crystal::material_mismatch(&cut, &file.stator.material));
    let (normal_amplitude_m, drive) =
        drive::normal_amplitude(w, file.stator.idt.as_ref(), &cut, frequency_hz, warnings)?;
    if drive.is_some() {
        refuse_tangential_with_drive(w)?;
    }
    let cut_pair = (&stator_cut, &crystal_wave);
    let (tangential_amplitude_m, tangential_amplitude_source) = tangential_amplitude(
        w,
        omega,
        normal_amplitude_m,
        drive.is_some(),
        cut_pair,
        warnings,
    )?;
    let (phase_velocity_m_per_s, phase_velocity_source) = phase_velocity(w, cut_pair, warnings)?;
    let (aperture_m, decay_length_m, burst_periods) = wave_extent(w, drive.as_ref())?;
    derived(
        "wave.tangential_amplitude",
        "tangential velocity A_t ω (m/s)",
        tangential_amplitude_m * omega,
    )?;
    let wavelength_m = derived(
        "wave.phase_velocity",
        "wavelength λ = c/f (m)",
        phase_velocity_m_per_s / frequency_hz,
    )?;
    if let Some(d) = decay_length_m {
        limits::decay_length(d, wavelength_m)?;
    }
    check_attenuation(w, decay_length_m, burst_periods)?;
    Ok(WaveParts {
        wave: Wave {
            frequency_hz,
            normal_amplitude_m,
            tangential_amplitude_m,
            phase_velocity_m_per_s,
            decay_length_m,
            burst_periods,
            aperture_m,
        },
        stator_cut,
        crystal_wave,
        drive,
        phase_velocity_source,
        tangential_amplitude_source,
    })
}

/// `[slider]` up to its mass: the shape (a ball or the post array), the ball, the material
/// (given, or the shape's default) and the plate's size (m).
struct SliderParts {
    ball: Option<ball_slider::BallSlider>,
    material: Material,
    length_m: f64,
    width_m: f64,
    thickness_m: f64,
}

fn resolve_slider(file: &SceneFile) -> Result<SliderParts, SceneError> {
    let s = &file.slider;
    let is_ball = choice(
        "slider.shape",
        s.shape.as_deref().unwrap_or("post-array"),
        &shape::SHAPE_NAMES,
    )?;
    let given_material = s
        .material
        .as_ref()
        .map(|spec| material("slider.material", spec))
        .transpose()?;
    let ball = shape::ball(file, is_ball, given_material.clone())?;
    let material = match (&ball, given_material) {
        (Some(ball), _) => ball.material.clone(),
        (None, Some(m)) => m,
        (None, None) => Material::silicon(),
    };
    Ok(SliderParts {
        ball,
        material,
        length_m: positive("slider.length", s.length.0)?,
        width_m: positive("slider.width", s.width.0)?,
        thickness_m: positive("slider.thickness", s.thickness.0)?,
    })
}

/// `[posts]`: the lattice, on the slider `length_m × width_m`; the array must fit on it and
/// the posts must not overlap (pitch = array / count).
fn resolve_posts(p: &PostsFile, length_m: f64, width_m: f64) -> Result<PostArray, SceneError> {
    let diameter_m = positive("posts.diameter", p.diameter.0)?;
    let height_m = positive("posts.height", p.height.0)?;
    let array_x_m = positive("posts.array", p.array.0)?;
    let array_y_m = match p.array_y {
        Some(a) => positive("posts.array_y", a.0)?,
        None => array_x_m,
    };
    let len = |v| format_quantity(v, Dimension::Length);
    if array_x_m > length_m || array_y_m > width_m {
        return Err(invalid(
            "posts.array",
            format!(
                "the post array ({} × {}) must fit on the slider ({} × {})",
                len(array_x_m),
                len(array_y_m),
                len(length_m),
                len(width_m)
            ),
        ));
    }
    let (count_x, count_y) = (p.count.along_x, p.count.along_y);
    limits::post_counts(count_x, count_y)?;
    let pitch =
        |array_m: f64, count: u32, what| derived("posts.count", what, array_m / f64::from(count));
    let pitch_x_m = pitch(array_x_m, count_x, "pitch along x (m)")?;
    let pitch_y_m = pitch(array_y_m, count_y, "pitch along y (m)")?;
    if diameter_m >= pitch_x_m.min(pitch_y_m) {
        return Err(invalid(
            "posts.diameter",
            format!(
                "posts of {} diameter overlap at a pitch of {} (array / count)",
                len(diameter_m),
                len(pitch_x_m.min(pitch_y_m))
            ),
        ));
    }
    let count = u64::from(count_x) * u64::from(count_y);
    derived(
        "posts.diameter",
        "contact area N·πd²/4 (m²)",
        count as f64 * std::f64::consts::PI * diameter_m * diameter_m / 4.0,
    )?;
    Ok(PostArray {
        diameter_m,
        height_m,
        count_x,
        count_y,
        array_x_m,
        array_y_m,
    })
}

/// `slider.mass` (or ρ·volume, or the ball's own) with its source, and the slider body; a
/// post's mass ρπd²h/4 must be a finite positive number.
fn slider_body(
    file: &SceneFile,
    parts: SliderParts,
    posts: &PostArray,
) -> Result<(SliderBody, &'static str), SceneError> {
    let SliderParts {
        ball,
        material,
        length_m,
        width_m,
        thickness_m,
    } = parts;
    let (mass_kg, mass_source) = match (&ball, file.slider.mass) {
        (Some(ball), AutoOr::Auto) => (ball.mass_kg(), "ball"),
        (Some(ball), AutoOr::Value(_)) => (ball.mass_kg(), "given"),
        (None, AutoOr::Auto) => (
            derived(
                "slider.mass",
                "mass ρ·length·width·thickness (kg)",
                material.density_kg_per_m3 * length_m * width_m * thickness_m,
            )?,
            "geometry",
        ),
        (None, AutoOr::Value(m)) => (positive("slider.mass", m.0)?, "given"),
    };
    let d = posts.diameter_m;
    derived(
        "posts.height",
        "post mass ρπd²h/4 (kg)",
        material.density_kg_per_m3 * std::f64::consts::PI * d * d / 4.0 * posts.height_m,
    )?;
    let body = SliderBody {
        material,
        length_m,
        width_m,
        thickness_m,
        mass_kg,
    };
    Ok((body, mass_source))
}

/// `[friction]`: each coefficient within its bound, μ_k ≤ μ_s.
fn resolve_friction(f: &FrictionFile) -> Result<Friction, SceneError> {
    for (field, mu) in [
        ("friction.static", f.mu_static),
        ("friction.kinetic", f.mu_kinetic),
    ] {
        limits::friction(field, mu)?;
    }
    if f.mu_kinetic > f.mu_static {
        return Err(invalid(
            "friction.kinetic",
            format!(
                "kinetic coefficient {} exceeds the static one {}: stick would break below the force slip sustains",
                f.mu_kinetic, f.mu_static
            ),
        ));
    }
    Ok(Friction {
        mu_static: f.mu_static,
        mu_kinetic: f.mu_kinetic,
    })
}

/// `[contact]`: η given or from the static FEM; a ball's one contact carries the whole
/// preload (η = 1), so no static stage runs for it, in a run or a sweep's FEM cache.
fn resolve_contact(c: &ContactFile, is_ball: bool) -> Contact {
    let (effective_ratio, source) = match c.effective_ratio {
        _ if is_ball => (Some(1.0), "ball"),
        EffectiveRatio::Fem => (None, "fem"),
        EffectiveRatio::Given(eta) => (Some(eta), "given"),
    };
    Contact {
        effective_ratio,
        effective_ratio_source: source.into(),
    }
}

/// `[static]`: counts and tolerances within their bounds, the choices by name; `count_y` is
/// the posts across the slider (the most rows a strip may hold).
fn resolve_static(st: &StaticFile, count_y: u32) -> Result<StaticSettings, SceneError> {
    if st.phases == 0 {
        return Err(invalid(
            "static.phases",
            "need at least one wave snapshot phase",
        ));
    }
    if !matches!(st.element_order, 1 | 2) {
        return Err(invalid(
            "static.element_order",
            format!("must be 1 (Tet4) or 2 (Tet10), got {}", st.element_order),
        ));
    }
    let tolerance = match st.tolerance {
        AutoOr::Auto => None,
        AutoOr::Value(t) => Some(positive("static.tolerance", t)?),
    };
    let (phases, max_phases) = (st.phases.into(), limits::MAX_PHASES.into());
    limits::at_most(
        "static.phases",
        phases,
        max_phases,
        "contact solves per static run",
    )?;
    let (iterations, max) = (st.max_iterations.into(), limits::MAX_ITERATIONS.into());
    limits::at_most("static.max_iterations", iterations, max, "iterations")?;
    if st.max_iterations == 0 {
        return Err(invalid("static.max_iterations", "must be ≥ 1"));
    }
    if st.strip_rows == 0 || st.strip_rows > count_y {
        return Err(invalid(
            "static.strip_rows",
            format!(
                "must lie in 1..={count_y} (posts.count_y), got {}",
                st.strip_rows
            ),
        ));
    }
    let stator = choice("static.stator", &st.stator, &StatorModel::NAMES)?;
    Ok(StaticSettings {
        model: choice("static.model", &st.model, &StaticModel::NAMES)?,
        phases: st.phases,
        element_order: st.element_order,
        mesh: st.mesh.clone(),
        stator,
        strip_rows: st.strip_rows,
        tolerance,
        max_iterations: st.max_iterations,
        fem_solver: choice("static.fem_solver", &st.fem_solver, &FEM_SOLVER_NAMES)?,
    })
}

/// A beam narrower than the post array across y: a warning naming `wave.aperture`.
fn aperture_warning(aperture_m: f64, posts: &PostArray) -> Option<Warning> {
    let len = |v| format_quantity(v, Dimension::Length);
    (posts.array_y_m > aperture_m).then(|| {
        Warning::new(
            "wave.aperture",
            format!(
                "the beam ({}) is narrower than the post array across y (posts.array_y {}): \
                 the dynamics drive every post with the full wave; only the power under the \
                 array (sawdrive wave) is capped by the aperture",
                len(aperture_m),
                len(posts.array_y_m)
            ),
        )
    })
}

impl Scene {
    /// Check and convert a scene file, table by table: the wave (with the stator's cut and
    /// transducer), the slider and its posts, friction, load, imperfections, contact, model and
    /// static settings; then the checks across tables (the static model against the motor).
    pub(crate) fn resolve(file: SceneFile) -> Result<Self, SceneError> {
        let mut warnings: Vec<Warning> = Vec::new();
        let wave = resolve_wave(&file, &mut warnings)?;
        let stator = material("stator.material", &file.stator.material)?;
        let slider = resolve_slider(&file)?;
        let posts = resolve_posts(&file.posts, slider.length_m, slider.width_m)?;
        let ball = slider.ball.clone();
        let (length_m, width_m) = (slider.length_m, slider.width_m);
        let (slider, mass_source) = slider_body(&file, slider, &posts)?;
        let friction = resolve_friction(&file.friction)?;
        let load = Load {
            preload_n: positive("load.preload", file.load.preload.0)?,
            external_load_n: file.load.external.0,
            mechanism: preload_mechanism(&file.load, length_m, width_m)?,
        };
        let imperfections = imperfections(&file, &posts)?;
        limits::imperfections(&imperfections, posts.height_m)?;
        let contact = resolve_contact(&file.contact, ball.is_some());
        let model = resolve_model(&file.model, wave.wave.frequency_hz, ball.is_some())?;
        let static_fem = resolve_static(&file.static_fem, posts.count_y)?;
        warnings.extend(aperture_warning(wave.wave.aperture_m, &posts));
        let motor = Motor {
            wave: wave.wave,
            stator,
            stator_cut: wave.stator_cut,
            slider,
            posts,
            friction,
            load,
            imperfections,
        };
        check_static_model(&static_fem, &motor, &contact)?;
        Ok(Self {
            name: file.name,
            description: file.description,
            motor,
            slider_mass_source: mass_source.into(),
            crystal_wave: wave.crystal_wave,
            phase_velocity_source: wave.phase_velocity_source.into(),
            tangential_amplitude_source: wave.tangential_amplitude_source.into(),
            wave_attenuation: file.wave.attenuation.unwrap_or_default(),
            drive: wave.drive,
            ball,
            warnings,
            contact,
            model,
            static_fem,
        })
    }
}
