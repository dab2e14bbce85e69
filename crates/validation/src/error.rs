//! The one error type of the crate.

use std::path::PathBuf;

use thiserror::Error;

/// Everything that can go wrong in a validation run. Each variant names the file, mesh group,
/// spring, option or command at fault.
#[derive(Debug, Error)]
pub enum ValidationError {
    /// A mesh file could not be read.
    #[error("validation: cannot read mesh {path}: {source}")]
    MeshRead {
        /// The mesh file.
        path: PathBuf,
        /// The reader's error (boxed: it is large).
        source: Box<gmsh_mesh::MeshError>,
    },
    /// A punch mesh lacks a physical group the problem needs.
    #[error("validation: mesh {mesh} has no physical group `{group}` ({why})")]
    MissingGroup {
        /// Mesh source name.
        mesh: String,
        /// Group name.
        group: &'static str,
        /// What the group is needed for.
        why: &'static str,
    },
    /// The mesh geometry does not look like the punch problem it is used for.
    #[error("validation: mesh {mesh}: {detail}")]
    BadPunchMesh {
        /// Mesh source name.
        mesh: String,
        /// What is wrong.
        detail: String,
    },
    /// The FEM failed (singular system, bad element, ...).
    #[error("validation: FEM failed for {context}: {source}")]
    Fem {
        /// Which problem (mesh, spring, material).
        context: String,
        /// elastic-fem's error.
        source: elastic_fem::FemError,
    },
    /// An analytic spring formula rejected its input.
    #[error("validation: formula for {spring} rejected its input: {source}")]
    Formula {
        /// Spring label.
        spring: &'static str,
        /// contact-springs' error.
        source: contact_springs::SpringError,
    },
    /// gmsh could not be run or failed.
    #[error("validation: mesh generation failed: `{command}`: {detail}")]
    MeshGeneration {
        /// The command line.
        command: String,
        /// gmsh's error lines or the OS error.
        detail: String,
    },
    /// A file could not be written or read.
    #[error("validation: I/O error on {path}: {source}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A chart could not be written.
    #[error("validation: cannot write chart {path}: {source}")]
    Chart {
        /// The chart path stem.
        path: PathBuf,
        /// charts' error.
        source: charts::ChartError,
    },
    /// JSON serialisation failed.
    #[error("validation: cannot serialise {what} to JSON: {source}")]
    Json {
        /// What was serialised.
        what: &'static str,
        /// serde_json's error.
        source: serde_json::Error,
    },
    /// An option is out of range.
    #[error("validation: option `{option}` = {value}: {reason}")]
    InvalidOption {
        /// Option name.
        option: &'static str,
        /// The value given.
        value: String,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// A convergence extrapolation could not be made.
    /// The stick/slip model refused a scene or failed (stick-slip study).
    #[error("validation: stick-slip model: {0}")]
    StickSlip(#[from] stick_slip::StickSlipError),
    #[error("validation: extrapolation of {quantity} failed: {reason}")]
    Extrapolation {
        /// Which quantity.
        quantity: String,
        /// Why.
        reason: String,
    },
}
