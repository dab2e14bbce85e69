//! The `[scatter]` section: which inputs scatter, and how (human units, one line each).
//!
//! ```toml
//! [scatter]
//! distribution = "normal"     # normal: values below are standard deviations (truncated to
//!                             # the physical range); uniform: half-widths around the nominal
//! height_scatter = "5 nm"     # σ of each post's extra height (Gaussian, a new seed per sample)
//! tilt_x = "10 nm"            # spread of the tilt across the length (zero mean)
//! tilt_y = "10 nm"            # … across the width
//! bow = "5 nm"                # spread of the bow (zero mean)
//! friction = 0.03             # spread of μ_s and of μ_k (drawn independently, μ_k ≤ μ_s)
//! preload = "2 N"             # preload tolerance
//! diameter = "0.5 um"         # post-diameter tolerance (one etch bias for all posts)
//! ```
//!
//! Every key is optional (0: no scatter). Negative spreads, unknown keys and missing units are
//! errors naming `scatter.<key>`. Normal draws of μ, P and d are truncated to
//! [[`MIN_FRICTION`], ∞), (0, ∞) and (0, ∞): a uniform range reaching below them is refused.

use serde::Serialize;

use design::{Distribution, ScatterInput};

use std::path::Path;

use super::motor::MotorSample;
use crate::scene::{Scene, SceneError, load_scene_text};
use crate::units::{Dimension, parse_quantity};

/// Smallest friction coefficient a draw may take (the dynamic model needs μ > 0 to drive).
pub const MIN_FRICTION: f64 = 1e-3;
/// Smallest fraction of the nominal preload or diameter a draw may take.
pub const MIN_FRACTION_OF_NOMINAL: f64 = 1e-3;
/// Upper end of the one-sided truncations ("no upper limit").
const UNBOUNDED: f64 = 1e300;

/// How a spread is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum SpreadKind {
    /// Standard deviation of a (truncated) normal.
    #[default]
    Normal,
    /// Half-width of a uniform.
    Uniform,
}

/// The scatter of a UQ run, SI.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct ScatterSpec {
    /// Meaning of the spreads.
    pub distribution: SpreadKind,
    /// σ of the per-post heights (m).
    pub height_scatter_m: f64,
    /// Tilt spread (m).
    pub tilt_x_m: f64,
    /// Tilt spread (m).
    pub tilt_y_m: f64,
    /// Bow spread (m).
    pub bow_m: f64,
    /// μ spread.
    pub friction: f64,
    /// Preload spread (N).
    pub preload_n: f64,
    /// Diameter spread (m).
    pub diameter_m: f64,
}

/// Keys of `[scatter]`.
pub const SCATTER_KEYS: [&str; 8] = [
    "distribution",
    "height_scatter",
    "tilt_x",
    "tilt_y",
    "bow",
    "friction",
    "preload",
    "diameter",
];

fn quantity(value: &toml::Value, key: &str, dim: Dimension) -> Result<f64, String> {
    let text = value.as_str().ok_or_else(|| {
        format!(
            "scatter.{key}: expected a quantity with its unit, e.g. {}",
            dim.example()
        )
    })?;
    parse_quantity(text, dim).map_err(|e| format!("scatter.{key}: {e}"))
}

fn spread(value: f64, key: &str) -> Result<f64, String> {
    if value >= 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(format!(
            "scatter.{key}: spread {value} must be ≥ 0 and finite"
        ))
    }
}

impl ScatterSpec {
    /// Reads the `[scatter]` table; errors are one line naming `scatter.<key>`.
    pub fn from_table(table: &toml::Table) -> Result<Self, String> {
        let mut s = Self::default();
        for (key, value) in table {
            match key.as_str() {
                "distribution" => {
                    s.distribution = match value.as_str() {
                        Some("normal") => SpreadKind::Normal,
                        Some("uniform") => SpreadKind::Uniform,
                        _ => {
                            return Err(format!(
                                "scatter.distribution: {value} is not \"normal\" or \"uniform\""
                            ));
                        }
                    }
                }
                "height_scatter" => {
                    s.height_scatter_m = spread(quantity(value, key, Dimension::Length)?, key)?
                }
                "tilt_x" => s.tilt_x_m = spread(quantity(value, key, Dimension::Length)?, key)?,
                "tilt_y" => s.tilt_y_m = spread(quantity(value, key, Dimension::Length)?, key)?,
                "bow" => s.bow_m = spread(quantity(value, key, Dimension::Length)?, key)?,
                "preload" => s.preload_n = spread(quantity(value, key, Dimension::Force)?, key)?,
                "diameter" => s.diameter_m = spread(quantity(value, key, Dimension::Length)?, key)?,
                "friction" => {
                    let v = value
                        .as_float()
                        .or_else(|| value.as_integer().map(|i| i as f64))
                        .ok_or_else(|| {
                            format!("scatter.friction: expected a number, got {value}")
                        })?;
                    s.friction = spread(v, key)?;
                }
                other => {
                    return Err(format!(
                        "scatter.{other}: unknown key (known: {})",
                        SCATTER_KEYS.join(", ")
                    ));
                }
            }
        }
        Ok(s)
    }

    /// Spreads within the range where the models hold (the bounds of `scene::limits`): friction
    /// spread ≤ the largest coefficient, height scatter ≤ h/3, tilt and bow spreads ≤ h, preload
    /// and diameter spreads below their nominal values.
    fn check_physical(&self, scene: &Scene) -> Result<(), String> {
        use crate::scene::limits::MAX_FRICTION;
        let h = scene.motor.posts.height_m;
        let checks = [
            ("friction", self.friction, MAX_FRICTION, "the largest friction coefficient"),
            ("height_scatter", self.height_scatter_m, h / 3.0, "a third of the post height"),
            ("tilt_x", self.tilt_x_m, h, "the post height"),
            ("tilt_y", self.tilt_y_m, h, "the post height"),
            ("bow", self.bow_m, h, "the post height"),
            ("preload", self.preload_n, scene.motor.load.preload_n, "the nominal preload"),
            ("diameter", self.diameter_m, scene.motor.posts.diameter_m, "the nominal diameter"),
        ];
        match checks.iter().find(|(_, spread, max, _)| spread > max) {
            None => Ok(()),
            Some((key, spread, max, what)) => Err(format!(
                "scatter.{key}: spread {spread:e} exceeds {what} ({max:e}, SI): the models do not hold there"
            )),
        }
    }

    /// A distribution of spread `spread` around `nominal`, truncated below at `low`.
    fn around(&self, nominal: f64, spread: f64, low: f64) -> Distribution {
        match self.distribution {
            SpreadKind::Normal => Distribution::TruncatedNormal {
                mean: nominal,
                sd: spread,
                low,
                high: UNBOUNDED,
            },
            SpreadKind::Uniform => Distribution::Uniform {
                low: nominal - spread,
                high: nominal + spread,
            },
        }
    }

    /// The scattered inputs (names with units) around `scene`'s nominal values, validated;
    /// errors name `scatter.<key>`. Order: the fields of [`MotorSample`] except the seed.
    pub fn inputs(&self, scene: &Scene) -> Result<Vec<ScatterInput>, String> {
        self.check_physical(scene)?;
        let zero_mean = |spread: f64| self.around(0.0, spread, -UNBOUNDED);
        let f = &scene.motor.friction;
        let list = [
            (
                "preload_n",
                "preload",
                self.around(
                    scene.motor.load.preload_n,
                    self.preload_n,
                    MIN_FRACTION_OF_NOMINAL * scene.motor.load.preload_n,
                ),
            ),
            (
                "post_diameter_m",
                "diameter",
                self.around(
                    scene.motor.posts.diameter_m,
                    self.diameter_m,
                    MIN_FRACTION_OF_NOMINAL * scene.motor.posts.diameter_m,
                ),
            ),
            (
                "mu_static",
                "friction",
                self.around(f.mu_static, self.friction, MIN_FRICTION),
            ),
            (
                "mu_kinetic",
                "friction",
                self.around(f.mu_kinetic, self.friction, MIN_FRICTION),
            ),
            ("tilt_x_m", "tilt_x", zero_mean(self.tilt_x_m)),
            ("tilt_y_m", "tilt_y", zero_mean(self.tilt_y_m)),
            ("bow_m", "bow", zero_mean(self.bow_m)),
        ];
        list.into_iter()
            .map(|(name, key, distribution)| {
                distribution.validate(&format!("scatter.{key}")).map_err(|e| e.to_string())?;
                if let Distribution::Uniform { low, .. } = distribution {
                    let floor = match key {
                        "friction" => MIN_FRICTION,
                        "preload" | "diameter" => 0.0,
                        _ => -UNBOUNDED,
                    };
                    if low <= floor {
                        return Err(format!(
                            "scatter.{key}: the uniform range reaches {low}, below the physical limit {floor}"
                        ));
                    }
                }
                Ok(ScatterInput {
                    name: name.to_owned(),
                    distribution,
                })
            })
            .collect()
    }

    /// The sample of drawn `values` (in the order of [`ScatterSpec::inputs`]) with the post
    /// heights seeded by `field_seed`.
    pub fn sample(&self, values: &[f64], field_seed: u64) -> MotorSample {
        MotorSample {
            preload_n: values[0],
            post_diameter_m: values[1],
            mu_static: values[2],
            mu_kinetic: values[3].min(values[2]),
            tilt_x_m: values[4],
            tilt_y_m: values[5],
            bow_m: values[6],
            height_scatter_m: self.height_scatter_m,
            scatter_seed: field_seed,
        }
    }
}

impl ScatterSpec {
    /// Takes the scene's own scatter keys into the spec: `posts.height_scatter` (σ of the post
    /// heights; each sample then draws its own heights from `--seed`, so `posts.scatter_seed` is
    /// not used) when `scatter.height_scatter` is not given. The scene's deterministic shape
    /// (`slider.tilt_x`, `slider.tilt_y`, `slider.bow`, `posts.height_map`) is refused: the UQ
    /// draws tilt and bow around zero from `scatter.*` spreads. Errors are one line naming the key.
    pub fn with_scene_keys(mut self, scene: &Scene) -> Result<Self, String> {
        let shape = &scene.motor.imperfections;
        for (key, value) in [
            ("slider.tilt_x", shape.tilt_x_m),
            ("slider.tilt_y", shape.tilt_y_m),
            ("slider.bow", shape.bow_m),
        ] {
            if value != 0.0 {
                let short = key.trim_start_matches("slider.");
                return Err(format!(
                    "{key}: uq draws the slider's shape around zero; give its spread as \
                     scatter.{short} instead of a fixed value"
                ));
            }
        }
        if shape.height_map.is_some() {
            return Err(
                "posts.height_map: uq draws the post heights (scatter.height_scatter or \
                        posts.height_scatter); a measured map is not sampled"
                    .into(),
            );
        }
        if shape.height_scatter_m > 0.0 {
            if self.height_scatter_m > 0.0 {
                return Err(
                    "posts.height_scatter and scatter.height_scatter both give the σ of \
                            the post heights; keep one"
                        .into(),
                );
            }
            self.height_scatter_m = shape.height_scatter_m;
        }
        Ok(self)
    }
}

/// Splits a scene file's text into the scene (without `[scatter]`) and the scatter table, and
/// the `--set` overrides into scene overrides and `scatter.*` ones (applied to the table).
pub fn split_scatter(
    scene_text: Option<&str>,
    overrides: &[String],
) -> Result<(Option<String>, Vec<String>, toml::Table), String> {
    let mut table = toml::Table::new();
    let scene = match scene_text {
        Some(text) => {
            let mut doc: toml::Table = text.parse().map_err(|e: toml::de::Error| {
                format!(
                    "scene: not valid TOML: {}",
                    e.to_string().trim().replace('\n', " ")
                )
            })?;
            if let Some(v) = doc.remove("scatter") {
                table = v
                    .as_table()
                    .cloned()
                    .ok_or("scatter: must be a table ([scatter])")?;
            }
            let friction_scatter = doc
                .get_mut("friction")
                .and_then(toml::Value::as_table_mut)
                .and_then(|f| f.remove("scatter"));
            if let Some(v) = friction_scatter {
                if table.contains_key("friction") {
                    return Err(
                        "friction.scatter and scatter.friction both give the spread of μ; \
                                keep one"
                            .into(),
                    );
                }
                table.insert("friction".into(), v);
            }
            Some(toml::to_string(&doc).map_err(|e| format!("scene: {e}"))?)
        }
        None => None,
    };
    let mut rest = Vec::new();
    // Where μ's spread came from: the scene-style name or the scatter one (both is an error).
    let mut friction_names = [false; 2];
    for o in overrides {
        // `friction.scatter` is the scene-style name of `scatter.friction`.
        let alias = o
            .strip_prefix("friction.scatter")
            .filter(|rest| rest.trim_start().starts_with('='));
        let o = &match alias {
            Some(rest) => format!("scatter.friction{rest}"),
            None => o.clone(),
        };
        if o.starts_with("scatter.friction") {
            friction_names[usize::from(alias.is_some())] = true;
            if friction_names == [true, true] {
                return Err(
                    "--set friction.scatter and --set scatter.friction both give the \
                            spread of μ; keep one"
                        .into(),
                );
            }
        }
        match o.strip_prefix("scatter.") {
            Some(kv) => {
                let (k, v) = kv
                    .split_once('=')
                    .ok_or_else(|| format!("--set {o}: expected scatter.KEY=VALUE"))?;
                let value = v.trim();
                let parsed = value
                    .parse::<f64>()
                    .map(toml::Value::Float)
                    .unwrap_or_else(|_| toml::Value::String(value.to_owned()));
                table.insert(k.trim().to_owned(), parsed);
            }
            None => rest.push(o.clone()),
        }
    }
    Ok((scene, rest, table))
}

/// Why the inputs of `sawdrive uq` could not be read.
#[derive(Debug, thiserror::Error)]
pub enum UqInputError {
    /// The scene file cannot be read, or its scene part is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The scatter (`[scatter]`, `scatter.*`, `friction.scatter`) is invalid, or conflicts with
    /// the scene.
    #[error("{0}")]
    Scatter(String),
}

/// The scene and scatter of `sawdrive uq [SCENE] --set …` (the command's and Python's one
/// reader): the scene file's `[scatter]` section, `friction.scatter` and the `scatter.*`
/// overrides form the scatter ([`split_scatter`]); the rest is the scene, read by the one scene
/// loader from the file's own path (relative paths resolve against its folder); then the
/// scene's own scatter keys join the scatter ([`ScatterSpec::with_scene_keys`]).
pub fn load_uq_inputs(
    path: Option<&Path>,
    overrides: &[String],
) -> Result<(Scene, ScatterSpec), UqInputError> {
    let text = match path {
        Some(p) => Some(crate::scene::read_scene_file(p)?),
        None => None,
    };
    let (scene_text, overrides, table) =
        split_scatter(text.as_deref(), overrides).map_err(UqInputError::Scatter)?;
    let scatter = ScatterSpec::from_table(&table).map_err(UqInputError::Scatter)?;
    let file = path.zip(scene_text.as_deref());
    let scene = load_scene_text(file, &overrides)?;
    let scatter = scatter
        .with_scene_keys(&scene)
        .map_err(UqInputError::Scatter)?;
    Ok((scene, scatter))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load_scene;

    fn spec(overrides: &[&str]) -> Result<ScatterSpec, String> {
        let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        let (_, rest, table) = split_scatter(None, &overrides)?;
        let scene = load_scene(None, &rest).map_err(|e| e.to_string())?;
        ScatterSpec::from_table(&table)?.with_scene_keys(&scene)
    }

    #[test]
    fn friction_scatter_is_the_scene_style_name_of_scatter_friction() {
        let s = spec(&["friction.scatter=0.03"]).unwrap();
        assert_eq!(s.friction, 0.03, "spread of μ from friction.scatter");
        let text = "[friction]\nstatic = 0.3\nscatter = 0.02\n[scatter]\nfriction = 0.01\n";
        let e = split_scatter(Some(text), &[]).unwrap_err();
        assert!(e.contains("friction.scatter and scatter.friction"), "{e}");
    }

    #[test]
    fn the_scenes_post_height_scatter_is_the_uq_height_spread_and_a_fixed_tilt_is_refused() {
        let s = spec(&["posts.height_scatter=5nm"]).unwrap();
        assert!(
            (s.height_scatter_m - 5e-9).abs() < 1e-20,
            "σ of the post heights from posts.height_scatter: {}",
            s.height_scatter_m
        );
        let e = spec(&["posts.height_scatter=5nm", "scatter.height_scatter=2nm"]).unwrap_err();
        assert!(
            e.contains("posts.height_scatter and scatter.height_scatter"),
            "{e}"
        );
        let e = spec(&["slider.tilt_x=10nm"]).unwrap_err();
        assert!(e.starts_with("slider.tilt_x:"), "{e}");
    }

    #[test]
    fn uq_inputs_resolve_relative_paths_against_the_scene_files_folder() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("scatter-scene.toml");
        let text = "[static]\nmesh = \"strip.msh\"\n[scatter]\nfriction = 0.02\n";
        std::fs::write(&path, text).unwrap();
        let (scene, scatter) = load_uq_inputs(Some(&path), &[]).unwrap();
        assert_eq!(
            Path::new(&scene.static_fem.mesh),
            dir.path().join("strip.msh"),
            "static.mesh of a scene read by uq resolves against the scene's folder"
        );
        assert_eq!(
            scatter.friction, 0.02,
            "spread of μ from the file's [scatter]"
        );
        let e = load_uq_inputs(Some(&dir.path().join("missing.toml")), &[]).unwrap_err();
        assert!(
            matches!(e, UqInputError::Scene(SceneError::Io { .. })),
            "an unreadable scene is a scene I/O error: {e}"
        );
    }

    #[test]
    fn both_names_of_the_friction_spread_on_the_command_line_are_refused() {
        let e = spec(&["friction.scatter=0.02", "scatter.friction=0.01"]).unwrap_err();
        assert!(
            e.contains("friction.scatter and --set scatter.friction"),
            "{e}"
        );
        let s = spec(&["scatter.friction=0.02", "scatter.friction=0.01"]).unwrap();
        assert_eq!(s.friction, 0.01, "a repeated --set keeps the last value");
    }
}
