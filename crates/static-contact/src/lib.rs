#![doc = include_str!("../README.md")]

pub mod analysis;
pub mod body;
pub mod body_solver;
mod body_spec;
mod error;
pub mod eta;
pub mod eta_full_contact;
pub mod halfspace;
pub mod lcp;
pub mod lumped;
pub mod mesh_source;
pub mod order_cache;
pub mod output;
pub mod params;
pub mod posts;
pub mod scene;

pub use analysis::{
    PostResult, PreloadResult, PreparedStrip, SnapshotResult, StaticAnalysis, StaticReport,
    prepare_strip,
};
pub use body::{BodyCompliance, BodySpec, Disk, FemStats, TangentialCompliance, TipLateral};
pub use body_solver::{BodySolver, FemSolver};
pub use error::{ContactError, Result};
pub use eta::{EtaFit, FitSample, fit_eta};
pub use eta_full_contact::full_contact_eta;
pub use lcp::{ActiveSetOptions, ActiveSetSolver, ContactProblem, ContactSolution, IterationLog};
pub use params::{MeshChoice, MeshSizes, StaticParams};
pub use run_control::RunControl;
pub use scene::{PostSite, StatorCompliance, StatorModel, StripConfig, StripModel, TipCompliance};
