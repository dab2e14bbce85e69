//! 3D small-strain linear elasticity on Tet4 / Tet10 meshes (gmsh node order).
//!
//! Pipeline (each step a public building block; [`solve_static`] chains them):
//! [`Model`] (nodes, tets, materials) → [`StiffnessPattern::build`] (symbolic, once per mesh)
//! → [`assemble_stiffness`] (numeric, parallel) → [`DofMap`] from [`Constraints`] →
//! [`ReducedSystem`] (u = T q + u_p) → [`sparse::SymbolicCholesky::analyze`] (METIS/AMD, once
//! per pattern) → [`sparse::SymbolicCholesky::factor`] (per set of values) → solve → expand →
//! reactions and stresses ([`post`]).
//!
//! Units: SI throughout (m, N, Pa, J). DOF numbering: `3 × node + component`.
//!
//! ```
//! use elastic_fem::{mesh_gen::{BoxFace, BoxMesh}, Constraints, Dirichlet, Material, Model,
//!     SolverOptions, StaticProblem, loads, solve_static};
//! // A 1 × 1 × 1 m block clamped at z = 0, 1 MPa traction along x on its top.
//! let mesh = BoxMesh::tet10([1.0; 3], [2, 2, 2]);
//! let model = Model::new(mesh.nodes.clone(), mesh.connectivity.clone(), Material::isotropic(200e9, 0.3).unwrap()).unwrap();
//! let mut f = vec![0.0; model.dof_count()];
//! loads::add_surface_traction(model.nodes(), &mesh.face_triangles(BoxFace::ZMax), [1e6, 0.0, 0.0], &mut f).unwrap();
//! let constraints = Constraints { dirichlet: vec![Dirichlet::clamped(mesh.face_nodes(BoxFace::ZMin))], ..Default::default() };
//! let solution = solve_static(&StaticProblem { model: &model, constraints: &constraints, load_n: &f }, &SolverOptions::default()).unwrap();
//! let total_reaction_x: f64 = solution.reaction_n.iter().step_by(3).sum();
//! assert!((total_reaction_x + 1e6).abs() < 1e-3, "reaction balances the 1 MN load");
//! ```

#![warn(missing_docs)]
// Index loops mirror the tensor formulas (C_ijkl, K_ab,ij); iterator chains would obscure them.
#![allow(clippy::needless_range_loop)]

pub mod amg;
pub mod assembly;
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
