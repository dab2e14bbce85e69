//! Punch meshes generated on demand with gmsh from `meshes/punch.geo` and kept in a cache folder
//! (never in `meshes/`): `$SAWDRIVE_MESH_CACHE`, or `target/sawdrive-meshes/` in the workspace.
//!
//! The gmsh command is the one of `scripts/mesh.sh` (MSH 4.1 binary, one thread, so that a
//! parameter set always gives the same mesh); files are written under a temporary name and
//! renamed only when gmsh succeeded, so an interrupted run never leaves a partial mesh.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde::{Deserialize, Serialize};

use crate::error::ValidationError;
use crate::punch_mesh::MeshSymmetry;

/// Environment variable naming the mesh cache folder.
pub const MESH_CACHE_ENV: &str = "SAWDRIVE_MESH_CACHE";
/// Environment variable naming the gmsh binary (as in `scripts/mesh.sh`).
pub const GMSH_ENV: &str = "GMSH";

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

    fn setnumbers(&self) -> Vec<(&'static str, String)> {
        let sym = match self.symmetry {
            MeshSymmetry::Full => 0,
            MeshSymmetry::Half => 1,
            MeshSymmetry::Quarter => 2,
        };
        vec![
            ("a", format!("{:e}", self.radius_m)),
            ("R_over_a", self.truncation_ratio.to_string()),
            ("h_edge_over_a", self.h_edge_over_a.to_string()),
            ("growth", self.growth.to_string()),
            ("h_max_over_a", self.h_max_over_a.to_string()),
            ("sym", sym.to_string()),
            ("order", self.order.to_string()),
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
    /// The path of the mesh for `parameters`, generating it with gmsh if it is not cached.
    pub fn punch_mesh(&self, parameters: &PunchMeshParameters) -> Result<PathBuf, ValidationError> {
        let path = self.dir.join(parameters.file_name());
        if path.is_file() {
            return Ok(path);
        }
        std::fs::create_dir_all(&self.dir).map_err(|source| ValidationError::Io {
            path: self.dir.clone(),
            source,
        })?;
        let tmp = self.dir.join(format!(
            ".{}.{}.tmp.msh",
            parameters.file_name(),
            std::process::id()
        ));
        let mut command = Command::new(&self.gmsh);
        command
            .arg(&self.geometry)
            .args(["-3", "-format", "msh41", "-bin", "-nt", "1"]);
        for (name, value) in parameters.setnumbers() {
            command.args(["-setnumber", name, &value]);
        }
        command.arg("-o").arg(&tmp);
        let shown = format!("{command:?}");
        let output = command
            .output()
            .map_err(|e| ValidationError::MeshGeneration {
                command: shown.clone(),
                detail: format!(
                    "cannot run gmsh ({e}); install it (apt-get install gmsh) or set {GMSH_ENV}"
                ),
            })?;
        let log = String::from_utf8_lossy(&output.stdout).to_string()
            + &String::from_utf8_lossy(&output.stderr);
        let errors: Vec<&str> = log.lines().filter(|l| l.starts_with("Error")).collect();
        if !output.status.success() || !errors.is_empty() || !tmp.is_file() {
            let _ = std::fs::remove_file(&tmp);
            let detail = if errors.is_empty() {
                log.lines().rev().take(10).collect::<Vec<_>>().join(" | ")
            } else {
                errors.join(" | ")
            };
            return Err(ValidationError::MeshGeneration {
                command: shown,
                detail,
            });
        }
        std::fs::rename(&tmp, &path).map_err(|source| ValidationError::Io {
            path: path.clone(),
            source,
        })?;
        Ok(path)
    }
}
