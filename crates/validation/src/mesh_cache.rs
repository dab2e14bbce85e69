//! Punch meshes generated on demand with gmsh from `meshes/punch.geo` (embedded in the binary,
//! [`gmsh_mesh::geo_scripts`]) and kept in the mesh folder of the one cache
//! ([`gmsh_mesh::cache::meshes_dir`]: `<cache>/meshes`, the cache being `--cache DIR`,
//! `$SAWDRIVE_CACHE`, `$XDG_CACHE_HOME/sawdrive` or `$HOME/.cache/sawdrive`), never in `meshes/`.
//!
//! gmsh runs through the workspace's one runner, [`gmsh_mesh::gmsh::run_geo`] (MSH 4.1 binary,
//! one thread, so that a parameter set always gives the same mesh; written under a temporary
//! name and renamed only when gmsh succeeded, so an interrupted run never leaves a partial mesh).

use std::path::PathBuf;

use gmsh_mesh::gmsh::{GmshOptions, run_geo};

use serde::{Deserialize, Serialize};

use crate::error::ValidationError;
use crate::punch_mesh::MeshSymmetry;

/// Environment variable naming the mesh cache folder ([`gmsh_mesh::cache::MESH_CACHE_ENV`]).
pub const MESH_CACHE_ENV: &str = gmsh_mesh::cache::MESH_CACHE_ENV;
/// Environment variable naming the gmsh binary (as in `scripts/mesh.sh`).
pub const GMSH_ENV: &str = gmsh_mesh::gmsh::GMSH_ENV;

/// Default cache folder: [`gmsh_mesh::cache::meshes_dir`].
pub fn default_cache_dir() -> PathBuf {
    gmsh_mesh::cache::meshes_dir()
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
    /// The `punch.geo` geometry; `None` (default): the embedded script, written into the cache
    /// folder when meshing ([`gmsh_mesh::geo_scripts::path`]).
    pub geometry: Option<PathBuf>,
    /// gmsh binary.
    pub gmsh: String,
}

impl Default for MeshCache {
    fn default() -> Self {
        Self {
            dir: default_cache_dir(),
            geometry: None,
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
        let geometry = match &self.geometry {
            Some(g) => g.clone(),
            None => gmsh_mesh::geo_scripts::path("punch").map_err(|e| {
                ValidationError::MeshGeneration {
                    command: "writing the embedded punch.geo into the cache".into(),
                    detail: e.to_string(),
                }
            })?,
        };
        let options = GmshOptions {
            program: PathBuf::from(&self.gmsh),
            ..GmshOptions::default()
        };
        run_geo(&geometry, &path, &setnumbers, &options).map_err(|e| {
            ValidationError::MeshGeneration {
                command: format!(
                    "{} {} {}",
                    self.gmsh,
                    geometry.display(),
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
