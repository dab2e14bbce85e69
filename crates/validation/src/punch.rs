//! FEM stiffness of a rigid flat punch on a truncated half-space, for each spring's boundary
//! condition.
//!
//! **Symmetry.** The four problems are linear and the domain (a hemisphere with a centred disk)
//! is invariant under the reflections y → −y and x → −x, so the solution inherits the symmetry
//! of the load:
//! - normal load (−z): even under both reflections, so u_y = 0 on y = 0 and u_x = 0 on x = 0
//!   (shear tractions vanish there: natural conditions). Quarter model, force × 4.
//! - tangential load (+x): even under y → −y, so u_y = 0 on y = 0 (half model, force × 2);
//!   odd under x → −x (the mirrored problem is the negated load), so on x = 0: u_y = u_z = 0
//!   with u_x free. A quarter model is therefore also exact for the tangential springs; the
//!   prescribed punch values agree with both (u_y = 0 always, u_z = 0 or free on x = 0).
//!
//! Each reflection maps every punch condition of docs/physics.md §3 onto itself (or its negative), so
//! these conditions are exact, not approximations.
//!
//! **Truncation.** The half-space is cut at r = R. Clamping the hemisphere (u = 0) overestimates
//! the stiffness by ≈ 0.6 a/R (docs/physics.md §8). Instead the far field is prescribed as the point
//! force field of the punch's own resultant P (Boussinesq for normal, Cerruti for tangential,
//! [`crate::point_load`]): u = P g(x) on r = R. Since P is unknown, two solves with one
//! factorisation are superposed:
//! - A: punch displaced by δ, far field clamped → punch force P_A (also the *clamped* result);
//! - B: punch held at 0, far field u = F_ref g(x) → punch force P_B;
//!
//! u = u_A + β u_B with the consistency P = P_A + β P_B = β F_ref, so
//! P = P_A / (1 − P_B / F_ref) and k = P / δ. The neglected far-field terms (force dipoles such
//! as the tilting moment of the bonded tangential punch, higher multipoles) decay one power of
//! a/r faster, so the truncation error becomes O((a/R)²) (measured in the truncation study).
//!
//! **Force.** The force on the punch is the sum of the consistent nodal reactions K u at the
//! punch nodes, times the symmetry multiplicity, evaluated variationally: with w = u_A / δ
//! (which equals the punch direction on the punch and vanishes on every other constrained DOF),
//! P = wᵀ K u for the exact u. For an approximate (iterative) solution u = u* + e with e = 0 on
//! the constrained DOFs, wᵀ K u carries the error e_Aᵀ K e only (K u* vanishes on the free DOFs),
//! i.e. second order in the energy-norm error, while the plain reaction sum would be first order
//! in it and sensitive to the boundary layer. For the direct solve both agree to round-off.
//!
//! **Solver.** [`PunchSolveOptions::method`] selects the direct Cholesky, the p-multigrid PCG of
//! elastic-fem, or the automatic choice by elastic-fem's cost model for the two right-hand sides
//! (A and B share one factorisation or one multigrid set-up).

use std::time::Instant;

use contact_springs::Material as SpringMaterial;
use elastic_fem::sparse::{CsrMatrix, FactorOptions, Ordering, SymbolicCholesky, SymmetricMatrix};
use elastic_fem::{
    Constraints, Dirichlet, DofMap, FemError, IterativeOptions, IterativeSolver, LameParameters,
    Material, Model, MultigridSetupTimes, ReducedSystem, SolverChoice, SolverMethod,
    StiffnessPattern, assemble_stiffness, choose_method, static_solver::locate_factor_error,
};
use serde::{Deserialize, Serialize};

use crate::error::ValidationError;
use crate::punch_mesh::{MeshSymmetry, PunchMesh};
use crate::spring::{PunchComponent, Spring};

/// Punch displacement δ relative to the punch radius. The problem is linear, so the value only
/// sets the scale of the numbers; small so that the displacements stay "small strain".
/// Dimensionless; default 1e-3.
pub const PUNCH_DISPLACEMENT_OVER_RADIUS: f64 = 1e-3;

/// Wall time of each stage of one solve (s).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct StageTimings {
    /// Sparsity pattern of K (symbolic assembly), shared by all springs on one mesh.
    pub pattern_s: f64,
    /// Numeric assembly of K, shared by all springs on one mesh and material.
    pub assembly_s: f64,
    /// Constraint map, rigid-mode check and reduction K_red = Tᵀ K T.
    pub reduction_s: f64,
    /// Ordering (METIS) and symbolic Cholesky (direct); method choice, transfer operators and
    /// fine CSR matrix (iterative).
    pub symbolic_s: f64,
    /// Numeric Cholesky (direct); coarse operator, coarse Cholesky and smoother (iterative).
    pub numeric_s: f64,
    /// Both triangular solves, expansion and reactions.
    pub solve_s: f64,
    /// Iterative path (0 on the direct one), part of `numeric_s`: full-row CSR copy of K_red.
    #[serde(default)]
    pub multigrid_fine_csr_s: f64,
    /// Iterative path, part of `numeric_s`: transfer operators P, Pᵀ.
    #[serde(default)]
    pub multigrid_transfer_s: f64,
    /// Iterative path, part of `numeric_s`: Galerkin coarse operator Pᵀ K_red P.
    #[serde(default)]
    pub multigrid_coarse_operator_s: f64,
    /// Iterative path, part of `numeric_s`: coarse Cholesky or coarse SA-AMG set-up.
    #[serde(default)]
    pub multigrid_coarse_solver_s: f64,
    /// Iterative path, part of `numeric_s`: fine smoother (diagonal, λ_max power iterations).
    #[serde(default)]
    pub multigrid_smoother_s: f64,
}

impl StageTimings {
    /// Wall time of one complete solve of one spring on a fresh mesh: every stage counted once.
    pub fn total_s(&self) -> f64 {
        self.pattern_s
            + self.assembly_s
            + self.reduction_s
            + self.symbolic_s
            + self.numeric_s
            + self.solve_s
    }
}

/// The FEM stiffness of one spring on one mesh.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PunchStiffness {
    /// Which spring (boundary condition).
    pub spring: Spring,
    /// Material name.
    pub material: String,
    /// Punch radius a (m).
    pub radius_m: f64,
    /// Truncation radius R (m).
    pub truncation_radius_m: f64,
    /// Model symmetry used.
    pub symmetry: MeshSymmetry,
    /// Element order (1 Tet4, 2 Tet10).
    pub order: u8,
    /// Stiffness with the point-force far field (N/m).
    pub stiffness_n_per_m: f64,
    /// Stiffness with the clamped far field (N/m).
    pub clamped_stiffness_n_per_m: f64,
    /// Mesh nodes.
    pub nodes: usize,
    /// Mesh elements.
    pub elements: usize,
    /// Unknowns after constraints.
    pub unknowns: usize,
    /// Stored entries of the Cholesky factor (of the coarse Tet4 operator for the iterative
    /// method).
    pub factor_nnz: usize,
    /// Stage wall times.
    pub timings: StageTimings,
    /// Linear solver used (`direct` or `iterative`).
    #[serde(default)]
    pub method: String,
    /// Why that solver (elastic-fem's cost model or "requested").
    #[serde(default)]
    pub method_reason: String,
    /// PCG iterations of the two right-hand sides (0 for the direct method, and for B when
    /// only A is solved).
    #[serde(default)]
    pub iterations: [usize; 2],
}

/// Elastic-fem material of a contact-springs material (isotropic, G and ν).
pub fn fem_material(material: &SpringMaterial) -> Result<Material, ValidationError> {
    LameParameters::from_shear_poisson(material.shear_modulus_pa, material.poisson_ratio)
        .map(Material::Isotropic)
        .map_err(|source| ValidationError::Fem {
            context: format!("material {}", material.name),
            source,
        })
}

/// Options of the punch solves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PunchSolveOptions {
    /// Fill-reducing ordering (default METIS).
    pub ordering: Ordering,
    /// Threads for the factorisation (0 = all).
    pub threads: usize,
    /// Direct, iterative or automatic (default automatic, elastic-fem's cost model).
    pub method: SolverMethod,
    /// Stopping rule of the iterative method (default: elastic-fem's default).
    pub iterative: IterativeOptions,
    /// Solve problem A only (the clamped far field), as the peer codes of
    /// `scripts/compare-peers.sh` do: one right-hand side, `stiffness_n_per_m` is NaN and
    /// `clamped_stiffness_n_per_m` the result. Default false (both far fields).
    pub clamped_only: bool,
}

impl Default for PunchSolveOptions {
    fn default() -> Self {
        Self {
            ordering: Ordering::Metis,
            threads: 0,
            method: SolverMethod::Auto,
            iterative: IterativeOptions::default(),
            clamped_only: false,
        }
    }
}

/// K_red as the chosen path needs it.
enum ReducedMatrix {
    /// Upper triangle (direct path, cost model).
    Upper(SymmetricMatrix),
    /// Both triangles by rows (requested iterative path).
    FullRows(CsrMatrix),
}

/// Solutions of the reduced systems A and B (A only if clamped_only) with what the solve reports.
struct TwoSolves {
    rhs: Vec<f64>,
    factor_nnz: usize,
    iterations: [usize; 2],
    symbolic_s: f64,
    numeric_s: f64,
    solve_s: f64,
    multigrid: MultigridSetupTimes,
}

/// The reduced systems of one spring ([`AssembledPunch::reduce`]).
struct Reduction {
    reduced: ReducedSystem,
    k_red: ReducedMatrix,
    /// Right-hand sides A then B, column-major.
    rhs: Vec<f64>,
    /// Dirichlet map of B (the point force's far field), absent if clamped only.
    map_b: Option<DofMap>,
    columns: usize,
    delta_m: f64,
    reference_force_n: f64,
    reduction_s: f64,
}

/// What the punch forces need of the far fields.
struct FarFields<'a> {
    map_b: Option<&'a DofMap>,
    delta_m: f64,
    reference_force_n: f64,
}

/// Solves the columns of `rhs` in place with the iterative solver; `started` is when the choice
/// of method began (its time less the setup's, `numeric_s`, and the solve's counts as symbolic).
fn solve_iterative(
    solver: &IterativeSolver,
    mut rhs: Vec<f64>,
    columns: usize,
    (started, numeric_s): (Instant, f64),
) -> Result<TwoSolves, FemError> {
    let solve = Instant::now();
    let reports = solver.solve_columns_in_place(&mut rhs, columns, &mut solver.workspace())?;
    let solve_s = solve.elapsed().as_secs_f64();
    Ok(TwoSolves {
        rhs,
        factor_nnz: solver.report().coarse_factor_nnz,
        iterations: [
            reports[0].iterations,
            reports.get(1).map_or(0, |r| r.iterations),
        ],
        symbolic_s: started.elapsed().as_secs_f64() - solve_s - numeric_s,
        numeric_s,
        solve_s,
        multigrid: solver.report().setup,
    })
}

/// Solves the columns of `rhs` in place by sparse Cholesky (the analysis the cost model made,
/// if any); `started` is when the choice of method began.
fn solve_direct(
    k_red: &SymmetricMatrix,
    reduced: &ReducedSystem,
    analysed: Option<SymbolicCholesky>,
    mut rhs: Vec<f64>,
    columns: usize,
    options: &PunchSolveOptions,
    started: Instant,
) -> Result<TwoSolves, FemError> {
    let symbolic = match analysed {
        Some(s) => s,
        None => SymbolicCholesky::analyze(k_red, options.ordering)?,
    };
    let symbolic_s = started.elapsed().as_secs_f64();
    let t = Instant::now();
    let factor_options = FactorOptions {
        threads: options.threads,
        ..FactorOptions::default()
    };
    let numeric = symbolic
        .factor_with(k_red, factor_options)
        .map_err(|e| locate_factor_error(e, reduced.dof_map()))?;
    let numeric_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    numeric.solve_columns_in_place(&mut rhs, columns)?;
    Ok(TwoSolves {
        rhs,
        factor_nnz: symbolic.factor_nnz(),
        iterations: [0, 0],
        symbolic_s,
        numeric_s,
        solve_s: t.elapsed().as_secs_f64(),
        multigrid: MultigridSetupTimes::default(),
    })
}

/// The assembled stiffness of one punch mesh for one material, reused by all springs.
#[derive(Debug)]
pub struct AssembledPunch<'m> {
    mesh: &'m PunchMesh,
    model: Model,
    stiffness: SymmetricMatrix,
    material: SpringMaterial,
    pattern_s: f64,
    assembly_s: f64,
}

impl<'m> AssembledPunch<'m> {
    /// Builds the model, the pattern and K for `material`.
    pub fn new(mesh: &'m PunchMesh, material: &SpringMaterial) -> Result<Self, ValidationError> {
        let context = || format!("mesh {} ({})", mesh.source, material.name);
        let model = Model::new(
            mesh.nodes.clone(),
            mesh.connectivity.clone(),
            fem_material(material)?,
        )
        .map_err(|source| ValidationError::Fem {
            context: context(),
            source,
        })?;
        let t = Instant::now();
        let pattern = StiffnessPattern::build(&model);
        let pattern_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let stiffness =
            assemble_stiffness(&model, &pattern).map_err(|source| ValidationError::Fem {
                context: context(),
                source,
            })?;
        let assembly_s = t.elapsed().as_secs_f64();
        Ok(Self {
            mesh,
            model,
            stiffness,
            material: material.clone(),
            pattern_s,
            assembly_s,
        })
    }

    /// The elastic-fem model (nodes, elements, material).
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The assembled stiffness K (N/m).
    pub fn stiffness(&self) -> &SymmetricMatrix {
        &self.stiffness
    }

    /// The constraints of problem A (punch displaced by `punch_m`, far field clamped) of `spring`.
    pub fn clamped_constraints(&self, spring: Spring, punch_m: f64) -> Constraints {
        self.constraints(spring, punch_m, &|_| [0.0; 3])
    }

    /// The Dirichlet conditions of `spring` with the punch at `punch_m` (m) and the far field
    /// given per far-field node.
    fn constraints(
        &self,
        spring: Spring,
        punch_m: f64,
        far_field_m: &dyn Fn([f64; 3]) -> [f64; 3],
    ) -> Constraints {
        let mesh = self.mesh;
        let mut values: Vec<Option<[Option<f64>; 3]>> = vec![None; mesh.node_count()];
        let mut set = |n: usize, c: usize, v: f64| {
            values[n].get_or_insert([None; 3])[c] = Some(v);
        };
        for &n in &mesh.far_field_nodes {
            let u = far_field_m(mesh.nodes[n]);
            for (c, v) in u.into_iter().enumerate() {
                set(n, c, v);
            }
        }
        // Symmetry planes (module docs): y = 0 always u_y = 0; x = 0 u_x = 0 (normal) or
        // u_y = u_z = 0 (tangential, antisymmetric).
        for &n in &mesh.sym_y0_nodes {
            set(n, 1, 0.0);
        }
        for &n in &mesh.sym_x0_nodes {
            if spring.is_normal() {
                set(n, 0, 0.0);
            } else {
                set(n, 1, 0.0);
                set(n, 2, 0.0);
            }
        }
        for &n in &mesh.punch_nodes {
            for (c, condition) in spring.punch_components().into_iter().enumerate() {
                if let PunchComponent::Prescribed(factor) = condition {
                    set(n, c, factor * punch_m);
                }
            }
        }
        let dirichlet = values
            .into_iter()
            .enumerate()
            .filter_map(|(n, v)| {
                v.map(|displacement_m| Dirichlet {
                    nodes: vec![n],
                    displacement_m,
                })
            })
            .collect();
        Constraints {
            dirichlet,
            ..Default::default()
        }
    }

    /// The FEM error of `spring` on this mesh, naming both.
    fn fem_error(&self, spring: Spring, source: FemError) -> ValidationError {
        ValidationError::Fem {
            context: format!(
                "{} on mesh {} ({})",
                spring.label(),
                self.mesh.source,
                self.material.name
            ),
            source,
        }
    }

    /// Solves `spring` and returns its stiffness with both far-field conditions (the clamped
    /// one only with [`PunchSolveOptions::clamped_only`]).
    pub fn solve(
        &self,
        spring: Spring,
        options: &PunchSolveOptions,
    ) -> Result<PunchStiffness, ValidationError> {
        let fem = |source: FemError| self.fem_error(spring, source);
        let Reduction {
            reduced,
            k_red,
            rhs,
            map_b,
            columns,
            delta_m,
            reference_force_n,
            reduction_s,
        } = self.reduce(spring, options)?;
        let t = Instant::now();
        let (choice, analysed) = self.choose(&k_red, columns, options).map_err(fem)?;
        let factor_options = FactorOptions {
            threads: options.threads,
            ..FactorOptions::default()
        };
        let solved = match choice.method {
            SolverMethod::Iterative => {
                let setup = Instant::now();
                let solver = self
                    .iterative_solver(&reduced, k_red, options, factor_options)
                    .map_err(fem)?;
                let numeric_s = setup.elapsed().as_secs_f64();
                solve_iterative(&solver, rhs, columns, (t, numeric_s)).map_err(fem)?
            }
            _ => {
                let ReducedMatrix::Upper(k_red) = k_red else {
                    unreachable!("the full-row copy is made for the iterative path only")
                };
                solve_direct(&k_red, &reduced, analysed, rhs, columns, options, t).map_err(fem)?
            }
        };
        let far_fields = FarFields {
            map_b: map_b.as_ref(),
            delta_m,
            reference_force_n,
        };
        let (forces, post_solve_s) = self
            .punch_forces(&reduced, &solved.rhs, &far_fields)
            .map_err(fem)?;
        let (stiffness_n_per_m, clamped_stiffness_n_per_m) = forces;
        let both = !options.clamped_only;
        if (both && !stiffness_n_per_m.is_finite()) || !clamped_stiffness_n_per_m.is_finite() {
            return Err(fem(FemError::NonFiniteSolution { unknown: 0 }));
        }
        let timings = self.timings(reduction_s, &solved, post_solve_s);
        let mesh = self.mesh;
        Ok(PunchStiffness {
            spring,
            material: self.material.name.clone(),
            radius_m: mesh.radius_m,
            truncation_radius_m: mesh.truncation_radius_m,
            symmetry: mesh.symmetry,
            order: mesh.order,
            stiffness_n_per_m,
            clamped_stiffness_n_per_m,
            nodes: mesh.node_count(),
            elements: mesh.element_count(),
            unknowns: reduced.dim(),
            factor_nnz: solved.factor_nnz,
            timings,
            method: choice.method.name().to_string(),
            method_reason: choice.reason,
            iterations: solved.iterations,
        })
    }

    /// The stage timings of one solve: assembly (shared by the springs), reduction, the solve's
    /// stages, the punch forces' time counted with the solve.
    fn timings(&self, reduction_s: f64, solved: &TwoSolves, post_solve_s: f64) -> StageTimings {
        StageTimings {
            pattern_s: self.pattern_s,
            assembly_s: self.assembly_s,
            reduction_s,
            symbolic_s: solved.symbolic_s,
            numeric_s: solved.numeric_s,
            solve_s: solved.solve_s + post_solve_s,
            multigrid_fine_csr_s: solved.multigrid.fine_csr_s,
            multigrid_transfer_s: solved.multigrid.transfer_s,
            multigrid_coarse_operator_s: solved.multigrid.coarse_operator_s,
            multigrid_coarse_solver_s: solved.multigrid.coarse_solver_s,
            multigrid_smoother_s: solved.multigrid.smoother_s,
        }
    }

    /// The solver path: `auto`'s choice (with the symbolic analysis its cost model made) on the
    /// upper-triangle copy, the iterative path when only the full-row copy was made.
    fn choose(
        &self,
        k_red: &ReducedMatrix,
        columns: usize,
        options: &PunchSolveOptions,
    ) -> Result<(SolverChoice, Option<SymbolicCholesky>), FemError> {
        match k_red {
            ReducedMatrix::Upper(k_red) => choose_method(
                options.method,
                k_red,
                columns,
                self.model.connectivity(),
                options.ordering,
            ),
            ReducedMatrix::FullRows(_) => {
                Ok((SolverChoice::requested(SolverMethod::Iterative), None))
            }
        }
    }

    /// The reduced systems of `spring`: A (clamped far field, punch displaced by δ) and, unless
    /// clamped only, B (the point force's far field, punch fixed) as right-hand sides of one
    /// matrix.
    fn reduce(
        &self,
        spring: Spring,
        options: &PunchSolveOptions,
    ) -> Result<Reduction, ValidationError> {
        let fem = |source: FemError| self.fem_error(spring, source);
        let mesh = self.mesh;
        let delta_m = PUNCH_DISPLACEMENT_OVER_RADIUS * mesh.radius_m;
        let (g, nu) = (self.material.shear_modulus_pa, self.material.poisson_ratio);
        // Reference force F_ref = G a δ... scaled so that u_B is O(δ a / R) on the far field.
        let reference_force_n = g * mesh.radius_m * delta_m;
        let point_force = spring.point_force();
        let t = Instant::now();
        let constraints_a = self.constraints(spring, delta_m, &|_| [0.0; 3]);
        let far_b = |x: [f64; 3]| {
            point_force
                .displacement_m_per_n(x, g, nu)
                .map(|u| u.map(|v| v * reference_force_n))
                .unwrap_or([0.0; 3])
        };
        let n = mesh.node_count();
        let map_a = DofMap::new(n, &constraints_a).map_err(fem)?;
        let columns = if options.clamped_only { 1 } else { 2 };
        // No rigid-mode check here: the clamped far field (and the punch) remove every rigid
        // motion by construction, and elastic-fem's body detection (`check_rigid_body_modes`)
        // splits connected meshes into spurious bodies on some gmsh meshes (union-find bug,
        // reported). A singular system would still be caught by the factorisation's pivot check.
        let reduced = ReducedSystem::new(&self.stiffness, map_a).map_err(fem)?;
        // The requested iterative path needs K_red only as its solver's full-row CSR, built
        // without the upper-triangle copy; the direct path and the cost model need that copy.
        let k_red = if options.method == SolverMethod::Iterative {
            ReducedMatrix::FullRows(reduced.reduce_matrix_csr(&self.stiffness).map_err(fem)?)
        } else {
            ReducedMatrix::Upper(reduced.reduce_matrix(&self.stiffness).map_err(fem)?)
        };
        let load_a = reduced
            .reduce_load(&self.stiffness, &vec![0.0; 3 * n])
            .map_err(fem)?;
        let mut rhs = Vec::with_capacity(columns * reduced.dim());
        rhs.extend_from_slice(&load_a);
        let map_b = if options.clamped_only {
            None
        } else {
            // f_red(B) = −Tᵀ K u_p(B); T is the same for A and B (same constrained DOFs).
            let map_b = DofMap::new(n, &self.constraints(spring, 0.0, &far_b)).map_err(fem)?;
            let mut k_up = vec![0.0; 3 * n];
            self.stiffness
                .mul_vec(&map_b.prescribed_vector(), &mut k_up);
            let restricted = reduced.dof_map().restrict(&k_up).map_err(fem)?;
            rhs.extend(restricted.into_iter().map(|v| -v));
            Some(map_b)
        };
        Ok(Reduction {
            reduced,
            k_red,
            rhs,
            map_b,
            columns,
            delta_m,
            reference_force_n,
            reduction_s: t.elapsed().as_secs_f64(),
        })
    }

    /// The multigrid-preconditioned CG solver of the reduced matrix, from whichever copy of it
    /// was made.
    fn iterative_solver(
        &self,
        reduced: &ReducedSystem,
        k_red: ReducedMatrix,
        options: &PunchSolveOptions,
        factor_options: FactorOptions,
    ) -> Result<IterativeSolver, FemError> {
        let (model, dof_map) = (&self.model, reduced.dof_map());
        match k_red {
            ReducedMatrix::Upper(k_red) => {
                IterativeSolver::new(model, dof_map, &k_red, &options.iterative, factor_options)
            }
            ReducedMatrix::FullRows(a) => {
                IterativeSolver::from_csr(model, dof_map, a, &options.iterative, factor_options)
            }
        }
    }

    /// Punch stiffness with the point force's far field and with the clamped one (N/m), and the
    /// time taken (s). Variational punch forces (module docs): P = wᵀ K u with w = u_A / δ.
    fn punch_forces(
        &self,
        reduced: &ReducedSystem,
        rhs: &[f64],
        far: &FarFields,
    ) -> Result<((f64, f64), f64), FemError> {
        let t = Instant::now();
        let (n, m) = (self.mesh.node_count(), reduced.dim());
        let u_a = reduced.dof_map().expand(&rhs[..m])?;
        let u_b = match far.map_b {
            Some(map_b) => Some(map_b.expand(&rhs[m..])?),
            None => None,
        };
        let mut k_ua = vec![0.0; 3 * n];
        self.stiffness.mul_vec(&u_a, &mut k_ua);
        let dot = |u: &[f64]| u.iter().zip(&k_ua).map(|(a, b)| a * b).sum::<f64>();
        let multiplicity = self.mesh.symmetry.multiplicity();
        let force_a = dot(&u_a) / far.delta_m * multiplicity;
        let force_b = u_b.map(|u_b| dot(&u_b) / far.delta_m * multiplicity);
        // Direction of the punch displacement along the force direction: +1 for all four springs.
        let stiffness_n_per_m = force_b.map_or(f64::NAN, |f_b| {
            force_a / (1.0 - f_b / far.reference_force_n) / far.delta_m
        });
        let clamped_stiffness_n_per_m = force_a / far.delta_m;
        Ok((
            (stiffness_n_per_m, clamped_stiffness_n_per_m),
            t.elapsed().as_secs_f64(),
        ))
    }
}
