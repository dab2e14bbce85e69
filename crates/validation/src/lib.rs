#![doc = include_str!("../README.md")]

pub mod cases;
pub mod error;
pub mod family;
pub mod mesh_cache;
pub mod point_load;
pub mod punch;
pub mod punch_mesh;
pub mod report;
pub mod richardson;
pub mod serde_nan;
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
