//! The strip's tip compliances C_nn, C_tt (every post of the strip row, from the condensed strip
//! FEM) as the static stage hands them to the coupled dynamics, cached per strip geometry in
//! `compliance-<geometry key>.json` with the SHA-256 of their values (a damaged or foreign entry
//! is rebuilt). Source: the strip's condensation (`static_contact::StripModel::tip_compliance`);
//! valid for the strip geometry of the key (the preload and the wave do not enter them).

use std::path::Path;

use serde::{Deserialize, Serialize};
use static_contact::{StaticParams, StripModel};

use super::cache::{self, Entry, Layout, Lookup};
use super::keys::{geometry_key, static_params};
use super::strip::StaticOutcome;
use crate::pipeline::PipelineError;
use crate::scene::Scene;

/// The compliance cache's entries, `compliance-<geometry key>.json`: the tips with the key and
/// the SHA-256 of their JSON. Format 2: the tangential compliance from partial forward solves,
/// values within 2e-15 relative of format 1's.
const TIPS_ENTRY: Layout = Layout {
    format: 2,
    key_field: Some("geometry_key"),
    hash_field: "tips_sha256",
    sidecar_field: None,
    value_field: "tips",
};

/// The strip's posts and tip compliances (column-major n × n), as cached.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StripTips {
    /// x of each post of the strip (m).
    pub post_x_m: Vec<f64>,
    /// Normal tip compliances (m/N), column-major n × n.
    pub normal_m_per_n: Vec<f64>,
    /// Tangential tip compliances (m/N), column-major n × n.
    pub tangential_m_per_n: Vec<f64>,
    /// The strip's share of the slider's posts.
    pub strip_share: f64,
}

impl StripTips {
    fn of(strip: &StripModel, strip_share: f64) -> Result<Self, PipelineError> {
        let tips = strip.tip_compliance()?;
        Ok(Self {
            post_x_m: strip.posts.iter().map(|p| p.x_m).collect(),
            normal_m_per_n: tips.normal_m_per_n.as_slice().to_vec(),
            tangential_m_per_n: tips.tangential_m_per_n.as_slice().to_vec(),
            strip_share,
        })
    }
}

/// Store the tip compliances of a freshly condensed strip in the compliance cache of
/// `cache_dir`, so that coupled runs of its geometry (a sweep's points) need no second FEM.
pub(super) fn cache_strip_tips(
    model: &StripModel,
    params: &StaticParams,
    cache_dir: &Path,
) -> Result<(), PipelineError> {
    let key = geometry_key(params)?;
    let tips = StripTips::of(model, params.strip_share())?;
    store(
        Some(&cache_dir.join(format!("compliance-{key}.json"))),
        &key,
        &tips,
    )
}

/// The strip's tips: from the fresh static analysis, else from the verified cache, else from
/// one strip condensation (then cached). A damaged entry is rebuilt and said so on stderr.
pub fn strip_tips(
    scene: &Scene,
    statics: &StaticOutcome,
    cache_dir: Option<&Path>,
) -> Result<StripTips, PipelineError> {
    let params = static_params(scene, cache_dir.map(|d| d.join("meshes")).as_deref())?;
    let share = params.strip_share();
    let key = geometry_key(&params)?;
    let file = cache_dir.map(|d| d.join(format!("compliance-{key}.json")));
    if let Some(analysis) = &statics.analysis {
        let tips = StripTips::of(&analysis.model, share)?;
        store(file.as_deref(), &key, &tips)?;
        return Ok(tips);
    }
    if let Some(file) = &file {
        match lookup(file, &key) {
            Lookup::Hit(tips) => return Ok(tips),
            Lookup::Miss => {}
            Lookup::Damaged(why) => eprintln!(
                "note: compliance cache entry {} not used: {why}; recomputing it",
                file.display()
            ),
        }
    }
    let prepared = static_contact::prepare_strip(&params)?;
    let tips = StripTips::of(&prepared.model, share)?;
    store(file.as_deref(), &key, &tips)?;
    Ok(tips)
}

/// The entry `file` of the geometry `key`, verified (the matrices must be n × n too).
fn lookup(file: &Path, key: &str) -> Lookup<StripTips> {
    let entry = Entry {
        file,
        layout: &TIPS_ENTRY,
        key,
        sidecars: None,
    };
    cache::get(&entry, |tips: &StripTips| {
        let n = tips.post_x_m.len();
        match tips.normal_m_per_n.len() == n * n && tips.tangential_m_per_n.len() == n * n {
            true => Ok(()),
            false => Err(format!("its matrices are not {n} × {n}")),
        }
    })
}

fn store(file: Option<&Path>, key: &str, tips: &StripTips) -> Result<(), PipelineError> {
    let Some(file) = file else {
        return Ok(());
    };
    let entry = Entry {
        file,
        layout: &TIPS_ENTRY,
        key,
        sidecars: None,
    };
    cache::put(&entry, tips)
}
