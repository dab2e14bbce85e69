//! Scene files: one motor described in TOML with human units.
//!
//! Layers, each overriding the one before: the embedded default scene (the paper's motor,
//! [`DEFAULT_SCENE_TOML`]), the user's scene file (which may give only what differs), and
//! `--set key=value` overrides. Unknown keys, missing units and out-of-range values are errors
//! naming the field.

mod crystal;
mod drive;
mod file;
pub mod limits;
mod merge;
mod moved;
mod positive;
mod quantity;
mod resolved;
mod shape;

use std::path::Path;

pub use crystal::{CUT_MISMATCH_WARNING_FRACTION, CrystalWave};
pub use drive::{Drive, FingerFilm};
pub use resolved::{
    Contact, DEFAULT_COUPLED_STEPS_PER_PERIOD, DEFAULT_CURVE_POINTS, DEFAULT_STATIC_MAX_ITERATIONS,
    DEFAULT_TRANSIENT_PERIODS, DEFAULT_VERTICAL_DAMPING_RATIO, Dynamics, Model, Scene, StaticModel,
    StaticSettings,
};

/// The embedded default scene: the source paper's motor.
pub const DEFAULT_SCENE_TOML: &str = include_str!("default.toml");

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("cannot read scene {path}: {source}")]
    Io {
        /// File at fault.
        path: String,
        /// Underlying error.
        source: std::io::Error,
    },
    /// The file is not valid TOML.
    #[error("{origin}: not valid TOML: {message}")]
    Syntax {
        /// File name, or `default scene`.
        origin: String,
        /// The parser's message with line and column.
        message: String,
    },
    /// A field is unknown, missing or has the wrong form.
    #[error("{origin}: {field}: {message}")]
    Field {
        /// File name, or `default scene`.
        origin: String,
        /// Dotted path of the field.
        field: String,
        /// What is wrong and the accepted form.
        message: String,
    },
    /// A value is out of its physical range.
    #[error("{field}: {message}")]
    Invalid {
        /// Dotted path of the field.
        field: String,
        /// What is wrong and the accepted range.
        message: String,
    },
    /// A `--set` override is malformed.
    #[error("--set {text}: {reason}")]
    BadOverride {
        /// The override as given.
        text: String,
        /// What is wrong.
        reason: String,
    },
}

/// The text of a scene (or scene-with-scatter) file: a regular file of at most
/// [`atomic_files::MAX_SETTINGS_FILE_BYTES`], else [`SceneError::Io`] naming it.
pub fn read_scene_file(path: &Path) -> Result<String, SceneError> {
    atomic_files::read_input_text(path, atomic_files::MAX_SETTINGS_FILE_BYTES).map_err(|e| {
        let (path, source) = e.into_parts();
        SceneError::Io {
            path: path.display().to_string(),
            source,
        }
    })
}

fn parse_table(text: &str, origin: &str) -> Result<toml::Table, SceneError> {
    motor::input::parse_table(text).map_err(|e| SceneError::Syntax {
        origin: origin.to_owned(),
        message: e.message.trim_start_matches("not valid TOML: ").to_owned(),
    })
}

/// Load a scene: the default, overlaid with `path` (if any), overlaid with `overrides`
/// (`key=value` each).
pub fn load_scene(path: Option<&Path>, overrides: &[String]) -> Result<Scene, SceneError> {
    match path {
        Some(path) => {
            let text = read_scene_file(path)?;
            load_scene_text(Some((path, &text)), overrides)
        }
        None => load_scene_text(None, overrides),
    }
}

/// [`load_scene`] on a scene file's text already read from its path (a caller may have edited
/// it, e.g. taken out the `[scatter]` section): relative `static.mesh` and `posts.height_map`
/// resolve against the path's folder, and messages name the path.
pub fn load_scene_text(
    file: Option<(&Path, &str)>,
    overrides: &[String],
) -> Result<Scene, SceneError> {
    let mut table = parse_table(DEFAULT_SCENE_TOML, "default scene")?;
    let default = table.clone();
    let origin = match file {
        Some((path, text)) => {
            let origin = path.display().to_string();
            check_decimal_integers(text, &origin)?;
            let mut user = parse_table(text, &origin)?;
            resolve_relative_mesh(&mut user, path);
            resolve_relative_height_map(&mut user, path);
            merge::deep_merge(&mut table, user);
            origin
        }
        None => "default scene".to_owned(),
    };
    let origin = if overrides.is_empty() {
        origin
    } else {
        format!("{origin} with --set")
    };
    for text in overrides {
        merge::deep_merge(&mut table, merge::override_table(text)?);
    }
    moved::check_scene_keys(&table, &origin)?;
    shape::check_ball_keys(&table, &default)?;
    let file: file::SceneFile = motor::input::from_table(table).map_err(|e| SceneError::Field {
        origin: origin.clone(),
        field: e.field,
        message: e.message,
    })?;
    check_name(&file.name)?;
    Scene::resolve(file)
}

/// Refuse TOML integers written in base 16, 8 or 2 (`count = 0x5`): scene numbers are decimal.
/// Reads `key = value` lines under their `[table]` header (the TOML parser keeps no spelling).
fn check_decimal_integers(text: &str, origin: &str) -> Result<(), SceneError> {
    let mut table = String::new();
    for line in text.lines().map(str::trim) {
        if let Some(header) = line.strip_prefix('[') {
            table = header
                .split(']')
                .next()
                .unwrap_or_default()
                .trim()
                .to_owned();
            continue;
        }
        let Some((key, value)) = line.split_once('=') else {
            continue;
        };
        let value = value.split('#').next().unwrap_or_default();
        if merge::is_non_decimal_integer(value) {
            let key = key.trim().trim_matches('"');
            return Err(SceneError::Field {
                origin: origin.to_owned(),
                field: if table.is_empty() {
                    key.to_owned()
                } else {
                    format!("{table}.{key}")
                },
                message: format!(
                    "{}: decimal integers only (hexadecimal, octal and binary literals are refused)",
                    value.trim()
                ),
            });
        }
    }
    Ok(())
}

/// A relative `static.mesh` in a scene file is relative to that file's folder.
fn resolve_relative_mesh(table: &mut toml::Table, scene_path: &Path) {
    let Some(toml::Value::Table(fem)) = table.get_mut("static") else {
        return;
    };
    let Some(toml::Value::String(mesh)) = fem.get_mut("mesh") else {
        return;
    };
    if mesh != "auto" && Path::new(mesh.as_str()).is_relative() {
        let base = scene_path.parent().unwrap_or(Path::new("."));
        *mesh = base.join(mesh.as_str()).display().to_string();
    }
}

/// A relative `posts.height_map` in a scene file is relative to that file's folder.
fn resolve_relative_height_map(table: &mut toml::Table, scene_path: &Path) {
    let Some(toml::Value::Table(posts)) = table.get_mut("posts") else {
        return;
    };
    let Some(toml::Value::String(map)) = posts.get_mut("height_map") else {
        return;
    };
    if Path::new(map.as_str()).is_relative() {
        let base = scene_path.parent().unwrap_or(Path::new("."));
        *map = base.join(map.as_str()).display().to_string();
    }
}

/// Scene names become directory names: one safe path component ([`atomic_files::check_name`]).
fn check_name(name: &str) -> Result<(), SceneError> {
    atomic_files::check_name(name).map_err(|e| SceneError::Invalid {
        field: "name".into(),
        message: format!("{e} (it names the output folder)"),
    })
}
