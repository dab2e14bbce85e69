//! The crate's error type: every variant names the file, group, post, parameter or iteration at
//! fault.

use std::path::PathBuf;

/// Errors of the static contact analysis.
#[derive(Debug, thiserror::Error)]
pub enum ContactError {
    /// A physical parameter is out of its valid range.
    #[error("invalid parameter `{parameter}` = {value}: {reason}")]
    InvalidParameter {
        /// Parameter name (with its unit suffix).
        parameter: &'static str,
        /// The value given.
        value: f64,
        /// What is wrong.
        reason: String,
    },
    /// The mesh could not be read, or lacks a group the scene needs.
    #[error("{}", mesh_message(file, source))]
    Mesh {
        /// Mesh file.
        file: String,
        /// Reader error.
        #[source]
        source: Box<gmsh_mesh::MeshError>,
    },
    /// The mesh does not fit the scene (post count, radius, pitch, group contents).
    #[error("mesh {file}: {detail}")]
    MeshMismatch {
        /// Mesh file.
        file: String,
        /// What does not fit.
        detail: String,
    },
    /// The finite element model failed (inverted element, singular stiffness, ...).
    #[error("FEM of the {body} in {file}: {source}")]
    Fem {
        /// Which body ("slider" or "stator").
        body: &'static str,
        /// Mesh file.
        file: String,
        /// The elastic-fem error (names the element or DOF).
        #[source]
        source: Box<elastic_fem::FemError>,
    },
    /// The contact iteration did not converge.
    #[error(
        "contact active-set iteration did not converge after {iterations} iterations \
         (last active set {active} of {posts} posts, scaled complementarity residual {residual:.3e} \
         > tolerance {tolerance:.1e}){context}"
    )]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// Active-set size at the last iteration.
        active: usize,
        /// Number of posts.
        posts: usize,
        /// Last residual (scaled units, see [`crate::ContactSolution::complementarity_residual`]).
        residual: f64,
        /// Tolerance.
        tolerance: f64,
        /// Scene context (preload, phase), may be empty.
        context: String,
    },
    /// The dense compliance matrix is not positive definite (bad stator model or mesh).
    #[error(
        "compliance matrix is not positive definite at post {post} (pivot {pivot:.3e} m/N): {what}"
    )]
    CompliancePositivity {
        /// Post index (0-based, in x order).
        post: usize,
        /// The failing pivot.
        pivot: f64,
        /// Which matrix.
        what: String,
    },
    /// gmsh is needed to mesh a scene that no committed mesh covers, and it failed (or is
    /// missing); the source names the geometry, the output and gmsh's message.
    #[error("{source}")]
    Meshing {
        /// Geometry name.
        geometry: String,
        /// The runner's error ([`gmsh_mesh::gmsh::run_geo`]).
        #[source]
        source: Box<gmsh_mesh::MeshError>,
    },
    /// A mesh of the automatic mesh cache exists but cannot be read.
    #[error(
        "cached mesh {file} cannot be read ({source}); delete it or clear the mesh cache \
         {cache_dir} and run again (it is regenerated)"
    )]
    CachedMesh {
        /// The cached mesh file.
        file: PathBuf,
        /// The cache folder.
        cache_dir: PathBuf,
        /// The reader's error.
        #[source]
        source: Box<gmsh_mesh::MeshError>,
    },
    /// A cache file could not be written (the run's results are still valid).
    #[error("writing the cache file {path}: {detail}")]
    CacheWrite {
        /// The cache file.
        path: PathBuf,
        /// What failed.
        detail: String,
    },
    /// The caller asked the run to stop (its [`crate::RunControl`]) before `before`.
    #[error("cancelled before {before}")]
    Cancelled {
        /// The step that did not start, e.g. `the contact solve at preload 20 N, phase 3 of 8`.
        before: String,
    },
    /// Writing an output file failed.
    #[error("writing {path}: {detail}")]
    Output {
        /// Output path.
        path: PathBuf,
        /// What failed.
        detail: String,
    },
}

/// Result alias of the crate.
pub type Result<T> = std::result::Result<T, ContactError>;

/// "mesh FILE: error", without repeating the file where the reader's error already starts
/// with it.
fn mesh_message(file: &str, source: &gmsh_mesh::MeshError) -> String {
    let message = source.to_string();
    if message.starts_with(file) {
        format!("mesh {message}")
    } else {
        format!("mesh {file}: {message}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mesh_error_names_its_file_once() {
        let source = gmsh_mesh::MeshError::Io {
            path: "/x.msh".into(),
            action: "reading".into(),
            source: std::io::Error::from(std::io::ErrorKind::NotFound),
        };
        let error = ContactError::Mesh {
            file: "/x.msh".into(),
            source: Box::new(source),
        };
        assert_eq!(error.to_string().matches("/x.msh").count(), 1, "{error}");
    }
}
