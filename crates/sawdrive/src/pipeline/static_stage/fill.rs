//! The sweep's static-cache fill: one FEM condensation per distinct strip geometry, a cached
//! report for every scene of it, and the strip's tip compliances for the coupled model.

use std::path::Path;

use static_contact::StaticParams;

use super::cache::Lookup;
use super::keys::{geometry_key, static_params};
use super::slider::announce;
use super::strip::{lookup, static_error, store};
use crate::pipeline::{PipelineError, RunControl};
use crate::scene::{Scene, StaticModel};

/// Fill the static cache for many scenes (a sweep) with one FEM condensation per distinct
/// geometry: scenes that differ only in preload share the factorised strip, and each gets its
/// own cached report. Scenes with a given η or an existing cache entry are skipped. Returns the
/// number of condensations run and the groups that failed (their points fail on their own later).
pub fn fill_static_cache(scenes: &[Scene], cache_dir: &Path) -> (usize, Vec<(String, String)>) {
    let mut groups: Vec<(String, Vec<(StaticParams, String)>)> = Vec::new();
    // Whole-slider scenes calibrate and cache on their own (one strip FEM per geometry).
    for scene in scenes.iter().filter(|s| {
        s.contact.effective_ratio.is_none()
            && s.static_fem.model.choose(&s.motor).0 == StaticModel::Strip
    }) {
        let Ok(params) = static_params(scene, Some(&cache_dir.join("meshes"))) else {
            continue;
        };
        let (Ok(key), Ok(hash)) = (geometry_key(&params), params.content_hash()) else {
            continue;
        };
        let file = cache_dir.join(format!("static-{hash}.json"));
        match lookup(&file, &hash, None) {
            Lookup::Hit(_) => continue,
            Lookup::Damaged(why) => announce(&[format!(
                "static cache entry {} not used: {why}; recomputing it",
                file.display()
            )]),
            Lookup::Miss => {}
        }
        match groups.iter_mut().find(|(k, _)| *k == key) {
            Some((_, members)) if !members.iter().any(|(_, h)| *h == hash) => {
                members.push((params, hash))
            }
            Some(_) => {}
            None => groups.push((key, vec![(params, hash)])),
        }
    }
    let mut built = 0;
    let mut failures = Vec::new();
    for (key, members) in groups {
        if let Err(e) = condense_and_cache(&members, cache_dir) {
            failures.push((key, e.to_string()));
        } else {
            built += 1;
        }
    }
    (built, failures)
}

/// Build the strip model of the first member once and cache a report for every member.
fn condense_and_cache(
    members: &[(StaticParams, String)],
    cache_dir: &Path,
) -> Result<(), PipelineError> {
    let prepared = static_contact::prepare_strip(&members[0].0)?;
    announce(&prepared.notes);
    super::tips::cache_strip_tips(&prepared.model, &members[0].0, cache_dir)?;
    for (params, hash) in members {
        let report = prepared
            .analyse(params, &params.post_springs()?, &RunControl::none())
            .map_err(|e| static_error(e, params))?;
        store(
            &cache_dir.join(format!("static-{hash}.json")),
            &report,
            None,
        )?;
    }
    Ok(())
}
