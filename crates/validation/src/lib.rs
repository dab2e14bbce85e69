//! Validation of the sawdrive physics against analytic references.
//!
//! **Springs** (issue 4): the FEM stiffness of a rigid flat punch of radius a on an elastic
//! half-space, for the four boundary conditions behind the Johnson springs k_pn, k_pt, k_sn,
//! k_st (docs/physics.md §3), converged in mesh size (Richardson, [`richardson`]) and truncation
//! radius (point-force far field, [`punch`]) with error estimates, against the formulas of
//! `contact-springs`; plus work-precision of Tet4 vs Tet10 and the failure modes
//! ([`stability`]). Entry point: [`validate_springs`]; text table via `Display`, `--json`
//! array via [`SpringsValidation::cases_json`], charts and files via [`report`].
//!
//! ```no_run
//! use validation::{SpringsOptions, validate_springs, report};
//! let validation = validate_springs(&SpringsOptions::default())?;   // ~30 min on 2 cores
//! println!("{validation}");
//! report::write_charts(&validation, "validation/springs".as_ref())?;
//! # Ok::<(), validation::ValidationError>(())
//! ```
//!
//! Run without the CLI: `cargo run --release -p validation --example validate_springs -- --help`.
//!
//! **Stick/slip dynamics** ([`stick_slip`]): work-precision and stability maps of the
//! integrators of the `stick-slip` crate, transient against period average, the paper's trends;
//! `sawdrive validate stick-slip` or
//! `cargo run --release -p validation --example validate_stick_slip`.
//!
//! **Static contact and η**: `cargo run --release -p validation --example static_contact_report`
//! regenerates `validation/static-contact/` (the numbers of its README).

pub mod error;
pub mod family;
pub mod mesh_cache;
pub mod point_load;
pub mod punch;
pub mod punch_mesh;
pub mod report;
pub mod richardson;
pub mod spring;
pub mod stability;
pub mod stick_slip;
pub mod study;

pub use error::ValidationError;
pub use family::{MeshFamily, benchmark_punch_mesh};
pub use mesh_cache::{MeshCache, PunchMeshParameters};
pub use punch::{AssembledPunch, PunchSolveOptions, PunchStiffness, StageTimings};
pub use punch_mesh::{MeshSymmetry, MirrorPlane, PunchMesh};
pub use spring::Spring;
pub use study::{SpringCase, SpringsOptions, SpringsValidation, validate_springs};
