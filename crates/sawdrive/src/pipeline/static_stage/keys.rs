//! The static stage's keys: its parameters for a scene ([`static_params`]), the hash of the
//! strip geometry a condensation depends on ([`geometry_key`]) and the SHA-256 of cached bytes.
//! Shared by the strip, the whole slider (whose near field is calibrated on the strip) and the
//! tip compliances; imports no other file of the stage.

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};
use static_contact::{MeshChoice, StaticParams};

use crate::pipeline::PipelineError;
use crate::scene::{Scene, StaticModel};

/// Relative tolerance on equal x and y pitch (the strip model needs a square post lattice).
const PITCH_MISMATCH_TOLERANCE: f64 = 1e-9;

/// The static stage's parameters for `scene`: the motor's ([`StaticParams::for_motor`]) with the
/// scene's static settings.
pub fn static_params(
    scene: &Scene,
    mesh_cache_dir: Option<&Path>,
) -> Result<StaticParams, PipelineError> {
    let posts = &scene.motor.posts;
    if !posts.is_square_lattice(PITCH_MISMATCH_TOLERANCE) {
        return Err(PipelineError::Unsupported {
            stage: "static",
            message: format!(
                "the strip model needs equal pitch in x and y, got {} m and {} m (posts.array / count): \
                 give effective_ratio as a number to skip the static stage",
                posts.pitch_x_m(),
                posts.pitch_y_m()
            ),
        });
    }
    let settings = &scene.static_fem;
    let mesh = match settings.mesh.as_str() {
        "auto" => MeshChoice::Auto,
        path => MeshChoice::File(PathBuf::from(path)),
    };
    Ok(StaticParams {
        phases: settings.phases as usize,
        element_order: settings.element_order as u8,
        strip_rows: settings.strip_rows as usize,
        stator: settings.stator,
        mesh,
        contact_tolerance: settings.tolerance_for(StaticModel::Strip),
        max_iterations: settings.max_iterations as usize,
        fem_solver: settings.fem_solver,
        mesh_cache_dir: mesh_cache_dir.map(Path::to_owned),
        ..StaticParams::for_motor(&scene.motor)
    })
}

/// SHA-256 of `bytes`, in hex.
pub(crate) fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Hash of what the condensed strip model depends on: the static inputs without the preloads
/// and snapshot phases (which only enter the cheap contact solves).
pub fn geometry_key(params: &StaticParams) -> Result<String, PipelineError> {
    let mut geometry = params.clone();
    geometry.preload_n = 1.0;
    geometry.preload_sweep_n.clear();
    geometry.phases = 1;
    Ok(geometry.content_hash()?)
}
