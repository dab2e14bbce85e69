//! The `[scatter]` section: which inputs scatter, and how. Each entry is named by the scene key
//! whose value it spreads, with that key's human unit (parsed by the evaluator as that key).
//!
//! ```toml
//! [scatter]
//! distribution = "normal"         # normal: values below are standard deviations (truncated to
//!                                 # the physical range); uniform: half-widths around the nominal
//! posts.height_scatter = "5 nm"   # σ of each post's extra height (Gaussian, a new seed per sample)
//! slider.tilt_x = "10 nm"         # spread of the tilt across the length (zero mean)
//! slider.tilt_y = "10 nm"         # … across the width
//! slider.bow = "5 nm"             # spread of the bow (zero mean)
//! friction = 0.03                 # spread of both coefficients of the scene's [friction]
//!                                 # (μ_s and μ_k drawn independently, μ_k ≤ μ_s)
//! load.preload = "2 N"            # preload tolerance
//! posts.diameter = "0.5 um"       # post-diameter tolerance (one etch bias for all posts)
//! ```
//!
//! Dotted keys may also be quoted (`"posts.diameter" = "0.5 um"`), and set from the command line
//! (`--set scatter.posts.diameter=0.5um`). Every key is optional (0: no scatter). Negative
//! spreads, unknown keys and missing units are errors naming `scatter.<key>`; a key of the
//! former spelling (`height_scatter`, `tilt_x`, `tilt_y`, `bow`, `preload`, `diameter`) is
//! refused with its scene-key spelling ([`RENAMED_SCATTER_KEYS`]). Normal draws of μ, P and d
//! are truncated to [[`MIN_FRICTION`], ∞), (0, ∞) and (0, ∞): a uniform range reaching below
//! them is refused.

use serde::{Deserialize, Serialize};

use std::path::Path;

use crate::error::StudyError;
use crate::evaluator::{Evaluator, MotorSample, SceneFacts};
use crate::{Distribution, ScatterInput};

/// Smallest friction coefficient a draw may take (the dynamic model needs μ > 0 to drive).
pub const MIN_FRICTION: f64 = 1e-3;
/// Smallest fraction of the nominal preload or diameter a draw may take.
pub const MIN_FRACTION_OF_NOMINAL: f64 = 1e-3;
/// Upper end of the one-sided truncations ("no upper limit").
const UNBOUNDED: f64 = 1e300;

/// How a spread is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
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

/// Keys of `[scatter]`: the scene keys whose values scatter (and `distribution`).
pub const SCATTER_KEYS: [&str; 8] = [
    "distribution",
    "posts.height_scatter",
    "slider.tilt_x",
    "slider.tilt_y",
    "slider.bow",
    "friction",
    "load.preload",
    "posts.diameter",
];

/// The former `[scatter]` keys and their scene-key spelling (refused, naming the new one).
pub const RENAMED_SCATTER_KEYS: [(&str, &str); 6] = [
    ("height_scatter", "posts.height_scatter"),
    ("tilt_x", "slider.tilt_x"),
    ("tilt_y", "slider.tilt_y"),
    ("bow", "slider.bow"),
    ("preload", "load.preload"),
    ("diameter", "posts.diameter"),
];

pub use motor::input::dotted_keys;

/// The `[scatter]` section as written: each entry under the scene key whose value it spreads
/// (`posts.diameter = "0.5 um"`), every table refusing unknown keys. Quantities keep their text
/// ([`Quantity`]) until the evaluator parses them as their scene key.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScatterFile {
    /// `normal` (standard deviations) or `uniform` (half-widths).
    #[serde(default)]
    pub distribution: SpreadKind,
    /// `posts.height_scatter`, `posts.diameter`.
    #[serde(default)]
    pub posts: PostsScatter,
    /// `slider.tilt_x`, `slider.tilt_y`, `slider.bow`.
    #[serde(default)]
    pub slider: SliderScatter,
    /// `load.preload`.
    #[serde(default)]
    pub load: LoadScatter,
    /// Spread of both friction coefficients.
    pub friction: Option<f64>,
}

/// `[scatter]` entries under `posts`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PostsScatter {
    /// σ of each post's extra height.
    pub height_scatter: Option<Quantity>,
    /// Post-diameter tolerance.
    pub diameter: Option<Quantity>,
}

/// `[scatter]` entries under `slider`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SliderScatter {
    /// Spread of the tilt across the length.
    pub tilt_x: Option<Quantity>,
    /// Spread of the tilt across the width.
    pub tilt_y: Option<Quantity>,
    /// Spread of the bow.
    pub bow: Option<Quantity>,
}

/// `[scatter]` entries under `load`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadScatter {
    /// Preload tolerance.
    pub preload: Option<Quantity>,
}

/// A quantity as written in a study file, `"20 um"`: its text, parsed by the evaluator as the
/// scene key it belongs to (the scene's own units and parser); a bare number is refused here.
#[derive(Debug, Clone, PartialEq)]
pub struct Quantity(pub String);

impl<'de> Deserialize<'de> for Quantity {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        match toml::Value::deserialize(deserializer)? {
            toml::Value::String(text) => Ok(Quantity(text)),
            other => Err(serde::de::Error::custom(format!(
                "expected a quantity with its unit, like \"20 um\", got {other}"
            ))),
        }
    }
}

fn quantity<E: Evaluator>(ev: &E, q: &Option<Quantity>, key: &str) -> Result<f64, StudyError> {
    match q {
        None => Ok(0.0),
        Some(Quantity(text)) => {
            let value = ev
                .quantity(key, text)
                .map_err(|e| StudyError::input(format!("scatter.{key}"), e))?;
            spread(value, key)
        }
    }
}

fn spread(value: f64, key: &str) -> Result<f64, StudyError> {
    if value >= 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(StudyError::input(
            format!("scatter.{key}"),
            format!("spread {value} must be ≥ 0 and finite"),
        ))
    }
}

/// The former `[scatter]` keys, for [`motor::input::first_moved`].
fn renamed_scatter_keys() -> Vec<(String, String)> {
    RENAMED_SCATTER_KEYS
        .iter()
        .map(|(old, new)| (format!("scatter.{old}"), format!("scatter.{new} (`{new} = …` in [scatter]): scatter entries are named by the scene key they spread")))
        .collect()
}

impl ScatterSpec {
    /// Reads the `[scatter]` table (dotted or quoted scene keys) into [`ScatterFile`]; errors
    /// are one line naming `scatter.<key>`, a former key naming its scene key. Quantities are
    /// parsed by `ev`, as the scene key they spread.
    pub fn from_table<E: Evaluator>(ev: &E, table: &toml::Table) -> Result<Self, StudyError> {
        let mut wrapped = toml::Table::new();
        wrapped.insert(
            "scatter".into(),
            toml::Value::Table(motor::input::nest_dotted_keys(table)),
        );
        let renamed = renamed_scatter_keys();
        let renamed: Vec<(&str, &str)> = renamed
            .iter()
            .map(|(o, n)| (o.as_str(), n.as_str()))
            .collect();
        if let Some(e) = motor::input::first_moved(&wrapped, &renamed) {
            return Err(StudyError::input(
                e.field,
                format!("renamed: {}", e.message),
            ));
        }
        #[derive(Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Section {
            scatter: ScatterFile,
        }
        let file = motor::input::from_table::<Section>(wrapped)
            .map_err(|e| StudyError::input(e.field, e.message))?
            .scatter;
        Ok(Self {
            distribution: file.distribution,
            height_scatter_m: quantity(ev, &file.posts.height_scatter, "posts.height_scatter")?,
            tilt_x_m: quantity(ev, &file.slider.tilt_x, "slider.tilt_x")?,
            tilt_y_m: quantity(ev, &file.slider.tilt_y, "slider.tilt_y")?,
            bow_m: quantity(ev, &file.slider.bow, "slider.bow")?,
            friction: spread(file.friction.unwrap_or(0.0), "friction")?,
            preload_n: quantity(ev, &file.load.preload, "load.preload")?,
            diameter_m: quantity(ev, &file.posts.diameter, "posts.diameter")?,
        })
    }

    /// Spreads within the range where the models hold (the scene's bounds): friction spread ≤
    /// the largest coefficient, height scatter ≤ h/3, tilt and bow spreads ≤ h, preload and
    /// diameter spreads below their nominal values.
    fn check_physical(&self, facts: &SceneFacts) -> Result<(), StudyError> {
        let h = facts.post_height_m;
        let checks = [
            (
                "friction",
                self.friction,
                facts.max_friction,
                "the largest friction coefficient",
            ),
            (
                "posts.height_scatter",
                self.height_scatter_m,
                h / 3.0,
                "a third of the post height",
            ),
            ("slider.tilt_x", self.tilt_x_m, h, "the post height"),
            ("slider.tilt_y", self.tilt_y_m, h, "the post height"),
            ("slider.bow", self.bow_m, h, "the post height"),
            (
                "load.preload",
                self.preload_n,
                facts.preload_n,
                "the nominal preload",
            ),
            (
                "posts.diameter",
                self.diameter_m,
                facts.post_diameter_m,
                "the nominal diameter",
            ),
        ];
        match checks.iter().find(|(_, spread, max, _)| spread > max) {
            None => Ok(()),
            Some((key, spread, max, what)) => Err(StudyError::input(
                format!("scatter.{key}"),
                format!(
                    "spread {spread:e} exceeds {what} ({max:e}, SI): the models do not hold there"
                ),
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

    /// The scattered inputs (names with units) around the scene's nominal values, validated;
    /// errors name `scatter.<key>`. Order: the fields of [`MotorSample`] except the seed.
    pub fn inputs(&self, facts: &SceneFacts) -> Result<Vec<ScatterInput>, StudyError> {
        self.check_physical(facts)?;
        let zero_mean = |spread: f64| self.around(0.0, spread, -UNBOUNDED);
        let list = [
            (
                "preload_n",
                "load.preload",
                self.around(
                    facts.preload_n,
                    self.preload_n,
                    MIN_FRACTION_OF_NOMINAL * facts.preload_n,
                ),
            ),
            (
                "post_diameter_m",
                "posts.diameter",
                self.around(
                    facts.post_diameter_m,
                    self.diameter_m,
                    MIN_FRACTION_OF_NOMINAL * facts.post_diameter_m,
                ),
            ),
            (
                "mu_static",
                "friction",
                self.around(facts.mu_static, self.friction, MIN_FRICTION),
            ),
            (
                "mu_kinetic",
                "friction",
                self.around(facts.mu_kinetic, self.friction, MIN_FRICTION),
            ),
            ("tilt_x_m", "slider.tilt_x", zero_mean(self.tilt_x_m)),
            ("tilt_y_m", "slider.tilt_y", zero_mean(self.tilt_y_m)),
            ("bow_m", "slider.bow", zero_mean(self.bow_m)),
        ];
        list.into_iter()
            .map(|(name, key, distribution)| {
                distribution.validate(&format!("scatter.{key}"))?;
                if let Distribution::Uniform { low, .. } = distribution {
                    let floor = match key {
                        "friction" => MIN_FRICTION,
                        "load.preload" | "posts.diameter" => 0.0,
                        _ => -UNBOUNDED,
                    };
                    if low <= floor {
                        return Err(StudyError::input(
                            format!("scatter.{key}"),
                            format!(
                                "the uniform range reaches {low}, below the physical limit {floor}"
                            ),
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

    /// Takes the scene's own scatter keys into the spec: `posts.height_scatter` (σ of the post
    /// heights; each sample then draws its own heights from `--seed`, so `posts.scatter_seed` is
    /// not used) when `scatter.height_scatter` is not given. The scene's deterministic shape
    /// (`slider.tilt_x`, `slider.tilt_y`, `slider.bow`, `posts.height_map`) is refused: the UQ
    /// draws tilt and bow around zero from `scatter.*` spreads. Errors are one line naming the key.
    pub fn with_scene_keys(mut self, facts: &SceneFacts) -> Result<Self, StudyError> {
        for (key, value) in [
            ("slider.tilt_x", facts.tilt_x_m),
            ("slider.tilt_y", facts.tilt_y_m),
            ("slider.bow", facts.bow_m),
        ] {
            if value != 0.0 {
                return Err(StudyError::input(
                    key,
                    format!(
                        "uq draws the slider's shape around zero; give its spread as \
                         scatter.{key} instead of a fixed value"
                    ),
                ));
            }
        }
        if facts.has_height_map {
            return Err(StudyError::input(
                "posts.height_map",
                "uq draws the post heights (scatter.posts.height_scatter or posts.height_scatter); \
                 a measured map is not sampled",
            ));
        }
        if facts.height_scatter_m > 0.0 {
            if self.height_scatter_m > 0.0 {
                return Err(StudyError::Conflict(
                    "posts.height_scatter and scatter.posts.height_scatter both give the σ of \
                     the post heights; keep one"
                        .into(),
                ));
            }
            self.height_scatter_m = facts.height_scatter_m;
        }
        Ok(self)
    }
}

/// The scene part (without `[scatter]`), the scene overrides and the scatter table of a scene
/// file's text and its `--set` overrides.
pub type SplitInputs = (Option<String>, Vec<String>, toml::Table);

/// Splits a scene file's text into the scene (without `[scatter]`) and the scatter table, and
/// the `--set` overrides into scene overrides and `scatter.*` ones (applied to the table).
pub fn split_scatter(
    scene_text: Option<&str>,
    overrides: &[String],
) -> Result<SplitInputs, StudyError> {
    let mut table = toml::Table::new();
    let scene = match scene_text {
        Some(text) => {
            let mut doc: toml::Table = text.parse().map_err(|e: toml::de::Error| {
                StudyError::input(
                    "scene",
                    format!(
                        "not valid TOML: {}",
                        e.to_string().trim().replace('\n', " ")
                    ),
                )
            })?;
            if let Some(v) = doc.remove("scatter") {
                table = v
                    .as_table()
                    .cloned()
                    .ok_or_else(|| StudyError::input("scatter", "must be a table ([scatter])"))?;
            }
            let friction_scatter = doc
                .get_mut("friction")
                .and_then(toml::Value::as_table_mut)
                .and_then(|f| f.remove("scatter"));
            if let Some(v) = friction_scatter {
                if table.contains_key("friction") {
                    return Err(StudyError::Conflict(
                        "friction.scatter and scatter.friction both give the spread of μ; \
                         keep one"
                            .into(),
                    ));
                }
                table.insert("friction".into(), v);
            }
            Some(toml::to_string(&doc).map_err(|e| StudyError::input("scene", e))?)
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
                return Err(StudyError::Conflict(
                    "--set friction.scatter and --set scatter.friction both give the \
                     spread of μ; keep one"
                        .into(),
                ));
            }
        }
        match o.strip_prefix("scatter.") {
            Some(kv) => {
                let (k, v) = kv.split_once('=').ok_or_else(|| {
                    StudyError::input(format!("--set {o}"), "expected scatter.KEY=VALUE")
                })?;
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

/// The scene and scatter of `sawdrive uq [SCENE] --set …` (the command's and Python's one
/// reader): the scene file's `[scatter]` section, `friction.scatter` and the `scatter.*`
/// overrides form the scatter ([`split_scatter`]); the rest is the scene, read by the
/// evaluator's scene loader from the file's own path (relative paths resolve against its
/// folder); then the scene's own scatter keys join the scatter
/// ([`ScatterSpec::with_scene_keys`]). A scene that cannot be read is
/// [`StudyError::Model`] (the evaluator's error as its source).
pub fn load_uq_inputs<E: Evaluator>(
    ev: &E,
    path: Option<&Path>,
    overrides: &[String],
) -> Result<(E::Scene, ScatterSpec), StudyError> {
    let text = match path {
        Some(p) => Some(ev.read_scene_file(p).map_err(StudyError::Model)?),
        None => None,
    };
    let (scene_text, overrides, table) = split_scatter(text.as_deref(), overrides)?;
    let scatter = ScatterSpec::from_table(ev, &table)?;
    let file = path.zip(scene_text.as_deref());
    let scene = ev
        .load_scene_text(file, &overrides)
        .map_err(StudyError::Model)?;
    let scatter = scatter.with_scene_keys(&ev.facts(&scene))?;
    Ok((scene, scatter))
}
