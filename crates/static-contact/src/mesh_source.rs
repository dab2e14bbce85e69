//! Choosing the `slider-strip` mesh of a run: a committed mesh of `meshes/` when its parameters
//! match, otherwise `scripts/mesh.sh` (gmsh) into a cache directory, named by a hash of the
//! geometry parameters so that a second run reuses it.

use std::path::{Path, PathBuf};
use std::process::Command;

use sha2::{Digest, Sha256};

use crate::error::{ContactError, Result};
use crate::params::{MeshChoice, StaticParams};
use crate::scene::StatorModel;

/// Relative tolerance when comparing mesh parameters with a committed mesh's. Default 1e-9.
pub const PARAMETER_MATCH_TOLERANCE: f64 = 1e-9;

/// Committed `slider-strip` meshes and the parameters they were made with (meshes/README.md).
const COMMITTED: &[(&str, &[(&str, f64)])] = &[(
    "slider-strip_p40um_d20um_n10_tet4_10k.msh",
    &[
        ("pitch", 40e-6),
        ("d", 20e-6),
        ("h", 2e-6),
        ("t", 0.5e-3),
        ("n_posts", 10.0),
        ("rows", 1.0),
        ("margin", 0.0),
        ("stator_depth", 1e-3),
        ("h_post", 2.5e-6),
        ("h_body", 100e-6),
        ("growth", 0.3),
        ("order", 1.0),
        ("periodic_x", 0.0),
    ],
)];

/// The workspace root: `$SAWDRIVE_ROOT`, else the one this crate was built in.
pub fn workspace_root() -> PathBuf {
    std::env::var_os("SAWDRIVE_ROOT").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."),
        PathBuf::from,
    )
}

/// The gmsh `-setnumber` parameters of the strip mesh the run needs.
pub fn strip_mesh_parameters(params: &StaticParams) -> Vec<(&'static str, f64)> {
    let stator_depth = match params.stator {
        StatorModel::HalfSpace => 0.0,
        StatorModel::MeshedBlock => params.stator_depth_m,
    };
    vec![
        ("pitch", params.post_pitch_m),
        ("d", params.post_diameter_m),
        ("h", params.post_height_m),
        ("t", params.slider_thickness_m),
        ("n_posts", params.strip_posts_along_x() as f64),
        ("rows", params.strip_rows as f64),
        ("margin", params.strip_margin_m()),
        ("stator_depth", stator_depth),
        ("h_post", params.mesh_h_post_m()),
        ("h_body", params.mesh_sizes.h_body_m),
        ("growth", params.mesh_sizes.growth),
        ("order", params.element_order as f64),
        ("periodic_x", 0.0),
    ]
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= PARAMETER_MATCH_TOLERANCE * a.abs().max(b.abs())
}

/// A committed mesh usable for these parameters. A mesh with a stator block also serves the
/// half-space stator model (its stator volume is then ignored).
pub fn committed_mesh(params: &StaticParams) -> Option<PathBuf> {
    let wanted = strip_mesh_parameters(params);
    COMMITTED.iter().find_map(|(file, made)| {
        let fits = wanted.iter().all(|(name, value)| {
            let Some((_, m)) = made.iter().find(|(n, _)| n == name) else {
                return false;
            };
            (*name == "stator_depth" && params.stator == StatorModel::HalfSpace) || same(*value, *m)
        });
        let path = workspace_root().join("meshes").join(file);
        (fits && path.is_file()).then_some(path)
    })
}

/// The bytes of `meshes/GEOMETRY.geo` (empty if it cannot be read; meshing then fails with its
/// own error). Cached meshes and results are keyed by them, so editing the geometry script
/// invalidates both.
pub fn geometry_source(geometry: &str) -> Vec<u8> {
    std::fs::read(
        workspace_root()
            .join("meshes")
            .join(format!("{geometry}.geo")),
    )
    .unwrap_or_default()
}

/// The cache directory for automatic meshes.
pub fn cache_dir(params: &StaticParams) -> PathBuf {
    params
        .mesh_cache_dir
        .clone()
        .or_else(|| std::env::var_os("SAWDRIVE_MESH_CACHE").map(PathBuf::from))
        .unwrap_or_else(|| std::env::temp_dir().join("sawdrive-meshes"))
}

/// The mesh file of the run: the given file, a committed mesh, or a cached/generated one.
pub fn resolve_mesh(params: &StaticParams) -> Result<PathBuf> {
    if let MeshChoice::File(path) = &params.mesh {
        return Ok(path.clone());
    }
    if let Some(path) = committed_mesh(params) {
        return Ok(path);
    }
    let setnumbers = strip_mesh_parameters(params);
    let mut hasher = Sha256::new();
    hasher.update(geometry_source("slider-strip"));
    for (name, value) in &setnumbers {
        hasher.update(format!("{name}={value:e}\n"));
    }
    let digest: String = hasher
        .finalize()
        .iter()
        .take(8)
        .map(|b| format!("{b:02x}"))
        .collect();
    let dir = cache_dir(params);
    let out = dir.join(format!(
        "slider-strip_n{}x{}_o{}_{digest}.msh",
        params.strip_posts_along_x(),
        params.strip_rows,
        params.element_order
    ));
    if out.is_file() {
        return Ok(out);
    }
    generate_mesh("slider-strip", &out, &setnumbers)?;
    Ok(out)
}

/// Runs `scripts/mesh.sh --binary GEOMETRY OUT NAME=VALUE...` (gmsh), creating OUT's directory.
/// Errors carry gmsh's message, or how to install gmsh if it is missing.
pub fn generate_mesh(geometry: &str, out: &Path, setnumbers: &[(&str, f64)]) -> Result<()> {
    let meshing_error = |detail: String| ContactError::Meshing {
        geometry: geometry.into(),
        out: out.to_path_buf(),
        detail,
    };
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir)
            .map_err(|e| meshing_error(format!("cannot create the directory: {e}")))?;
    }
    let script = workspace_root().join("scripts/mesh.sh");
    if !script.is_file() {
        return Err(meshing_error(format!(
            "{} not found (set SAWDRIVE_ROOT to the sawdrive checkout)",
            script.display()
        )));
    }
    let mut command = Command::new("bash");
    command.arg(&script).arg("--binary").arg(geometry).arg(out);
    for (name, value) in setnumbers {
        command.arg(format!("{name}={value:e}"));
    }
    let output = command
        .output()
        .map_err(|e| meshing_error(format!("cannot run {}: {e}", script.display())))?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let hint = if output.status.code() == Some(127) {
            " (gmsh is missing: install it with `apt-get install gmsh` or scripts/install-deps.sh)"
        } else {
            ""
        };
        return Err(meshing_error(format!(
            "scripts/mesh.sh failed{hint}: {}",
            stderr.trim()
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ten_post_strip_resolves_to_the_committed_mesh() {
        let params = StaticParams {
            strip_posts: Some(10),
            element_order: 1,
            mesh_sizes: crate::params::MeshSizes {
                h_post_over_radius: 0.25,
                ..Default::default()
            },
            ..StaticParams::default()
        };
        let path = committed_mesh(&params).expect("committed 10-post strip mesh matches");
        assert!(
            path.ends_with("slider-strip_p40um_d20um_n10_tet4_10k.msh"),
            "picked {}",
            path.display()
        );
        let tet10 = StaticParams {
            element_order: 2,
            ..params
        };
        assert!(
            committed_mesh(&tet10).is_none(),
            "a Tet10 request must not reuse the Tet4 mesh"
        );
    }
}
