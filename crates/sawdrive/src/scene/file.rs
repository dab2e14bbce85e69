//! The scene file as a user writes it (human units). Every table refuses unknown keys.

use std::fmt;

use serde::Deserialize;
use serde::de::{self, Deserializer, MapAccess, Visitor};

use super::quantity::{
    AutoOr, Density, EffectiveRatio, Force, Frequency, Length, Mass, PostCount, Pressure, Time,
    Velocity, Voltage,
};

/// One motor: wave, materials, slider, posts, friction, loads, contact ratio and solver settings.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Name of the scene; results go to `OUT/<name>/`.
    pub name: String,
    /// Free text.
    #[serde(default)]
    pub description: String,
    pub wave: WaveFile,
    pub stator: StatorFile,
    pub slider: SliderFile,
    pub posts: PostsFile,
    pub friction: FrictionFile,
    pub load: LoadFile,
    pub contact: ContactFile,
    pub model: ModelFile,
    #[serde(rename = "static")]
    pub static_fem: StaticFile,
}

/// The stator's travelling Rayleigh wave.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WaveFile {
    pub frequency: Frequency,
    /// Normal amplitude A_n (give this or `drive_voltage`).
    pub normal_amplitude: Option<Length>,
    /// Peak drive voltage V₀₋ₚ on the `[stator.idt]` transducer (give this or
    /// `normal_amplitude`): the amplitude follows from the transducer model.
    pub drive_voltage: Option<Voltage>,
    /// Tangential velocity amplitude V_t = A_t ω (give this or `tangential_amplitude`);
    /// `"auto"`: A_t = |u_x/u_z| A_n of the stator's cut.
    pub tangential_velocity: Option<AutoOr<Velocity>>,
    /// Tangential displacement amplitude A_t (give this or `tangential_velocity`); `"auto"` as
    /// for `tangential_velocity`.
    pub tangential_amplitude: Option<AutoOr<Length>>,
    /// Phase velocity c; `"auto"`: the free-surface Rayleigh velocity of the stator's cut.
    pub phase_velocity: AutoOr<Velocity>,
    /// Beam width across y (the IDT's aperture), e.g. `"9 mm"`; absent: `stator.idt.aperture`.
    pub aperture: Option<Length>,
    /// Amplitude decay length along x (none: no decay).
    pub decay_length: Option<Length>,
    /// Finite burst length in wave periods (none: continuous drive).
    pub burst_periods: Option<f64>,
    /// The energy-conserving wave under the slider: `"auto"` (default), `"on"` or `"off"`.
    pub attenuation: Option<stick_slip::AttenuationSetting>,
}

/// The stator: its material (contact compliance) and its crystal cut (the wave).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StatorFile {
    pub material: MaterialSpec,
    /// The crystal cut whose Rayleigh wave drives the slider.
    pub cut: CutSpec,
    /// The interdigital transducer that `wave.drive_voltage` drives.
    pub idt: Option<IdtFile>,
}

/// `[stator.idt]`: a uniform single-electrode interdigital transducer.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdtFile {
    /// Number of finger pairs N_p (≥ 1).
    pub finger_pairs: u32,
    /// Finger width w, e.g. `"100 um"`.
    pub finger_width: Length,
    /// Gap between neighbouring fingers g, e.g. `"100 um"`.
    pub gap: Length,
    /// Acoustic aperture W (the fingers' overlap, the beam's width), e.g. `"9 mm"`.
    pub aperture: Length,
    /// The finger film, for the finger resistance (absent: perfect conductors).
    pub metallisation: Option<MetallisationFile>,
}

/// `stator.idt.metallisation = { metal = "aluminium", thickness = "100 nm" }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MetallisationFile {
    /// `aluminium`, `chromium`, `gold` or `copper`.
    pub metal: String,
    /// Film thickness, e.g. `"100 nm"`.
    pub thickness: Length,
}

/// A crystal cut: a named cut (`"128yx-linbo3"`, `"yz-linbo3"`, `"st-x-quartz"`) or
/// `{ crystal = "linbo3", euler = [φ, θ, ψ] }` (ZXZ Euler angles in degrees).
#[derive(Debug, Clone, PartialEq)]
pub enum CutSpec {
    /// A named cut.
    Named(String),
    /// A crystal at given Euler angles.
    Euler(EulerCut),
}

/// A crystal cut given by its Euler angles.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EulerCut {
    /// `linbo3` (Kovacs et al. 1990), `linbo3-warner` (Warner et al. 1967) or `quartz`
    /// (Bechmann 1958); default: the stator's material when it is `linbo3`.
    pub crystal: Option<String>,
    /// ZXZ Euler angles (φ, θ, ψ) of the wave frame, degrees.
    pub euler: [f64; 3],
}

impl<'de> Deserialize<'de> for CutSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct CutVisitor;
        impl<'de> Visitor<'de> for CutVisitor {
            type Value = CutSpec;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(
                    "a named cut (\"128yx-linbo3\", \"yz-linbo3\", \"st-x-quartz\") or a table { crystal, euler = [φ, θ, ψ] }",
                )
            }
            fn visit_str<E: de::Error>(self, name: &str) -> Result<CutSpec, E> {
                Ok(CutSpec::Named(name.to_owned()))
            }
            fn visit_map<M: MapAccess<'de>>(self, map: M) -> Result<CutSpec, M::Error> {
                EulerCut::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(CutSpec::Euler)
            }
        }
        deserializer.deserialize_any(CutVisitor)
    }
}

/// The slider body.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SliderFile {
    /// `post-array` (default: the textured plate of `[posts]`) or `ball`.
    pub shape: Option<String>,
    /// Diameter of the ball (`shape = "ball"` only), e.g. `"2 mm"`.
    pub ball_diameter: Option<Length>,
    /// Absent: silicon for the post array, bearing steel for a ball.
    pub material: Option<MaterialSpec>,
    pub length: Length,
    pub width: Length,
    pub thickness: Length,
    /// Slider mass; `"auto"`: ρ · length · width · thickness.
    pub mass: AutoOr<Mass>,
    /// Tilt: height change of the back across the length (the +x end higher), e.g. `"20 nm"`.
    pub tilt_x: Length,
    /// Tilt across the width (the +y side higher).
    pub tilt_y: Length,
    /// Bow: the corners above the centre (> 0: convex towards the stator).
    pub bow: Length,
}

/// The posts (projections) on the slider's underside.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PostsFile {
    pub diameter: Length,
    pub height: Length,
    pub count: PostCount,
    /// Extent of the post array along x (centre of the first post to the far edge of the last:
    /// count × pitch), e.g. `"4 mm"`.
    pub array: Length,
    /// Extent along y when the array is not square (default: `array`).
    pub array_y: Option<Length>,
    /// σ of the Gaussian post-height scatter, e.g. `"5 nm"` (≥ 0).
    pub height_scatter: Length,
    /// Seed of the scatter.
    pub scatter_seed: u64,
    /// A measured height map: CSV of `row,column,height_m` (relative to the scene file).
    pub height_map: Option<String>,
}

/// Coulomb friction at the post tips.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionFile {
    #[serde(rename = "static")]
    pub mu_static: f64,
    #[serde(rename = "kinetic")]
    pub mu_kinetic: f64,
}

/// External forces on the slider.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadFile {
    pub preload: Force,
    /// External load opposing the motion.
    pub external: Force,
    /// How the preload reaches the slider: `rigid`, `pressure` or `point`.
    pub mechanism: String,
    /// Where a `point` preload acts, from the slider's (−x, −y) corner: `"2.5 mm, 2.5 mm"`.
    pub point: Option<String>,
}

/// Contact reduction.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactFile {
    pub effective_ratio: EffectiveRatio,
}

/// Dynamic-model settings: the choice and the curve's size at the top of `[model]`, each model's
/// own settings in its sub-table, so that a setting cannot be written where its model does not
/// read it (every table refuses unknown keys).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelFile {
    /// `auto`, `periodic-average`, `transient` or `coupled`.
    pub dynamics: String,
    /// Largest estimated relative error of the lumped model that `dynamics = "auto"` accepts
    /// before it runs the coupled model; `"auto"`: 0.02 (`model.dynamics = "auto"` only).
    pub lumped_tolerance: AutoOr<f64>,
    /// Points on the speed–thrust curve of whichever model runs (period average: speeds;
    /// transient: loads; coupled and ball: curve points); `"auto"`: each model's default.
    pub curve_points: AutoOr<u32>,
    /// `[model.lumped]`: the lumped models (period average and transient).
    pub lumped: LumpedFile,
    /// `[model.transient]`: the transient lumped model.
    pub transient: TransientFile,
    /// `[model.coupled]`: the coupled model of every post of the strip.
    pub coupled: CoupledFile,
    /// `[model.ball]`: the ball model (`slider.shape = "ball"`).
    pub ball: BallFile,
}

/// `[model.lumped]`: settings of the lumped model of N_eff = η·N posts (period average and
/// transient; it also runs beside the coupled model as its comparison).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LumpedFile {
    /// `auto`, `event-driven`, `return-mapping`, `regularized` or `post-mass`.
    pub integrator: String,
    /// Integrator time step; `"auto"` picks one inside the stability limit.
    pub time_step: AutoOr<Time>,
    /// Regularisation velocity of the tanh friction law (regularized integrator only).
    pub regularization_velocity: AutoOr<Velocity>,
    /// `quasi-static` (⟨ΣN⟩ = P over a period) or `dynamic` (M z̈ = ΣN − P).
    pub vertical: String,
    /// Damping ratio ζ of the slider's vertical mode (`vertical = "dynamic"` only); `"auto"`: 0.05.
    pub vertical_damping_ratio: AutoOr<f64>,
}

/// `[model.transient]`: settings of the transient lumped model only.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransientFile {
    /// Wave periods simulated by the transient model; `"auto"`: 1000.
    pub periods: AutoOr<u32>,
}

/// `[model.coupled]`: settings of the coupled model only.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoupledFile {
    /// Time steps per wave period; `"auto"`: 64.
    pub steps_per_period: AutoOr<u32>,
}

/// `[model.ball]`: settings of the ball model only.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BallFile {
    /// Time steps per wave period; `"auto"`: the ball crate's 128.
    pub steps_per_period: AutoOr<u32>,
}

/// Static FEM contact settings.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StaticFile {
    /// `strip` (one post row, FEM), `slider` (every post) or `auto`.
    pub model: String,
    /// Wave snapshot phases θ₀ pooled in the η fit.
    pub phases: u32,
    /// FEM element order: 1 (Tet4) or 2 (Tet10).
    pub element_order: u32,
    /// Mesh file for the slider strip; `"auto"`: committed mesh or gmsh.
    pub mesh: String,
    /// Stator compliance: `half-space` (Johnson rigid-disk compliances) or `meshed-block`.
    pub stator: String,
    /// Rows of posts across the strip between its symmetry planes (1; 2+ to check the strip).
    pub strip_rows: u32,
    /// Relative complementarity tolerance of the contact solver; `"auto"`: each static model's
    /// own ([`super::StaticSettings::tolerance_for`]).
    pub tolerance: AutoOr<f64>,
    /// Maximum active-set iterations.
    pub max_iterations: u32,
    /// Linear solver of the FEM bodies: `auto` (cost model), `direct` or `iterative`.
    pub fem_solver: String,
}

/// A material: a built-in name (`"si"`, `"linbo3"`) or a table of constants.
#[derive(Debug, Clone, PartialEq)]
pub enum MaterialSpec {
    /// A built-in material.
    Named(String),
    /// User-defined isotropic constants.
    Custom(CustomMaterial),
}

/// User-defined isotropic material: give `shear_modulus` or `youngs_modulus`, and `poisson_ratio`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CustomMaterial {
    #[serde(default = "custom_name")]
    pub name: String,
    pub shear_modulus: Option<Pressure>,
    pub youngs_modulus: Option<Pressure>,
    pub poisson_ratio: f64,
    pub density: Density,
}

fn custom_name() -> String {
    "custom".into()
}

impl<'de> Deserialize<'de> for MaterialSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct SpecVisitor;
        impl<'de> Visitor<'de> for SpecVisitor {
            type Value = MaterialSpec;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("\"si\", \"linbo3\" or a table { shear_modulus | youngs_modulus, poisson_ratio, density }")
            }
            fn visit_str<E: de::Error>(self, name: &str) -> Result<MaterialSpec, E> {
                Ok(MaterialSpec::Named(name.to_owned()))
            }
            fn visit_map<M: MapAccess<'de>>(self, map: M) -> Result<MaterialSpec, M::Error> {
                CustomMaterial::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(MaterialSpec::Custom)
            }
        }
        deserializer.deserialize_any(SpecVisitor)
    }
}
