//! The slider's shape (`slider.shape`): the textured plate of `[posts]` (`post-array`, the
//! default) or one ball (`ball`, crate `ball-slider`: Hertz normal contact, Mindlin–Cattaneo
//! partial slip, on the same wave).
//!
//! With a ball the scene maps as the ball model's author proposes (crates/ball-slider/README.md):
//! `slider.ball_diameter` → diameter, `slider.material` (default bearing steel) → the ball's
//! material, `slider.mass` → moving mass (`"auto"`: the ball's own ρπd³/6), `wave.*` → the wave,
//! `stator.material` → stator, `friction.*` → one μ (static = kinetic, Mindlin's theory),
//! `load.preload`, `load.external` → the forces, `model.ball.steps_per_period`,
//! `model.curve_points` → numerics. What a ball does not use — the plate's size, tilt and bow, `[posts]`,
//! `[contact]`, `[static]`, the preload mechanism and the lumped and coupled models' settings —
//! is refused, naming the key, when it differs from the default scene's value, as are a wave the
//! ball model does not represent (a decay length, a burst).

use ball_slider::{BallSlider, bearing_steel};
use contact_springs::Material;
use motor::input::at;
use toml::{Table, Value};

use super::SceneError;
use super::file::SceneFile;
use super::quantity::AutoOr;

/// `slider.shape` names: whether the slider is a ball.
pub const SHAPE_NAMES: [(&str, bool); 2] = [("post-array", false), ("ball", true)];

/// Scene keys (or whole tables) that a ball does not use; a value other than the default
/// scene's is refused naming its key.
const NOT_FOR_A_BALL: [&str; 16] = [
    "slider.length",
    "slider.width",
    "slider.thickness",
    "slider.tilt_x",
    "slider.tilt_y",
    "slider.bow",
    "posts",
    "contact",
    "static",
    "load.mechanism",
    "load.point",
    "model.dynamics",
    "model.lumped_tolerance",
    "model.lumped",
    "model.transient",
    "model.coupled",
];

fn invalid(field: &str, message: impl Into<String>) -> SceneError {
    SceneError::Invalid {
        field: field.to_owned(),
        message: message.into(),
    }
}

/// The first dotted key under `path` whose value in `merged` differs from `default`.
fn first_difference(path: &str, merged: Option<&Value>, default: Option<&Value>) -> Option<String> {
    match (merged, default) {
        (Some(Value::Table(m)), Some(Value::Table(d))) => m
            .keys()
            .chain(d.keys())
            .find_map(|k| first_difference(&format!("{path}.{k}"), m.get(k), d.get(k))),
        (m, d) if m == d => None,
        _ => Some(path.to_owned()),
    }
}

/// Refuse, naming the key, a value a ball does not use that differs from the default scene's
/// (`merged`: the scene after its layers, `default`: the embedded default scene).
pub fn check_ball_keys(merged: &Table, default: &Table) -> Result<(), SceneError> {
    if at(merged, "slider.shape").and_then(Value::as_str) != Some("ball") {
        return Ok(());
    }
    match NOT_FOR_A_BALL
        .iter()
        .find_map(|key| first_difference(key, at(merged, key), at(default, key)))
    {
        None => Ok(()),
        Some(key) => Err(invalid(
            &key,
            "is not used with slider.shape = \"ball\" (one Hertz–Mindlin contact: no post \
             array, static stage, plate or lumped/coupled model settings): remove it",
        )),
    }
}

/// The key that names a ball's material, the one that also accepts `steel`.
pub const BALL_MATERIAL_KEY: &str = "slider.material";

/// The named material of key `field`: contact-springs' (`si`, `linbo3`), and for
/// `slider.material` also the ball's bearing steel (`steel`, AISI 52100; the stator stays a
/// crystal).
pub fn named_material(field: &str, name: &str) -> Option<Material> {
    Material::named(name).or_else(|| {
        (field == BALL_MATERIAL_KEY && name.eq_ignore_ascii_case("steel")).then(bearing_steel)
    })
}

/// The ball of a `slider.shape = "ball"` scene (`None` for the post array), with `material` the
/// resolved `slider.material` (`None`: not given, the shape's default). The ball's own rules
/// are checked here, naming their keys.
pub fn ball(
    file: &SceneFile,
    is_ball: bool,
    material: Option<Material>,
) -> Result<Option<BallSlider>, SceneError> {
    let s = &file.slider;
    if !is_ball {
        return match s.ball_diameter {
            Some(_) => Err(invalid(
                "slider.ball_diameter",
                "applies only to slider.shape = \"ball\"; remove it or set the shape",
            )),
            None => Ok(None),
        };
    }
    let diameter_m = match s.ball_diameter {
        None => {
            return Err(invalid(
                "slider.ball_diameter",
                "missing: slider.shape = \"ball\" needs the ball's diameter, e.g. \"2 mm\"",
            ));
        }
        Some(d) => super::positive::positive("slider.ball_diameter", d.0)?,
    };
    let moving_mass_kg = match s.mass {
        AutoOr::Auto => None,
        AutoOr::Value(m) => Some(super::positive::positive("slider.mass", m.0)?),
    };
    let f = &file.friction;
    if f.mu_static != f.mu_kinetic {
        return Err(invalid(
            "friction.kinetic",
            format!(
                "must equal friction.static ({}) for a ball: Mindlin–Cattaneo partial slip has \
                 one friction coefficient",
                f.mu_static
            ),
        ));
    }
    let w = &file.wave;
    let unsupported = [
        ("wave.decay_length", w.decay_length.is_some()),
        ("wave.burst_periods", w.burst_periods.is_some()),
    ];
    if let Some((key, _)) = unsupported.iter().find(|(_, given)| *given) {
        return Err(invalid(
            key,
            "is not modelled for slider.shape = \"ball\": the ball model takes the steady, \
             continuous wave at its one contact (no decay or burst); remove it",
        ));
    }
    Ok(Some(BallSlider {
        diameter_m,
        material: material.unwrap_or_else(bearing_steel),
        moving_mass_kg,
    }))
}
