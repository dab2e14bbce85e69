//! Static stage, whole-slider model (`static.model = "slider"`): every post of the
//! slider on the frozen wave ([`slider_contact`], docs/physics.md §6), with the motor's
//! imperfections and preload mechanism.
//!
//! Two scales (slider-contact's README): the post's own near field s_post comes from the
//! one-off strip FEM of the scene's post cell ([`slider_contact::calibrate_near_field`] on
//! static_contact's one-row strip: post column, bonded base, mesh), cached by the strip's
//! geometry as `near-field-<key>.json`; the lattice far field and the contact solves run per
//! scene and are cached as `slider-<content hash>.json`, the hash covering every input of
//! [`SliderParams`] (near field, phases, tolerance, imperfections including the seed and every
//! height of a measured map, mechanism). Both entries carry the SHA-256 of their JSON and are
//! rebuilt, with a note on stderr, when that check fails. Post-force maps are drawn from the
//! report (charts crate), never computed in the plotting code.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use charts::{CategoryMap, write_category_map};
use serde::{Deserialize, Serialize};
use slider_contact::{
    LatticeGeometry, NearFieldCalibration, SliderError, SliderParams, SliderReport,
};

use super::cache::{self, Entry, Layout, Lookup};
use super::keys::{geometry_key, sha256_hex, static_params};
use crate::output::io;
use crate::pipeline::PipelineError;
use crate::scene::{Scene, StaticModel};

/// The cache entries of this module (near field, whole-slider stage): the value and the SHA-256
/// of its JSON; the inputs' hash is in the file name and checked against the value's own.
const SLIDER_ENTRY: Layout = Layout {
    format: 1,
    key_field: None,
    hash_field: "sha256",
    sidecar_field: None,
    value_field: "value",
};

/// Posts above which the post-force map is written as PNG only (its SVG, one rectangle per
/// post, would be ≈ 0.9 MB at 10 000 posts). Default 2500.
const SVG_MAP_MAX_POSTS: usize = 2500;

/// Force classes of the post-force map, upper bounds in units of the mean post force P/N.
const FORCE_CLASSES: [(f64, &str); 6] = [
    (0.0, "lifted off"),
    (0.5, "< 0.5 P/N"),
    (1.0, "0.5–1 P/N"),
    (2.0, "1–2 P/N"),
    (4.0, "2–4 P/N"),
    (f64::INFINITY, "> 4 P/N"),
];

/// The whole-slider static stage's result: the library's report, the near field it used and
/// the content hash of its inputs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SliderStage {
    /// SHA-256 of every input ([`slider_content_hash`]).
    pub content_hash: String,
    /// The post lattice on the slider (positions of the map).
    pub geometry: LatticeGeometry,
    /// The near field taken from the strip FEM.
    pub near_field: NearFieldCalibration,
    /// The library's report (η, forces and gaps per phase, timings).
    pub report: SliderReport,
}

/// Reads a verified entry of `cache_dir/name`, noting (and dropping) a damaged or foreign one
/// (`matches`: whether the value is of the inputs asked for).
fn cached<T: Serialize + for<'de> Deserialize<'de>>(
    cache_dir: Option<&Path>,
    name: &str,
    matches: impl Fn(&T) -> bool,
    notes: &mut Vec<String>,
) -> Option<T> {
    let file = cache_dir?.join(name);
    let entry = entry(&file);
    match cache::get(&entry, |value: &T| match matches(value) {
        true => Ok(()),
        false => Err("it holds other inputs".into()),
    }) {
        Lookup::Hit(value) => Some(value),
        Lookup::Miss => None,
        Lookup::Damaged(why) => {
            notes.push(format!(
                "cache entry {} not used: {why}; recomputing it",
                file.display()
            ));
            None
        }
    }
}

/// The entry `file` of this module's layout.
fn entry(file: &Path) -> Entry<'_> {
    Entry {
        file,
        layout: &SLIDER_ENTRY,
        key: "",
        sidecars: None,
    }
}

/// The library's errors name the scene keys; they reach the user as one line.
fn slider_error(e: SliderError) -> PipelineError {
    PipelineError::Unsupported {
        stage: "static (whole slider)",
        message: e.to_string(),
    }
}

/// The near field of the scene's post cell: from the cache, or the strip FEM (one row) of the
/// scene's geometry, mesh and element order. Returns it and the FEM's seconds (0 if cached).
fn near_field(
    scene: &Scene,
    cache_dir: Option<&Path>,
    notes: &mut Vec<String>,
) -> Result<(NearFieldCalibration, f64), PipelineError> {
    let mut strip = static_params(scene, cache_dir.map(|d| d.join("meshes")).as_deref())?;
    strip.strip_rows = 1;
    let name = format!("near-field-{}.json", geometry_key(&strip)?);
    if let Some(cal) = cached(cache_dir, &name, |_: &NearFieldCalibration| true, notes) {
        return Ok((cal, 0.0));
    }
    let start = Instant::now();
    let prepared = static_contact::prepare_strip(&strip)?;
    notes.extend(prepared.notes.iter().cloned());
    let cal = slider_contact::calibrate_near_field(&prepared.model, strip.slider_thickness_m)
        .map_err(slider_error)?;
    if let Some(dir) = cache_dir {
        cache::put(&entry(&dir.join(&name)), &cal)?;
    }
    Ok((cal, start.elapsed().as_secs_f64()))
}

/// The whole-slider parameters of `scene` ([`SliderParams::for_motor`]: lattice, materials,
/// wave, preload, imperfections, mechanism) with the scene's phases and complementarity
/// tolerance ([`crate::scene::StaticSettings::tolerance_for`]) and the near field `cal`.
pub fn slider_params(scene: &Scene, cal: &NearFieldCalibration) -> SliderParams {
    let mut params = SliderParams::for_motor(&scene.motor);
    params.phases = scene.static_fem.phases as usize;
    params.solver.tolerance = scene.static_fem.tolerance_for(StaticModel::Slider);
    params.near_field = cal.near_field();
    params
}

/// SHA-256 of every input of the whole-slider run (the parameters' JSON: near field, lattice,
/// materials, wave, preload, phases, solver, imperfections with seed and map heights, mechanism).
pub fn slider_content_hash(params: &SliderParams) -> Result<String, PipelineError> {
    let bytes = serde_json::to_vec(&("slider-contact", SLIDER_ENTRY.format, params))?;
    Ok(sha256_hex(&bytes))
}

/// The whole-slider static stage of `scene`: near field (cached one-off strip FEM), then the
/// contact of every post at each phase, or the verified cached report of the same inputs.
/// Returns the stage, the FEM's seconds (0 when the near field was cached), whether the report
/// came from the cache, and the notes (also printed on stderr).
pub fn run_slider_static(
    scene: &Scene,
    cache_dir: Option<&Path>,
) -> Result<(SliderStage, f64, bool, Vec<String>), PipelineError> {
    run_slider_static_at(scene, cache_dir, &[])
}

/// The whole slider's η under a local amplitude profile (`amplitude_scale_x`: A/A₀ of each post
/// column, x ascending, the energy-conserving wave's): the static stage's contact solves on the
/// wave each post sees, with the same near field and verified cache (the profile is part of the
/// content hash). `None`: not identifiable. The cache's notes are printed on stderr.
pub fn slider_eta_at_profile(
    scene: &Scene,
    cache_dir: Option<&Path>,
    amplitude_scale_x: &[f64],
) -> Result<Option<f64>, PipelineError> {
    let (stage, _, _, notes) = run_slider_static_at(scene, cache_dir, amplitude_scale_x)?;
    announce(&notes);
    Ok(stage.report.effective_contact_ratio)
}

/// [`run_slider_static`] under the local amplitude `amplitude_scale_x` (empty: the constant wave).
fn run_slider_static_at(
    scene: &Scene,
    cache_dir: Option<&Path>,
    amplitude_scale_x: &[f64],
) -> Result<(SliderStage, f64, bool, Vec<String>), PipelineError> {
    let mut notes = Vec::new();
    let (cal, fem_s) = near_field(scene, cache_dir, &mut notes)?;
    let mut params = slider_params(scene, &cal);
    params.amplitude_scale_x = amplitude_scale_x.to_vec();
    let content_hash = slider_content_hash(&params)?;
    let name = format!("slider-{content_hash}.json");
    let hit = cached(
        cache_dir,
        &name,
        |s: &SliderStage| s.content_hash == content_hash,
        &mut notes,
    );
    if let Some(stage) = hit {
        return Ok((stage, fem_s, true, notes));
    }
    let report = slider_contact::run(&params).map_err(slider_error)?;
    let stage = SliderStage {
        content_hash,
        geometry: params.geometry(),
        near_field: cal,
        report,
    };
    if let Some(dir) = cache_dir {
        cache::put(&entry(&dir.join(&name)), &stage)?;
    }
    Ok((stage, fem_s, false, notes))
}

/// Post-force class of `force_n` given the mean post force.
fn force_class(force_n: f64, mean_n: f64) -> usize {
    if force_n <= 0.0 {
        return 0;
    }
    FORCE_CLASSES
        .iter()
        .position(|(hi, _)| force_n / mean_n < *hi)
        .unwrap_or(FORCE_CLASSES.len() - 1)
}

/// Writes the 2D post-force map of the first phase (θ₀ = 0) into `dir`: `post_forces.csv`
/// (row, column, x_m, y_m, force_n, gap_m; rows along y, columns along x, positions from the
/// slider's corner) and `post_force_map.png` (+ `.svg` up to `SVG_MAP_MAX_POSTS` posts).
pub fn write_slider_maps(stage: &SliderStage, dir: &Path) -> Result<Vec<PathBuf>, PipelineError> {
    let r = &stage.report;
    let (nx, ny) = (r.posts_x, r.posts_y);
    let Some(first) = r.snapshots.first() else {
        return Ok(Vec::new());
    };
    let g = &stage.geometry;
    let (x_m, y_m) = (|i| g.x_m(i), |j| g.y_m(j));
    let csv = dir.join("post_forces.csv");
    let mut text = String::from("row,column,x_m,y_m,force_n,gap_m\n");
    for i in 0..nx {
        for j in 0..ny {
            let k = i * ny + j;
            text.push_str(&format!(
                "{j},{i},{:e},{:e},{:e},{:e}\n",
                x_m(i),
                y_m(j),
                first.force_n[k],
                first.gap_m[k]
            ));
        }
    }
    std::fs::write(&csv, text).map_err(io("write", &csv))?;
    let mean_n = r.preload_n / (nx * ny) as f64;
    let map = CategoryMap {
        title: format!(
            "post forces at θ₀ = 0, P = {} N, {} back",
            r.preload_n,
            r.mechanism.name()
        ),
        x_label: "x (mm), wave direction".into(),
        y_label: "y (mm)".into(),
        xs: (0..nx).map(|i| 1e3 * x_m(i)).collect(),
        ys: (0..ny).map(|j| 1e3 * y_m(j)).collect(),
        cells: (0..ny)
            .map(|j| {
                (0..nx)
                    .map(|i| force_class(first.force_n[i * ny + j], mean_n))
                    .collect()
            })
            .collect(),
        categories: FORCE_CLASSES.iter().map(|(_, n)| n.to_string()).collect(),
        ..CategoryMap::default()
    };
    let stem = dir.join("post_force_map");
    let mut files = vec![csv];
    for file in write_category_map(&map, &stem)? {
        let svg = file.extension().is_some_and(|e| e == "svg");
        if svg && nx * ny > SVG_MAP_MAX_POSTS {
            std::fs::remove_file(&file).map_err(io("remove", &file))?;
        } else {
            files.push(file);
        }
    }
    Ok(files)
}

/// Tells the user on stderr (one line each).
pub(super) fn announce(notes: &[String]) {
    let mut stderr = std::io::stderr().lock();
    for note in notes {
        let _ = writeln!(stderr, "note: {note}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn force_classes_put_lifted_posts_first_and_overloaded_last() {
        assert_eq!(force_class(0.0, 1.0), 0, "lifted-off post");
        assert_eq!(force_class(0.3, 1.0), 1, "below half the mean force");
        assert_eq!(force_class(1.5, 1.0), 3, "1–2 P/N");
        assert_eq!(force_class(9.0, 1.0), 5, "above 4 P/N");
    }
}
