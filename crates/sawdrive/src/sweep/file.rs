//! Sweep files: a grid of scene overrides run through the pipeline.
//!
//! ```toml
//! name = "post-count"                 # results go to OUT/<name>/
//! scene = "motor.toml"                # optional, relative to the sweep file; default scene otherwise
//! set = { "model.dynamics" = "periodic-average" }   # fixed overrides for every point
//!
//! [grid]                              # cartesian product over scene keys (any --set key)
//! preload = ["5 N", "10 N", "20 N"]
//!
//! [[variants]]                        # optional: coupled overrides, each crossed with the grid
//! label = "20 um"
//! set = { "posts.diameter" = "20 um", "posts.count" = "100x100" }
//!
//! [[charts]]                          # one chart per entry: y against x, one series per variant
//! x = "preload_n"
//! y = "stall_thrust_n"
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

/// Most points one sweep may have: each point is a pipeline run of a second or more, so 10 000
/// points is hours of work on one machine; larger studies are split or sharded by the user.
pub const MAX_SWEEP_POINTS: usize = 10_000;

/// A sweep as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    /// Name of the sweep; results go to `OUT/<name>/`.
    pub name: String,
    /// Free text.
    #[serde(default)]
    pub description: String,
    /// Scene file the grid modifies, relative to the sweep file.
    pub scene: Option<PathBuf>,
    /// Overrides applied to every point.
    #[serde(default)]
    pub set: BTreeMap<String, toml::Value>,
    /// Cartesian grid: key → list of values.
    #[serde(default)]
    pub grid: BTreeMap<String, Vec<toml::Value>>,
    /// Coupled overrides, each crossed with the grid.
    #[serde(default)]
    pub variants: Vec<Variant>,
    /// Charts drawn from the results table.
    #[serde(default)]
    pub charts: Vec<ChartSpec>,
}

/// A named set of overrides that go together (e.g. post diameter and count at equal area).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Variant {
    /// Legend label.
    pub label: String,
    /// Overrides.
    pub set: BTreeMap<String, toml::Value>,
}

/// One chart of the sweep: `y` against `x`, one series per variant (or per value of `series`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChartSpec {
    /// Results column on the x axis.
    pub x: String,
    /// Results column on the y axis.
    pub y: String,
    /// Grid key whose values make the series (default: the variants).
    pub series: Option<String>,
    /// Chart title (default: "y vs x").
    pub title: Option<String>,
    /// File stem (default: "y_vs_x").
    pub file: Option<String>,
}

/// Why a sweep file was refused.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The file could not be read.
    #[error("cannot read sweep {path}: {source}")]
    Io {
        /// File at fault.
        path: String,
        /// Underlying error.
        source: std::io::Error,
    },
    /// Not valid TOML, or an unknown or malformed key.
    #[error("{path}: {field}: {message}")]
    Field {
        /// File at fault.
        path: String,
        /// Dotted path of the key.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// A grid that has no point, or a chart naming an unknown column.
    #[error("{path}: {message}")]
    Invalid {
        /// File at fault.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// One point of a sweep: its label and the overrides that define it.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepPoint {
    /// Variant label ("" without variants).
    pub variant: String,
    /// Grid values of this point, by key, as written.
    pub grid_values: BTreeMap<String, String>,
    /// All `key=value` overrides of this point, in application order.
    pub overrides: Vec<String>,
}

/// Text of a TOML value as `--set` takes it: strings bare, others as TOML.
fn override_text(value: &toml::Value) -> String {
    match value {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

impl SweepFile {
    /// Read and check a sweep file.
    pub fn load(path: &Path) -> Result<Self, SweepError> {
        let shown = path.display().to_string();
        let text = atomic_files::read_input_text(path, atomic_files::MAX_SETTINGS_FILE_BYTES)
            .map_err(|e| SweepError::Io {
                path: shown.clone(),
                source: e.into_parts().1,
            })?;
        let field = |e: motor::input::InputError| SweepError::Field {
            path: shown.clone(),
            field: e.field,
            message: e.message,
        };
        let table = motor::input::parse_table(&text).map_err(field)?;
        let mut sweep: SweepFile = motor::input::from_table(table).map_err(field)?;
        sweep.check().map_err(|message| SweepError::Invalid {
            path: shown.clone(),
            message,
        })?;
        if let Some((key, _)) = sweep.grid.iter().find(|(_, values)| values.is_empty()) {
            return Err(SweepError::Invalid {
                path: shown,
                message: format!("grid.{key} is empty: give at least one value"),
            });
        }
        if sweep.grid.is_empty() && sweep.variants.is_empty() {
            return Err(SweepError::Invalid {
                path: shown,
                message: "the sweep has no [grid] and no [[variants]]: nothing to run".into(),
            });
        }
        if let Some(scene) = &sweep.scene
            && scene.is_relative()
        {
            sweep.scene = Some(path.parent().unwrap_or(Path::new(".")).join(scene));
        }
        Ok(sweep)
    }

    /// Names that become paths are one safe component, labels are printable and distinct,
    /// chart series name a grid key, and the grid has at most [`MAX_SWEEP_POINTS`] points.
    fn check(&self) -> Result<(), String> {
        atomic_files::check_name(&self.name).map_err(|e| format!("name: {e}"))?;
        for (i, chart) in self.charts.iter().enumerate() {
            if let Some(file) = &chart.file {
                atomic_files::check_name(file).map_err(|e| format!("charts[{i}].file: {e}"))?;
            }
            if let Some(series) = chart
                .series
                .as_ref()
                .filter(|k| !self.grid.contains_key(*k))
            {
                return Err(format!(
                    "charts[{i}].series: {series:?} is not a [grid] key (grid keys: {})",
                    self.grid.keys().cloned().collect::<Vec<_>>().join(", ")
                ));
            }
        }
        let mut labels = std::collections::BTreeSet::new();
        for (i, variant) in self.variants.iter().enumerate() {
            if variant.label.chars().any(char::is_control) {
                return Err(format!(
                    "variants[{i}].label {:?}: control characters are refused",
                    variant.label
                ));
            }
            if !labels.insert(variant.label.as_str()) {
                return Err(format!(
                    "variants[{i}].label {:?} is used twice: each variant needs its own label",
                    variant.label
                ));
            }
        }
        let points = self
            .grid
            .values()
            .try_fold(self.variants.len().max(1), |n, v| {
                n.checked_mul(v.len()).filter(|&n| n <= MAX_SWEEP_POINTS)
            });
        if points.is_none() {
            return Err(format!(
                "the grid has more than {MAX_SWEEP_POINTS} points ({} variants × {}): split it into several sweeps",
                self.variants.len().max(1),
                self.grid
                    .iter()
                    .map(|(k, v)| format!("{} {k}", v.len()))
                    .collect::<Vec<_>>()
                    .join(" × ")
            ));
        }
        Ok(())
    }

    /// Every point: the variants (or one unnamed) crossed with the cartesian grid.
    pub fn points(&self) -> Vec<SweepPoint> {
        let fixed: Vec<String> = self
            .set
            .iter()
            .map(|(k, v)| format!("{k}={}", override_text(v)))
            .collect();
        let variants: Vec<(String, Vec<String>)> = if self.variants.is_empty() {
            vec![(String::new(), Vec::new())]
        } else {
            self.variants
                .iter()
                .map(|v| {
                    (
                        v.label.clone(),
                        v.set
                            .iter()
                            .map(|(k, val)| format!("{k}={}", override_text(val)))
                            .collect(),
                    )
                })
                .collect()
        };
        let mut combos: Vec<BTreeMap<String, String>> = vec![BTreeMap::new()];
        for (key, values) in &self.grid {
            combos = combos
                .into_iter()
                .flat_map(|combo| {
                    values.iter().map(move |value| {
                        let mut next = combo.clone();
                        next.insert(key.clone(), override_text(value));
                        next
                    })
                })
                .collect();
        }
        let mut points = Vec::new();
        for (label, variant_overrides) in &variants {
            for combo in &combos {
                let mut overrides = fixed.clone();
                overrides.extend(variant_overrides.iter().cloned());
                overrides.extend(combo.iter().map(|(k, v)| format!("{k}={v}")));
                points.push(SweepPoint {
                    variant: label.clone(),
                    grid_values: combo.clone(),
                    overrides,
                });
            }
        }
        points
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sweep(text: &str) -> Result<SweepFile, SweepError> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.toml");
        std::fs::write(&path, text).unwrap();
        SweepFile::load(&path)
    }

    #[test]
    fn grid_is_crossed_with_variants() {
        let s = sweep(
            "name = \"s\"\nset = { \"model.dynamics\" = \"periodic-average\" }\n[grid]\npreload = [\"5 N\", \"10 N\"]\nfriction = [0.2, 0.3]\n\
             [[variants]]\nlabel = \"20 um\"\nset = { \"posts.diameter\" = \"20 um\" }\n\
             [[variants]]\nlabel = \"50 um\"\nset = { \"posts.diameter\" = \"50 um\", \"posts.count\" = \"40x40\" }\n",
        )
        .unwrap();
        let points = s.points();
        assert_eq!(points.len(), 8, "2 variants × 2 preloads × 2 frictions");
        assert_eq!(
            points[0].overrides[0], "model.dynamics=periodic-average",
            "fixed overrides first"
        );
        assert!(
            points[7]
                .overrides
                .contains(&"posts.count=40x40".to_string())
        );
        assert!(points[7].overrides.contains(&"friction=0.3".to_string()));
    }

    #[test]
    fn empty_grids_and_unknown_keys_are_refused() {
        let err = sweep("name = \"s\"\n[grid]\npreload = []\n")
            .unwrap_err()
            .to_string();
        assert!(err.contains("grid.preload is empty"), "{err}");
        let err = sweep("name = \"s\"\n").unwrap_err().to_string();
        assert!(err.contains("nothing to run"), "{err}");
        let err = sweep("name = \"s\"\ngrdi = 3\n").unwrap_err().to_string();
        assert!(err.contains("grdi"), "{err}");
    }

    #[test]
    fn names_that_would_write_outside_out_are_refused() {
        for (text, says) in [
            ("name = \"../escaped\"", "name: \"../escaped\""),
            ("name = \"..\"", "name:"),
            ("name = \"/abs/path\"", "name:"),
            ("name = \".cache\"", "name:"),
            ("name = \"\"", "name:"),
            (
                "name = \"s\"\n[[charts]]\nx = \"preload_n\"\ny = \"speed_m_per_s\"\nfile = \"/any/path/victim\"",
                "charts[0].file",
            ),
        ] {
            let err = sweep(&format!("{text}\n[grid]\npreload = [\"5 N\"]\n"))
                .unwrap_err()
                .to_string();
            assert!(err.contains(says), "{text}: {err}");
        }
    }

    #[test]
    fn settings_that_would_be_ignored_or_explode_are_refused() {
        let err = sweep(
            "name = \"s\"\n[grid]\npreload = [\"5 N\"]\n[[charts]]\nx = \"a\"\ny = \"b\"\nseries = \"friction\"\n",
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("not a [grid] key"), "{err}");
        let err = sweep(
            "name = \"s\"\n[[variants]]\nlabel = \"a\"\nset = {}\n[[variants]]\nlabel = \"a\"\nset = {}\n",
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("used twice"), "{err}");
        let err = sweep("name = \"s\"\n[[variants]]\nlabel = \"a\\u001b[2J\"\nset = {}\n")
            .unwrap_err()
            .to_string();
        assert!(err.contains("control characters"), "{err}");
        let values = vec!["1"; 101].join(", ");
        let err = sweep(&format!(
            "name = \"s\"\n[grid]\na = [{values}]\nb = [{values}]\nc = [{values}]\n"
        ))
        .unwrap_err()
        .to_string();
        assert!(
            err.contains("more than 10000 points") && err.contains("101 a"),
            "{err}"
        );
    }
}
