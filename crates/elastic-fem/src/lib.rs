#![doc = include_str!("../README.md")]
#![warn(missing_docs)]
// Index loops mirror the tensor formulas (C_ijkl, K_ab,ij); iterator chains would obscure them.
#![allow(clippy::needless_range_loop)]

pub mod amg;
pub mod assembly;
pub mod chebyshev;
pub mod condense;
pub mod constraints;
pub mod element;
pub mod error;
pub mod iterative;
pub mod loads;
pub mod locality;
pub mod material;
pub mod matrix_free;
pub mod mesh_gen;
pub mod model;
pub mod pattern;
pub mod post;
pub mod quadrature;
pub mod reduction;
pub mod rigid_modes;
pub mod shape;
pub mod sparse;
pub mod static_solver;

pub use assembly::{assemble_stiffness, assemble_stiffness_into};
pub use constraints::{Constraints, Dirichlet, PeriodicPairs, RigidComponent, RigidFace};
pub use error::{FemError, FemResult};
pub use iterative::{
    CoarseSolver, IterativeOptions, IterativeSolver, MultigridReport, MultigridSetupTimes,
};
pub use loads::SurfaceTriangles;
pub use material::{CubicCrystal, LameParameters, Material};
pub use model::{Connectivity, Model, QualityReport};
pub use pattern::StiffnessPattern;
pub use reduction::{DofMap, DofTarget, ReducedSystem};
pub use rigid_modes::{FreeRigidMode, check_rigid_body_modes, free_rigid_body_modes};
pub use static_solver::{
    CostEstimate, CostQuery, RigidFaceResult, SolveReport, SolverChoice, SolverMethod,
    SolverOptions, StaticProblem, StaticSolution, choose_method, choose_method_with, solve_static,
};
