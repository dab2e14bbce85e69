//! One elastic body (slider strip or stator block) condensed onto its contact disks.
//!
//! Each contact disk is rigid in z (all its nodes share one z displacement, a rigid-face tie),
//! free (frictionless) or fixed (bonded) in x and y. The body's stiffness K is assembled and
//! factored **once** (METIS ordering with the disk ties eliminated last, elastic-fem's sparse
//! Cholesky); the dense compliance C_ij = z-displacement of disk i per unit force on disk j is
//! the inverse of the factor's trailing block (the exact Schur-complement inverse onto the disk
//! unknowns, elastic-fem `sparse/trailing.rs`), no solve per disk. The same factor later
//! rebuilds the full displacement field for any set of post forces. `static.fem_solver` (or the
//! cost model) may replace the factor by PCG ([`crate::body_solver`]).

use std::path::Path;
use std::time::Instant;

use elastic_fem::sparse::SymmetricMatrix;
use elastic_fem::{
    Connectivity, Constraints, Dirichlet, DofMap, DofTarget, FemError, Model, ReducedSystem,
    RigidComponent, RigidFace, StiffnessPattern, assemble_stiffness,
};
use gmsh_mesh::Tets;
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::body_solver::{BodySolver, FemSolver, condense_body, plan_body};
pub use crate::body_spec::{BodySpec, Disk, TipLateral};
use crate::error::{ContactError, Result};

/// Relative tolerance (of the disk radius) for picking the nodes of a contact disk. Default 1e-3.
pub const DISK_NODE_TOLERANCE: f64 = 1e-3;
/// Right-hand sides solved together when building the compliance. Default 16.
pub const SOLVE_BATCH_COLUMNS: usize = 16;

/// Size and timings of one condensed body.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FemStats {
    /// Nodes of the body.
    pub nodes: usize,
    /// Tetrahedra of the body.
    pub tets: usize,
    /// Element order (1 Tet4, 2 Tet10).
    pub order: u8,
    /// Unknowns after constraints.
    pub reduced_unknowns: usize,
    /// Stored values of the Cholesky factor.
    pub factor_nnz: usize,
    /// Assembly time (s): from the body's sub-mesh to its reduced stiffness, wall time; the
    /// structure-only work (`analysis_s`) runs beside the numeric assembly and is inside it.
    pub assembly_s: f64,
    /// Floating-point operations of the numeric factorisation (multiply–adds).
    #[serde(default)]
    pub factor_flops: f64,
    /// Of `factor_s`: METIS ordering and symbolic analysis (s), run beside the numeric assembly
    /// (so also inside `assembly_s`).
    #[serde(default)]
    pub analysis_s: f64,
    /// Whether the fill-reducing ordering came from the mesh cache (no METIS run).
    #[serde(default)]
    pub ordering_cached: bool,
    /// Symbolic + numeric factorisation time (s); iterative: the preconditioner set-up.
    pub factor_s: f64,
    /// Time of the condensation onto the disks from the factor (s); iterative: the PCG columns.
    pub solve_s: f64,
    /// The solver that ran: `direct` or `iterative` ([`crate::body_solver`]).
    #[serde(default = "FemSolver::direct")]
    pub solver: FemSolver,
    /// PCG iterations of the condensation, all columns (0 for the direct solver).
    #[serde(default)]
    pub pcg_iterations: usize,
}

/// Tangential condensed compliance of a body's tips (see
/// [`BodyCompliance::tangential_compliance`]).
#[derive(Debug, Clone, PartialEq)]
pub struct TangentialCompliance {
    /// C_xx (m/N): x displacement of tip i per unit x force on tip j.
    pub tangential_m_per_n: DMatrix<f64>,
    /// C_zx (m/N): normal displacement of tip i (along the contact force's direction on this
    /// body) per unit x force on tip j.
    pub normal_from_tangential_m_per_n: DMatrix<f64>,
}

/// A body condensed onto its disks.
#[derive(Debug)]
pub struct BodyCompliance {
    /// Body name.
    pub name: &'static str,
    /// Dense disk compliance (m/N), disk order of the spec.
    pub compliance_m_per_n: DMatrix<f64>,
    /// Size and timings.
    pub stats: FemStats,
    /// Why the solver of `stats.solver` (the cost model's figures, or "requested").
    pub solver_reason: String,
    model: Model,
    reduced: ReducedSystem,
    factor: BodySolver,
    masters: Vec<usize>,
    mesh_node: Vec<usize>,
    disk_nodes: Vec<Vec<usize>>,
    disk_fraction: f64,
    force_sign: f64,
}

fn fem_error(spec: &BodySpec<'_>, source: FemError) -> ContactError {
    ContactError::Fem {
        body: spec.name,
        file: spec.mesh.source.clone(),
        source: Box::new(source),
    }
}

fn mesh_error(spec: &BodySpec<'_>, source: gmsh_mesh::MeshError) -> ContactError {
    ContactError::Mesh {
        file: spec.mesh.source.clone(),
        source: Box::new(source),
    }
}

/// A mesh-mismatch error naming the body's mesh file.
fn mismatch(spec: &BodySpec<'_>, detail: String) -> ContactError {
    ContactError::MeshMismatch {
        file: spec.mesh.source.clone(),
        detail,
    }
}

/// The sub-mesh of the body's volume, renumbered: its tetrahedra, each mesh node's local number
/// (`usize::MAX`: not in the body) and each local node's mesh node.
struct SubMesh {
    tets: Vec<usize>,
    local: Vec<usize>,
    mesh_node: Vec<usize>,
}

impl SubMesh {
    fn of(spec: &BodySpec<'_>) -> Result<Self> {
        let tets = spec
            .mesh
            .group_tets(&spec.volume_group)
            .map_err(|e| mesh_error(spec, e))?;
        if tets.is_empty() {
            return Err(mismatch(
                spec,
                format!("volume group `{}` has no tetrahedra", spec.volume_group),
            ));
        }
        let mut local = vec![usize::MAX; spec.mesh.nodes.len()];
        let mut mesh_node = Vec::new();
        for &t in &tets {
            for &n in spec.mesh.tets.nodes(t) {
                if local[n] == usize::MAX {
                    local[n] = mesh_node.len();
                    mesh_node.push(n);
                }
            }
        }
        Ok(Self {
            tets,
            local,
            mesh_node,
        })
    }

    /// The FEM model of the sub-mesh; a bad element is named by its gmsh tag.
    fn model(&self, spec: &BodySpec<'_>) -> Result<Model> {
        let nodes: Vec<[f64; 3]> = self.mesh_node.iter().map(|&n| spec.mesh.nodes[n]).collect();
        let local = &self.local;
        let tets = &self.tets;
        let connectivity = match &spec.mesh.tets {
            Tets::Linear(all) => {
                Connectivity::Tet4(tets.iter().map(|&t| all[t].map(|n| local[n])).collect())
            }
            Tets::Quadratic(all) => {
                Connectivity::Tet10(tets.iter().map(|&t| all[t].map(|n| local[n])).collect())
            }
        };
        Model::new(nodes, connectivity, spec.material).map_err(|e| {
            // Name the gmsh element tag of a bad element.
            let tag = |element: usize| spec.mesh.tet_tags[tets[element]];
            let e = match e {
                FemError::InvertedElement { element, .. }
                | FemError::DegenerateElement { element, .. } => {
                    return mismatch(
                        spec,
                        format!(
                            "{} element with gmsh tag {} is inverted or degenerate: {e}",
                            spec.name,
                            tag(element)
                        ),
                    );
                }
                other => other,
            };
            fem_error(spec, e)
        })
    }

    /// The local numbers of the nodes of `group`; a node outside the body is a mismatch.
    fn group_local_nodes(&self, spec: &BodySpec<'_>, group: &str) -> Result<Vec<usize>> {
        let nodes = spec
            .mesh
            .group_nodes(group)
            .map_err(|e| mesh_error(spec, e))?;
        nodes
            .iter()
            .map(|&n| {
                let l = self.local[n];
                if l == usize::MAX {
                    Err(mismatch(
                        spec,
                        format!(
                            "node tag {} of group `{group}` is not a node of the {} volume",
                            spec.mesh.node_tags[n], spec.name
                        ),
                    ))
                } else {
                    Ok(l)
                }
            })
            .collect()
    }
}

/// The contact nodes of each disk (within [`DISK_NODE_TOLERANCE`] of its circle); at least 3
/// per disk, no node in two disks.
fn disk_nodes(
    spec: &BodySpec<'_>,
    model: &Model,
    sub: &SubMesh,
    contact: &[usize],
) -> Result<Vec<Vec<usize>>> {
    let mut owner = vec![usize::MAX; model.node_count()];
    let mut disk_nodes = Vec::with_capacity(spec.disks.len());
    for (d, disk) in spec.disks.iter().enumerate() {
        let tol = DISK_NODE_TOLERANCE * disk.radius_m;
        let picked: Vec<usize> = contact
            .iter()
            .copied()
            .filter(|&n| {
                let x = model.nodes()[n];
                let r =
                    ((x[0] - disk.centre_m[0]).powi(2) + (x[1] - disk.centre_m[1]).powi(2)).sqrt();
                r <= disk.radius_m + tol && (x[2] - disk.centre_m[2]).abs() <= tol
            })
            .collect();
        if picked.len() < 3 {
            return Err(mismatch(
                spec,
                format!(
                    "contact disk {d} of the {} (centre {:?} m, radius {:.3e} m) has {} nodes in group `{}`: is the mesh made for this post layout?",
                    spec.name,
                    disk.centre_m,
                    disk.radius_m,
                    picked.len(),
                    spec.contact_group
                ),
            ));
        }
        for &n in &picked {
            if owner[n] != usize::MAX {
                return Err(mismatch(
                    spec,
                    format!(
                        "node {} lies in contact disks {} and {d}",
                        spec.mesh.node_tags[sub.mesh_node[n]], owner[n]
                    ),
                ));
            }
            owner[n] = d;
        }
        disk_nodes.push(picked);
    }
    Ok(disk_nodes)
}

/// The body's constraints: clamped and roller groups, one rigid face per disk (z loaded, x and
/// y free or bonded as `spec.lateral` says).
fn constraints(
    spec: &BodySpec<'_>,
    sub: &SubMesh,
    disk_nodes: &[Vec<usize>],
) -> Result<Constraints> {
    let mut constraints = Constraints::default();
    for g in &spec.clamped_groups {
        constraints
            .dirichlet
            .push(Dirichlet::clamped(sub.group_local_nodes(spec, g)?));
    }
    for (g, c) in &spec.roller_groups {
        constraints.dirichlet.push(Dirichlet::component(
            sub.group_local_nodes(spec, g)?,
            *c,
            0.0,
        ));
    }
    for nodes in disk_nodes {
        let lateral = match spec.lateral {
            TipLateral::Free => RigidComponent::Free,
            TipLateral::Bonded => RigidComponent::Prescribed {
                displacement_m: 0.0,
            },
        };
        constraints.rigid_faces.push(RigidFace {
            nodes: nodes.clone(),
            components: [lateral, lateral, RigidComponent::Loaded { force_n: 0.0 }],
        });
    }
    Ok(constraints)
}

/// The numeric assembly and, beside it, what needs only the structure: the reduced pattern, the
/// solver choice and the symbolic analysis (METIS when not cached). Returns the reduced system,
/// its stiffness and the solver plan.
#[allow(clippy::type_complexity)]
fn assemble_and_plan(
    spec: &BodySpec<'_>,
    model: &Model,
    pattern: &StiffnessPattern,
    dof_map: DofMap,
    masters: &[usize],
    order_cache: Option<&Path>,
    solver: FemSolver,
) -> Result<(
    ReducedSystem,
    SymmetricMatrix,
    crate::body_solver::SolverPlan,
)> {
    let (stiffness, planned) = rayon::join(
        || assemble_stiffness(model, pattern).map_err(|e| fem_error(spec, e)),
        || -> Result<_> {
            let reduced =
                ReducedSystem::from_pattern(pattern, dof_map).map_err(|e| fem_error(spec, e))?;
            let k_red = reduced.zero_matrix();
            let plan = plan_body(spec, model, &k_red, masters, order_cache, solver)?;
            Ok((reduced, k_red, plan))
        },
    );
    let (reduced, mut k_red, plan) = planned?;
    reduced
        .reduce_matrix_into(&stiffness?, &mut k_red)
        .map_err(|e| fem_error(spec, e))?;
    Ok((reduced, k_red, plan))
}

impl BodyCompliance {
    /// Assembles, constrains, factors and condenses the body.
    pub fn build(spec: &BodySpec<'_>) -> Result<Self> {
        Self::build_with_order_cache(spec, None)
    }

    /// [`Self::build`], reading the fill-reducing ordering of the body's stiffness from the
    /// folder `order_cache` (a mesh cache) or storing it there ([`crate::order_cache`]): a
    /// second run of the same mesh skips the METIS ordering.
    pub fn build_with_order_cache(spec: &BodySpec<'_>, order_cache: Option<&Path>) -> Result<Self> {
        Self::build_with_solver(spec, order_cache, FemSolver::Auto)
    }

    /// [`Self::build_with_order_cache`] with the solver `solver` (`static.fem_solver`;
    /// [`crate::body_solver`]: direct, iterative, or chosen by the cost model).
    pub fn build_with_solver(
        spec: &BodySpec<'_>,
        order_cache: Option<&Path>,
        solver: FemSolver,
    ) -> Result<Self> {
        let start = Instant::now();
        if !(spec.disk_fraction > 0.0 && spec.disk_fraction <= 1.0) {
            return Err(ContactError::InvalidParameter {
                parameter: "disk_fraction",
                value: spec.disk_fraction,
                reason: "must lie in (0, 1]".into(),
            });
        }
        let sub = SubMesh::of(spec)?;
        let model = sub.model(spec)?;
        let contact = sub.group_local_nodes(spec, &spec.contact_group)?;
        let disk_nodes = disk_nodes(spec, &model, &sub, &contact)?;
        let constraints = constraints(spec, &sub, &disk_nodes)?;
        let pattern = StiffnessPattern::build(&model);
        let dof_map =
            DofMap::new(model.node_count(), &constraints).map_err(|e| fem_error(spec, e))?;
        let masters: Vec<usize> = disk_nodes
            .iter()
            .enumerate()
            .map(|(d, nodes)| match dof_map.target(3 * nodes[0] + 2) {
                DofTarget::Reduced(j) => Ok(j),
                DofTarget::Prescribed(_) => Err(mismatch(
                    spec,
                    format!(
                        "contact disk {d} of the {} touches a clamped group: its z is prescribed",
                        spec.name
                    ),
                )),
            })
            .collect::<Result<_>>()?;
        let (reduced, k_red, plan) = assemble_and_plan(
            spec,
            &model,
            &pattern,
            dof_map,
            &masters,
            order_cache,
            solver,
        )?;
        let assembly_s = start.elapsed().as_secs_f64();
        let condensed = condense_body(spec, &model, &reduced, &k_red, &masters, plan)?;
        let stats = FemStats {
            nodes: model.node_count(),
            tets: model.element_count(),
            order: spec.mesh.tets.order(),
            reduced_unknowns: reduced.dim(),
            factor_nnz: condensed.factor_nnz,
            factor_flops: condensed.factor_flops,
            assembly_s,
            analysis_s: condensed.analysis_s,
            ordering_cached: condensed.ordering_cached,
            factor_s: condensed.factor_s,
            solve_s: condensed.solve_s,
            solver: condensed.solver.method(),
            pcg_iterations: condensed.pcg_iterations,
        };
        Ok(Self {
            name: spec.name,
            compliance_m_per_n: condensed.compliance,
            stats,
            solver_reason: condensed.reason,
            model,
            reduced,
            factor: condensed.solver,
            masters,
            mesh_node: sub.mesh_node,
            disk_nodes,
            disk_fraction: spec.disk_fraction,
            force_sign: spec.force_sign,
        })
    }

    /// Displacement field (m, DOF 3 n + c of the body's own node numbering) under post forces
    /// `force_n` (N, one per disk, ≥ 0 pressing the bodies together), relative to the body's
    /// clamped support.
    pub fn displacement(&self, force_n: &[f64]) -> Result<Vec<f64>> {
        let mut q = vec![0.0; self.reduced.dim()];
        for (j, f) in force_n.iter().enumerate() {
            q[self.masters[j]] += self.force_sign * self.disk_fraction * f;
        }
        let wrap = |source| ContactError::Fem {
            body: self.name,
            file: String::new(),
            source: Box::new(source),
        };
        self.factor.solve_in_place(&mut q).map_err(wrap)?;
        self.reduced.expand(&q).map_err(wrap)
    }

    /// Nodal-averaged stress (Pa, Voigt xx yy zz yz xz xy) of a displacement field of this body.
    pub fn nodal_stress(&self, u: &[f64]) -> Result<Vec<[f64; 6]>> {
        elastic_fem::post::nodal_averaged_stress(&self.model, u).map_err(|source| {
            ContactError::Fem {
                body: self.name,
                file: String::new(),
                source: Box::new(source),
            }
        })
    }

    /// Tangential (x) condensed compliance of the tips from the **same factor** (no second FEM):
    /// a unit x force on disk j spread equally over its nodes; column j holds the x displacement
    /// of every disk (the same equal-weight average over its nodes: a symmetric generalised
    /// compliance, C_xx = Wᵀ K⁻¹ W) and the z displacement of every disk's rigid tie (the
    /// slider-side normal–tangential cross term C_zx = E_zᵀ K⁻¹ W, normal tip displacement per
    /// unit tangential force). Equal nodal forces approximate a uniform shear traction; a rigid
    /// x tie would be slightly stiffer (the tip face of a post is nearly rigid in shear).
    ///
    /// Both blocks are blocks of one Gram matrix [W E_z]ᵀ K⁻¹ [W E_z] = Yᵀ Y with
    /// Y = L⁻¹ P [W E_z], computed by forward solves restricted to the elimination-tree paths of
    /// the disk unknowns (elastic-fem `sparse/sparse_rhs.rs`); no backward solve, no full
    /// solve. [`Self::tangential_compliance_by_solves`] gives the same matrices from full solves.
    ///
    /// Needs in-plane-free disks ([`TipLateral::Free`]: the x displacements are unknowns) and
    /// whole disks, or half disks cut by a mirror plane y = const (the half strip): an x load is
    /// symmetric about that plane, so the half body carries half of each post's x force, as it
    /// does of the normal force. A cut by a plane x = const has no such symmetry and is refused.
    ///
    /// With the direct factor: partial forward solves ([`Self::tangential_compliance_with_work`]);
    /// with the iterative solver (no factor): one PCG solve per disk
    /// ([`Self::tangential_compliance_by_solves`]).
    pub fn tangential_compliance(&self) -> Result<TangentialCompliance> {
        match self.factor.cholesky() {
            Some(_) => Ok(self.tangential_compliance_with_work()?.0),
            None => self.tangential_compliance_by_solves(),
        }
    }

    /// [`Self::tangential_compliance`] with the work of its partial forward solves.
    pub fn tangential_compliance_with_work(
        &self,
    ) -> Result<(TangentialCompliance, elastic_fem::sparse::InverseGramStats)> {
        let x_dofs = self.tangential_dofs()?;
        let n = x_dofs.len();
        let mut columns: Vec<elastic_fem::sparse::SparseColumn> = x_dofs
            .iter()
            .map(|dofs| {
                let weight = 1.0 / dofs.len() as f64;
                dofs.iter().map(|&j| (j, weight)).collect()
            })
            .collect();
        columns.extend(self.masters.iter().map(|&m| vec![(m, 1.0)]));
        let factor = self
            .factor
            .cholesky()
            .ok_or_else(|| ContactError::InvalidParameter {
                parameter: "fem_solver",
                value: f64::NAN,
                reason: format!(
                    "the partial forward solves of the {} need its Cholesky factor; it was \
                     condensed iteratively",
                    self.name
                ),
            })?;
        let (gram, work) = factor
            .inverse_gram(&columns)
            .map_err(|source| self.solve_error(source))?;
        // A post's force f puts disk_fraction · f on the disk of this body.
        let tangential = gram.view((0, 0), (n, n)) * self.disk_fraction;
        let cross = gram.view((n, 0), (n, n)) * (self.force_sign * self.disk_fraction);
        Ok((
            TangentialCompliance {
                tangential_m_per_n: tangential,
                normal_from_tangential_m_per_n: cross,
            },
            work,
        ))
    }

    /// [`Self::tangential_compliance`] from full solves with the factor (SOLVE_BATCH_COLUMNS
    /// right-hand sides at a time): the reference of the partial forward solves, ≈ 2 nnz(L)
    /// multiply–adds per disk.
    pub fn tangential_compliance_by_solves(&self) -> Result<TangentialCompliance> {
        let x_dofs = self.tangential_dofs()?;
        let dim = self.reduced.dim();
        let n = x_dofs.len();
        let mut tangential = DMatrix::zeros(n, n);
        let mut cross = DMatrix::zeros(n, n);
        for first in (0..n).step_by(SOLVE_BATCH_COLUMNS) {
            let cols = SOLVE_BATCH_COLUMNS.min(n - first);
            let mut rhs = vec![0.0; dim * cols];
            for c in 0..cols {
                let dofs = &x_dofs[first + c];
                for &j in dofs {
                    rhs[c * dim + j] += 1.0 / dofs.len() as f64;
                }
            }
            self.factor
                .solve_columns_in_place(&mut rhs, cols)
                .map_err(|source| self.solve_error(source))?;
            for c in 0..cols {
                let column = &rhs[c * dim..(c + 1) * dim];
                for i in 0..n {
                    let dofs = &x_dofs[i];
                    tangential[(i, first + c)] =
                        dofs.iter().map(|&j| column[j]).sum::<f64>() / dofs.len() as f64;
                    cross[(i, first + c)] = self.force_sign * column[self.masters[i]];
                }
            }
        }
        // A post's force f puts disk_fraction · f on the disk of this body.
        Ok(TangentialCompliance {
            tangential_m_per_n: (&tangential + tangential.transpose()) * (0.5 * self.disk_fraction),
            normal_from_tangential_m_per_n: cross * self.disk_fraction,
        })
    }

    fn solve_error(&self, source: FemError) -> ContactError {
        ContactError::Fem {
            body: self.name,
            file: String::new(),
            source: Box::new(source),
        }
    }

    /// Reduced x unknowns of each disk, after checking that the tangential compliance applies
    /// (whole or y-cut half disks, x free).
    fn tangential_dofs(&self) -> Result<Vec<Vec<usize>>> {
        if !(self.disk_fraction == 1.0 || (self.disk_fraction == 0.5 && self.disks_cut_along_x())) {
            return Err(ContactError::InvalidParameter {
                parameter: "disk_fraction",
                value: self.disk_fraction,
                reason: "the tangential compliance needs whole contact disks (1) or halves cut \
                         by a plane y = const (0.5)"
                    .into(),
            });
        }
        let map = self.reduced.dof_map();
        let mut x_dofs: Vec<Vec<usize>> = Vec::with_capacity(self.disk_nodes.len());
        for (d, nodes) in self.disk_nodes.iter().enumerate() {
            let mut dofs = Vec::with_capacity(nodes.len());
            for &n in nodes {
                match map.target(3 * n) {
                    DofTarget::Reduced(j) => dofs.push(j),
                    DofTarget::Prescribed(_) => {
                        return Err(ContactError::InvalidParameter {
                            parameter: "lateral",
                            value: d as f64,
                            reason: format!(
                                "contact disk {d} of the {} has a prescribed x displacement: the tangential compliance needs TipLateral::Free",
                                self.name
                            ),
                        });
                    }
                }
            }
            x_dofs.push(dofs);
        }
        Ok(x_dofs)
    }

    /// Whether every disk's nodes span (nearly) its whole diameter in x: a disk cut, if at all,
    /// by a plane y = const.
    fn disks_cut_along_x(&self) -> bool {
        self.disk_nodes.iter().all(|nodes| {
            let x = nodes.iter().map(|&n| self.model.nodes()[n][0]);
            let (lo, hi) = x.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
            let y = nodes.iter().map(|&n| self.model.nodes()[n][1]);
            let (ylo, yhi) = y.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
            hi - lo > 1.5 * (yhi - ylo)
        })
    }

    /// Mesh node index of each body node.
    pub fn mesh_nodes(&self) -> &[usize] {
        &self.mesh_node
    }

    /// Body node indices of each contact disk.
    pub fn disk_nodes(&self) -> &[Vec<usize>] {
        &self.disk_nodes
    }

    /// +1 (slider) or −1 (stator).
    pub fn force_sign(&self) -> f64 {
        self.force_sign
    }
}
