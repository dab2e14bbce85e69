//! Punch meshes generated on demand with gmsh from `meshes/punch.geo` and kept in a cache folder
//! (never in `meshes/`): `$SAWDRIVE_MESH_CACHE`, or `target/sawdrive-meshes/` in the workspace.
//!
//! gmsh runs through the workspace's one runner, [`gmsh_mesh::gmsh::run_geo`] (MSH 4.1 binary,
//! one thread, so that a parameter set always gives the same mesh; written under a temporary
//! name and renamed only when gmsh succeeded, so an interrupted run never leaves a partial mesh).

use std::path::{Path, PathBuf};

use gmsh_mesh::gmsh::{GmshOptions, run_geo};

use serde::{Deserialize, Serialize};

use crate::error::ValidationError;
use crate::punch_mesh::MeshSymmetry;

/// Environment variable naming the mesh cache folder.
pub const MESH_CACHE_ENV: &str = "SAWDRIVE_MESH_CACHE";
/// Environment variable naming the gmsh binary (as in `scripts/mesh.sh`).
pub const GMSH_ENV: &str = gmsh_mesh::gmsh::GMSH_ENV;

/// The workspace root (two levels above this crate).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Default cache folder: `$SAWDRIVE_MESH_CACHE` or `<workspace>/target/sawdrive-meshes`.
pub fn default_cache_dir() -> PathBuf {
    std::env::var_os(MESH_CACHE_ENV)
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace_root().join("target/sawdrive-meshes"))
}

/// Default geometry: `<workspace>/meshes/punch.geo`.
pub fn default_punch_geometry() -> PathBuf {
    workspace_root().join("meshes/punch.geo")
}

/// Parameters of one `punch.geo` mesh (see meshes/README.md), lengths in units of a except `a`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PunchMeshParameters {
    /// Punch radius a (m).
    pub radius_m: f64,
    /// R / a.
    pub truncation_ratio: f64,
    /// Element size at the punch edge / a.
    pub h_edge_over_a: f64,
    /// Size growth per unit distance from the edge.
    pub growth: f64,
    /// Size cap / a (0: R/4).
    pub h_max_over_a: f64,
    /// Model part.
    pub symmetry: MeshSymmetry,
    /// 1 Tet4, 2 Tet10.
    pub order: u8,
}

impl PunchMeshParameters {
    /// File name encoding every parameter.
    pub fn file_name(&self) -> String {
        format!(
            "punch-{}_a{}um_R{}a_he{}_g{}_hmax{}_tet{}.msh",
            self.symmetry.name(),
            (self.radius_m * 1e9).round() / 1e3,
            self.truncation_ratio,
            self.h_edge_over_a,
            self.growth,
            self.h_max_over_a,
            if self.order == 2 { 10 } else { 4 }
        )
    }

    fn setnumbers(&self) -> Vec<(&'static str, f64)> {
        let sym = match self.symmetry {
            MeshSymmetry::Full => 0.0,
            MeshSymmetry::Half => 1.0,
            MeshSymmetry::Quarter => 2.0,
        };
        vec![
            ("a", self.radius_m),
            ("R_over_a", self.truncation_ratio),
            ("h_edge_over_a", self.h_edge_over_a),
            ("growth", self.growth),
            ("h_max_over_a", self.h_max_over_a),
            ("sym", sym),
            ("order", f64::from(self.order)),
        ]
    }
}

/// Where and how meshes are generated.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshCache {
    /// Cache folder (created if missing).
    pub dir: PathBuf,
    /// The `punch.geo` geometry.
    pub geometry: PathBuf,
    /// gmsh binary.
    pub gmsh: String,
}

impl Default for MeshCache {
    fn default() -> Self {
        Self {
            dir: default_cache_dir(),
            geometry: default_punch_geometry(),
            gmsh: std::env::var(GMSH_ENV).unwrap_or_else(|_| "gmsh".into()),
        }
    }
}

impl MeshCache {
    /// The path of the mesh for `parameters`, generating it with gmsh (the workspace's one
    /// runner, [`gmsh_mesh::gmsh::run_geo`]) if it is not cached.
    pub fn punch_mesh(&self, parameters: &PunchMeshParameters) -> Result<PathBuf, ValidationError> {
        let path = self.dir.join(parameters.file_name());
        if path.is_file() {
            return Ok(path);
        }
        let setnumbers = parameters.setnumbers();
        let options = GmshOptions {
            program: PathBuf::from(&self.gmsh),
            ..GmshOptions::default()
        };
        run_geo(&self.geometry, &path, &setnumbers, &options).map_err(|e| {
            ValidationError::MeshGeneration {
                command: format!(
                    "{} {} {}",
                    self.gmsh,
                    self.geometry.display(),
                    setnumbers
                        .iter()
                        .map(|(n, v)| format!("-setnumber {n} {v:e}"))
                        .collect::<Vec<_>>()
                        .join(" ")
                ),
                detail: e.to_string(),
            }
        })?;
        Ok(path)
    }
}
