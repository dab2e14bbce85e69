//! Static frictionless unilateral contact of the textured slider on the SAW stator, and the
//! effective contact ratio η (docs/physics.md §6).
//!
//! Pipeline: a `slider-strip` mesh (one post pitch wide, symmetry planes in y, the whole post row
//! along x; for one row only its half up to the mirror plane through the post axes, half tip
//! disks carrying half of each post's force) → [`StripModel`]: the slider strip's FEM stiffness factored once and condensed onto the
//! rigid post tips, plus the stator's compliance (elastic half-space or meshed block) → a dense
//! post compliance C → per snapshot of the frozen wave w(x) = A_n sin(θ₀ − kx), the contact
//! problem (f ≥ 0, g ≥ 0, f·g = 0, Σf = P) solved by a logged active-set method
//! ([`ActiveSetSolver`]) → post forces → η fitted against the lumped model ([`fit_eta`]).
//!
//! ```
//! use nalgebra::DMatrix;
//! use static_contact::{ActiveSetSolver, ContactProblem};
//! // Three independent posts (k = 1e6 N/m) on heights 0, 10, 20 nm under 15 mN.
//! let problem = ContactProblem {
//!     compliance_m_per_n: DMatrix::identity(3, 3) * 1e-6,
//!     obstacle_height_m: vec![0.0, 10e-9, 20e-9],
//!     preload_n: 0.015,
//!     length_scale_m: Some(20e-9),
//! };
//! let solution = ActiveSetSolver::default().solve(&problem).unwrap();
//! assert!((solution.force_n[2] - 0.0125).abs() < 1e-12 && (solution.force_n[1] - 0.0025).abs() < 1e-12);
//! assert!(solution.complementarity_residual < 1e-9);
//! ```

pub mod analysis;
pub mod body;
pub mod body_solver;
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
    PostResult, PreloadResult, PreparedStrip, ShouldStop, SnapshotResult, StaticAnalysis,
    StaticReport, prepare_strip, run, run_with, run_with_springs, run_with_springs_cancellable,
};
pub use body::{BodyCompliance, BodySpec, Disk, FemStats, TangentialCompliance, TipLateral};
pub use body_solver::{BodySolver, FemSolver};
pub use error::{ContactError, Result};
pub use eta::{EtaFit, FitSample, fit_eta};
pub use eta_full_contact::full_contact_eta;
pub use lcp::{ActiveSetOptions, ActiveSetSolver, ContactProblem, ContactSolution, IterationLog};
pub use params::{MeshChoice, MeshSizes, StaticParams};
pub use scene::{PostSite, StatorCompliance, StatorModel, StripConfig, StripModel, TipCompliance};
