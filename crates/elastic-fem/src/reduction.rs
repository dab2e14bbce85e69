//! Constraint elimination by reduction: u = T q + u_p.
//!
//! Every full DOF is either *prescribed* (value in u_p) or mapped to exactly one reduced
//! unknown q_j with coefficient 1 (ties from rigid faces and periodic pairs merge DOFs into one
//! unknown). Then K_red = Tᵀ K T and f_red = Tᵀ (f − K u_p) + F_rigid. Because T has full column
//! rank, K_red stays symmetric and is positive definite whenever the constraints remove all
//! rigid-body modes. With a 0/1 selection matrix T, K_red is a pure scatter-add of K's entries,
//! done through a precomputed map (pattern built once, numeric reduction per matrix).

use rayon::prelude::*;

use crate::constraints::{Constraints, RigidComponent};
use crate::error::{FemError, FemResult};
use crate::pattern::StiffnessPattern;
use crate::sparse::matrix::fingerprint;
use crate::sparse::{CsrLayout, CsrMatrix, SymmetricMatrix};

/// Relative tolerance under which two prescribed values for the same (tied) DOF are treated
/// as equal. Dimensionless; default 1e-12.
pub const PRESCRIBED_CONFLICT_TOLERANCE: f64 = 1e-12;

/// What a full DOF becomes after reduction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DofTarget {
    /// Equal to reduced unknown `q[j]`.
    Reduced(usize),
    /// Prescribed displacement (m).
    Prescribed(f64),
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// Describes full DOF `dof` as "node N component c".
pub fn describe_dof(dof: usize) -> String {
    format!("node {} component {}", dof / 3, AXES[dof % 3])
}

struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        Self {
            parent: (0..n).collect(),
        }
    }
    fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            self.parent[x] = self.parent[self.parent[x]];
            x = self.parent[x];
        }
        x
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            // Keep the smaller index as root: deterministic numbering.
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.parent[hi] = lo;
        }
    }
}

fn check_node(context: impl Fn() -> String, node: usize, node_count: usize) -> FemResult<()> {
    if node >= node_count {
        return Err(FemError::ConstraintNodeOutOfRange {
            context: context(),
            node,
            node_count,
        });
    }
    Ok(())
}

fn same_value(a: f64, b: f64) -> bool {
    (a - b).abs() <= PRESCRIBED_CONFLICT_TOLERANCE * a.abs().max(b.abs())
}

/// Ties the components of every periodic pair (slave, master) into one class.
fn link_periodic(
    uf: &mut UnionFind,
    constraints: &Constraints,
    node_count: usize,
) -> FemResult<()> {
    for (p, periodic) in constraints.periodic.iter().enumerate() {
        for &[s, m] in &periodic.pairs {
            check_node(|| format!("periodic[{p}]"), s, node_count)?;
            check_node(|| format!("periodic[{p}]"), m, node_count)?;
            for c in (0..3).filter(|&c| periodic.components[c]) {
                uf.union(3 * s + c, 3 * m + c);
            }
        }
    }
    Ok(())
}

/// The prescribed value of each full DOF, if any.
struct Prescribed(Vec<Option<f64>>);

impl Prescribed {
    /// Prescribe `value` at `dof`: finite, and equal to any value given before.
    fn set(&mut self, dof: usize, value: f64, what: &'static str) -> FemResult<()> {
        if !value.is_finite() {
            return Err(FemError::NonFiniteInput {
                what,
                node: dof / 3,
                component: dof % 3,
            });
        }
        match self.0[dof] {
            Some(old) if !same_value(old, value) => Err(FemError::ConflictingPrescribedValues {
                node: dof / 3,
                component: dof % 3,
                first_m: old,
                second_m: value,
            }),
            _ => {
                self.0[dof] = Some(value);
                Ok(())
            }
        }
    }

    /// The Dirichlet values of `constraints`.
    fn dirichlet(&mut self, constraints: &Constraints, node_count: usize) -> FemResult<()> {
        for (d, dirichlet) in constraints.dirichlet.iter().enumerate() {
            for &node in &dirichlet.nodes {
                check_node(|| format!("dirichlet[{d}]"), node, node_count)?;
                for c in 0..3 {
                    if let Some(v) = dirichlet.displacement_m[c] {
                        self.set(3 * node + c, v, "Dirichlet value")?;
                    }
                }
            }
        }
        Ok(())
    }
}

/// Ties each rigid face's loaded or prescribed components into one class (on its first node);
/// returns the loads, by the first node's DOF.
fn link_rigid_faces(
    uf: &mut UnionFind,
    prescribed: &mut Prescribed,
    constraints: &Constraints,
    node_count: usize,
) -> FemResult<Vec<(usize, f64)>> {
    let mut class_force: Vec<(usize, f64)> = Vec::new();
    for (r, face) in constraints.rigid_faces.iter().enumerate() {
        for &node in &face.nodes {
            check_node(|| format!("rigid_face[{r}]"), node, node_count)?;
        }
        let Some(&first) = face.nodes.first() else {
            continue;
        };
        for c in 0..3 {
            let tie = |uf: &mut UnionFind| {
                face.nodes
                    .iter()
                    .for_each(|&node| uf.union(3 * first + c, 3 * node + c))
            };
            match face.components[c] {
                RigidComponent::Free => {}
                RigidComponent::Loaded { force_n } => {
                    if !force_n.is_finite() {
                        return Err(FemError::NonFiniteInput {
                            what: "rigid face force",
                            node: first,
                            component: c,
                        });
                    }
                    tie(uf);
                    class_force.push((3 * first + c, force_n));
                }
                RigidComponent::Prescribed { displacement_m } => {
                    tie(uf);
                    prescribed.set(3 * first + c, displacement_m, "rigid face displacement")?;
                }
            }
        }
    }
    Ok(class_force)
}

/// Each class's prescribed value (with the DOF that gave it), if any member is prescribed; the
/// values of one class must agree.
fn class_values(
    uf: &mut UnionFind,
    prescribed: &Prescribed,
) -> FemResult<Vec<Option<(f64, usize)>>> {
    let n = prescribed.0.len();
    let mut class_value: Vec<Option<(f64, usize)>> = vec![None; n];
    for dof in 0..n {
        if let Some(v) = prescribed.0[dof] {
            let root = uf.find(dof);
            match class_value[root] {
                Some((old, _)) if !same_value(old, v) => {
                    return Err(FemError::ConflictingPrescribedValues {
                        node: dof / 3,
                        component: dof % 3,
                        first_m: old,
                        second_m: v,
                    });
                }
                Some(_) => {}
                None => class_value[root] = Some((v, dof)),
            }
        }
    }
    Ok(class_value)
}

/// The target of every full DOF (its class's value, or its class's reduced unknown, numbered
/// in the order of the classes' first DOF) and each unknown's representative DOF.
fn number_classes(
    uf: &mut UnionFind,
    class_value: &[Option<(f64, usize)>],
) -> (Vec<DofTarget>, Vec<usize>) {
    let n = class_value.len();
    let mut class_index: Vec<usize> = vec![usize::MAX; n];
    let mut targets = Vec::with_capacity(n);
    let mut representative = Vec::new();
    for dof in 0..n {
        let root = uf.find(dof);
        let target = match class_value[root] {
            Some((v, _)) => DofTarget::Prescribed(v),
            None => {
                if class_index[root] == usize::MAX {
                    class_index[root] = representative.len();
                    representative.push(dof);
                }
                DofTarget::Reduced(class_index[root])
            }
        };
        targets.push(target);
    }
    (targets, representative)
}

/// The map full DOF → reduced unknown or prescribed value, built from [`Constraints`].
#[derive(Debug, Clone, PartialEq)]
pub struct DofMap {
    targets: Vec<DofTarget>,
    reduced_count: usize,
    reduced_force: Vec<f64>,
    representative: Vec<usize>,
    rigid_faces: Vec<[Option<DofTarget>; 3]>,
}

impl DofMap {
    /// No constraints: q = u.
    pub fn unconstrained(node_count: usize) -> Self {
        let n = 3 * node_count;
        Self {
            targets: (0..n).map(DofTarget::Reduced).collect(),
            reduced_count: n,
            reduced_force: vec![0.0; n],
            representative: (0..n).collect(),
            rigid_faces: Vec::new(),
        }
    }

    /// Builds the map; errors name conflicting values, unknown nodes or non-finite inputs.
    /// DOFs tied by periodic pairs and rigid faces form classes (union–find); a class with a
    /// prescribed member is prescribed, every other class is one reduced unknown.
    pub fn new(node_count: usize, constraints: &Constraints) -> FemResult<Self> {
        let n = 3 * node_count;
        let mut uf = UnionFind::new(n);
        link_periodic(&mut uf, constraints, node_count)?;
        let mut prescribed = Prescribed(vec![None; n]);
        prescribed.dirichlet(constraints, node_count)?;
        let class_force = link_rigid_faces(&mut uf, &mut prescribed, constraints, node_count)?;
        let class_value = class_values(&mut uf, &prescribed)?;
        let (targets, representative) = number_classes(&mut uf, &class_value);
        let reduced_count = representative.len();
        let mut reduced_force = vec![0.0; reduced_count];
        for (dof, force) in class_force {
            if let DofTarget::Reduced(j) = targets[dof] {
                reduced_force[j] += force;
            }
        }
        let rigid_faces = constraints
            .rigid_faces
            .iter()
            .map(|face| {
                std::array::from_fn(|c| match (face.components[c], face.nodes.first()) {
                    (RigidComponent::Free, _) | (_, None) => None,
                    (_, Some(&first)) => Some(targets[3 * first + c]),
                })
            })
            .collect();
        Ok(Self {
            targets,
            reduced_count,
            reduced_force,
            representative,
            rigid_faces,
        })
    }

    /// Number of full DOFs (3 × nodes).
    pub fn full_count(&self) -> usize {
        self.targets.len()
    }

    /// Number of reduced unknowns.
    pub fn reduced_count(&self) -> usize {
        self.reduced_count
    }

    /// Target of full DOF `dof`.
    pub fn target(&self, dof: usize) -> DofTarget {
        self.targets[dof]
    }

    /// All targets.
    pub fn targets(&self) -> &[DofTarget] {
        &self.targets
    }

    /// The smallest full DOF mapped to reduced unknown `j` (for messages and post-processing).
    pub fn representative_dof(&self, j: usize) -> usize {
        self.representative[j]
    }

    /// External forces on reduced unknowns from loaded rigid faces (N).
    pub fn rigid_face_forces(&self) -> &[f64] {
        &self.reduced_force
    }

    /// Per rigid face and component: the target of its tied displacement (`None` = free).
    pub fn rigid_face_targets(&self) -> &[[Option<DofTarget>; 3]] {
        &self.rigid_faces
    }

    /// u_p: prescribed values at prescribed DOFs, 0 elsewhere (m).
    pub fn prescribed_vector(&self) -> Vec<f64> {
        self.targets
            .iter()
            .map(|t| {
                if let DofTarget::Prescribed(v) = t {
                    *v
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// u = T q + u_p.
    pub fn expand(&self, q: &[f64]) -> FemResult<Vec<f64>> {
        if q.len() != self.reduced_count {
            return Err(FemError::DimensionMismatch {
                what: "reduced solution",
                expected: self.reduced_count,
                found: q.len(),
            });
        }
        Ok(self
            .targets
            .iter()
            .map(|t| match t {
                DofTarget::Reduced(j) => q[*j],
                DofTarget::Prescribed(v) => *v,
            })
            .collect())
    }

    /// Tᵀ v: sums full-vector entries into their reduced unknowns (prescribed DOFs dropped).
    pub fn restrict(&self, v: &[f64]) -> FemResult<Vec<f64>> {
        if v.len() != self.full_count() {
            return Err(FemError::DimensionMismatch {
                what: "full vector",
                expected: self.full_count(),
                found: v.len(),
            });
        }
        let mut out = vec![0.0; self.reduced_count];
        for (t, x) in self.targets.iter().zip(v) {
            if let DofTarget::Reduced(j) = t {
                out[*j] += x;
            }
        }
        Ok(out)
    }
}

/// Reduced unknown of every full DOF as a compact table ([`PRESCRIBED`]: none).
fn reduced_table(dof_map: &DofMap) -> Vec<u32> {
    dof_map
        .targets
        .iter()
        .map(|t| match t {
            DofTarget::Reduced(j) => *j as u32,
            DofTarget::Prescribed(_) => PRESCRIBED,
        })
        .collect()
}

/// Scatter-map marker: entry couples a prescribed DOF and is dropped from K_red.
const DROPPED: u32 = u32::MAX;

/// Marker of a prescribed DOF in the compact table full DOF → reduced unknown.
const PRESCRIBED: u32 = u32::MAX;

/// Columns per rayon task when building the reduced pattern (pass 2) and scatter map (pass 3):
/// enough to amortise scheduling over ≈ 30–80 entries per column. Dimensionless; default 512.
pub const REDUCTION_COLUMNS_PER_TASK: usize = 512;

/// Blocks of full columns bucketed in parallel when building the reduced pattern; the result
/// does not depend on it. Dimensionless; default 16.
const REDUCTION_BLOCKS: usize = 16;

/// Candidate rows (reduced, upper: row ≤ column) of every reduced column contributed by the
/// full columns `cols`, as CSC (pointers over all `m` reduced columns, rows in full order).
fn column_buckets(
    m: usize,
    cp: &[usize],
    ri: &[usize],
    reduced: &[u32],
    skip: Option<&[bool]>,
    cols: std::ops::Range<usize>,
) -> (Vec<usize>, Vec<u32>) {
    let mut ptr = vec![0usize; m + 1];
    let pairs = |k: usize| {
        let rk = reduced[k];
        let rows = if rk == PRESCRIBED || skip.is_some_and(|s| s[k]) {
            &[][..]
        } else {
            &ri[cp[k]..cp[k + 1]]
        };
        rows.iter().filter_map(move |&i| {
            let rii = reduced[i];
            (rii != PRESCRIBED).then_some((rk as usize, rii as usize))
        })
    };
    for k in cols.clone() {
        for (rk, rii) in pairs(k) {
            ptr[rk.max(rii) + 1] += 1;
        }
    }
    for j in 0..m {
        ptr[j + 1] += ptr[j];
    }
    let mut fill = ptr[..m].to_vec();
    let mut rows = vec![0u32; ptr[m]];
    for k in cols {
        for (rk, rii) in pairs(k) {
            let col = rk.max(rii);
            rows[fill[col]] = rk.min(rii) as u32;
            fill[col] += 1;
        }
    }
    (ptr, rows)
}

/// The pattern of K_red = Tᵀ K T (upper CSC, rows sorted and unique) for the full upper pattern
/// (`cp`, `ri`). Full columns are bucketed by reduced column in [`REDUCTION_BLOCKS`] blocks (in
/// parallel), then each reduced column gathers its buckets, sorts and deduplicates (columns in
/// parallel). A pure index computation: the same result for any thread count.
fn reduced_pattern(
    m: usize,
    cp: &[usize],
    ri: &[usize],
    reduced: &[u32],
    skip: Option<&[bool]>,
) -> FemResult<(Vec<usize>, Vec<usize>)> {
    if m > u32::MAX as usize {
        return Err(FemError::SparseBackend(format!(
            "{m} reduced unknowns exceed 32-bit indices"
        )));
    }
    let bounds = crate::sparse::csr::split_columns(cp, REDUCTION_BLOCKS);
    let buckets: Vec<(Vec<usize>, Vec<u32>)> = bounds
        .par_windows(2)
        .map(|w| column_buckets(m, cp, ri, reduced, skip, w[0]..w[1]))
        .collect();
    let chunks: Vec<(Vec<usize>, Vec<usize>)> = (0..m)
        .into_par_iter()
        .chunks(REDUCTION_COLUMNS_PER_TASK)
        .map(|cols| {
            let (mut lens, mut rows) = (Vec::with_capacity(cols.len()), Vec::new());
            for j in cols {
                let start = rows.len();
                for (ptr, r) in &buckets {
                    rows.extend(r[ptr[j]..ptr[j + 1]].iter().map(|&i| i as usize));
                }
                rows[start..].sort_unstable();
                let mut len = start;
                for q in start..rows.len() {
                    if len == start || rows[q] != rows[len - 1] {
                        rows[len] = rows[q];
                        len += 1;
                    }
                }
                rows.truncate(len);
                lens.push(len - start);
            }
            (lens, rows)
        })
        .collect();
    drop(buckets);
    let mut col_ptr = Vec::with_capacity(m + 1);
    col_ptr.push(0usize);
    let total: usize = chunks.iter().map(|c| c.1.len()).sum();
    let mut rows = Vec::with_capacity(total);
    for (lens, r) in chunks {
        for len in lens {
            col_ptr.push(col_ptr.last().copied().unwrap_or(0) + len);
        }
        rows.extend(r);
    }
    Ok((col_ptr, rows))
}

/// Whether the reduction only selects DOFs: no two DOFs share an unknown (no rigid faces or
/// periodic ties), so unknowns are numbered in DOF order and K_red is K without the prescribed
/// rows and columns.
fn is_selection(dof_map: &DofMap) -> bool {
    // Unknowns are numbered as their first DOF comes (`DofMap::new`): with one DOF each they
    // increase with the DOF.
    let selected = dof_map
        .targets
        .iter()
        .filter(|t| matches!(t, DofTarget::Reduced(_)))
        .count();
    selected == dof_map.reduced_count && dof_map.representative.windows(2).all(|w| w[0] < w[1])
}

/// Full columns k of K whose reduced column is a plain selection, `None` when unknowns are not
/// numbered in the order of their first DOF. Column k is *clean* when its DOF is free and has
/// an unknown of its own, none of its rows is tied (shares its unknown with another DOF), and
/// it is no row of a tied column. Untied unknowns then increase with their DOF, so reduced
/// column r_k is exactly the unknowns of column k's free rows, in order, and no other full
/// column adds to it (an entry (k, k′ > k) lands in column r_k only if r_k′ < r_k, i.e. k′
/// tied). On the strip, with its post tips tied, most columns are clean.
fn clean_columns(
    cp: &[usize],
    ri: &[usize],
    reduced: &[u32],
    dof_map: &DofMap,
) -> Option<Vec<bool>> {
    if !dof_map.representative.windows(2).all(|w| w[0] < w[1]) {
        return None;
    }
    let mut count = vec![0u32; dof_map.reduced_count];
    for &r in reduced.iter().filter(|&&r| r != PRESCRIBED) {
        count[r as usize] = count[r as usize].saturating_add(1);
    }
    let tied = |k: usize| reduced[k] != PRESCRIBED && count[reduced[k] as usize] > 1;
    let mut clean: Vec<bool> = (0..reduced.len())
        .map(|k| reduced[k] != PRESCRIBED && !tied(k))
        .collect();
    for k in 0..reduced.len() {
        let tied_k = tied(k);
        for &i in &ri[cp[k]..cp[k + 1]] {
            if tied(i) {
                clean[k] = false;
            }
            if tied_k {
                clean[i] = false;
            }
        }
    }
    Some(clean)
}

/// The reduced pattern when `clean` ([`clean_columns`]) marks the full columns that are plain
/// selections: those copied with their free rows, the others through [`reduced_pattern`]. The
/// same pattern as [`reduced_pattern`] of all columns.
fn mostly_selected_pattern(
    m: usize,
    cp: &[usize],
    ri: &[usize],
    reduced: &[u32],
    dof_map: &DofMap,
    clean: &[bool],
) -> FemResult<(Vec<usize>, Vec<usize>)> {
    let (other_ptr, other_rows) = reduced_pattern(m, cp, ri, reduced, Some(clean))?;
    let mut col_ptr = Vec::with_capacity(m + 1);
    col_ptr.push(0usize);
    let mut rows = Vec::with_capacity(ri.len());
    for j in 0..m {
        let k = dof_map.representative[j];
        if clean[k] {
            rows.extend(
                ri[cp[k]..cp[k + 1]]
                    .iter()
                    .map(|&i| reduced[i])
                    .filter(|&r| r != PRESCRIBED)
                    .map(|r| r as usize),
            );
        } else {
            rows.extend_from_slice(&other_rows[other_ptr[j]..other_ptr[j + 1]]);
        }
        col_ptr.push(rows.len());
    }
    Ok((col_ptr, rows))
}

/// The reduced pattern and scatter map of a pure selection ([`is_selection`]) in one pass over
/// K's upper pattern: unknowns increase with the DOF, so every free column keeps its free rows
/// in order and its entries land one after another. The same result as the general passes.
fn selected_pattern(
    m: usize,
    cp: &[usize],
    ri: &[usize],
    reduced: &[u32],
) -> (Vec<usize>, Vec<usize>, Vec<u32>) {
    let mut col_ptr = Vec::with_capacity(m + 1);
    col_ptr.push(0usize);
    let mut rows = Vec::with_capacity(ri.len());
    let mut scatter = vec![DROPPED; ri.len()];
    for k in 0..cp.len() - 1 {
        if reduced[k] == PRESCRIBED {
            continue;
        }
        for p in cp[k]..cp[k + 1] {
            let rii = reduced[ri[p]];
            if rii != PRESCRIBED {
                scatter[p] = rows.len() as u32;
                rows.push(rii as usize);
            }
        }
        col_ptr.push(rows.len());
    }
    (col_ptr, rows, scatter)
}

/// Blocks of full columns whose scatter-map entries are computed in parallel; the result does
/// not depend on it. Dimensionless; default 64.
const SCATTER_BLOCKS: usize = 64;

/// Position in K_red (with the [`DOUBLE`] flag) of every entry of K's upper pattern (`cp`,
/// `ri`), or [`DROPPED`]; `reduced` is the unknown of every full DOF, (`col_ptr`, `rows`) the
/// reduced pattern. A pure index computation: the same result for any thread count.
fn scatter_map(
    cp: &[usize],
    ri: &[usize],
    reduced: &[u32],
    clean: Option<&[bool]>,
    col_ptr: &[usize],
    rows: &[usize],
) -> Vec<u32> {
    let n = cp.len() - 1;
    let bounds = crate::sparse::csr::split_columns(cp, SCATTER_BLOCKS);
    let mut scatter = Vec::with_capacity(cp[n]);
    scatter.resize(cp[n], DROPPED);
    let mut blocks: Vec<(std::ops::Range<usize>, &mut [u32])> = Vec::new();
    let mut rest = scatter.as_mut_slice();
    for w in bounds.windows(2) {
        let (block, tail) = std::mem::take(&mut rest).split_at_mut(cp[w[1]] - cp[w[0]]);
        blocks.push((w[0]..w[1], block));
        rest = tail;
    }
    blocks.into_par_iter().for_each(|(cols, out)| {
        let base = cp[cols.start];
        for k in cols {
            let rk = reduced[k];
            if rk == PRESCRIBED {
                continue;
            }
            if clean.is_some_and(|c| c[k]) {
                // Its free rows, in order, are the whole reduced column rk.
                let mut pos = col_ptr[rk as usize];
                for p in cp[k]..cp[k + 1] {
                    if reduced[ri[p]] != PRESCRIBED {
                        out[p - base] = pos as u32;
                        pos += 1;
                    }
                }
                continue;
            }
            for p in cp[k]..cp[k + 1] {
                let i = ri[p];
                let rii = reduced[i];
                if rii == PRESCRIBED {
                    continue;
                }
                let (r, c) = (rk.min(rii) as usize, rk.max(rii) as usize);
                let pos = col_ptr[c]
                    + rows[col_ptr[c]..col_ptr[c + 1]]
                        .binary_search(&r)
                        .expect("reduced pattern holds every entry");
                out[p - base] = pos as u32 | if rk == rii && i != k { DOUBLE } else { 0 };
            }
        }
    });
    scatter
}

/// Scatter-map flag: off-diagonal entry whose two DOFs merged into one unknown (counts twice).
const DOUBLE: u32 = 1 << 31;

/// The reduced system K_red = Tᵀ K T: its pattern (built once) and the scatter map from K's
/// entries. Reduce any matrix with K's pattern (e.g. after a material change) numerically.
#[derive(Debug, Clone)]
pub struct ReducedSystem {
    dof_map: DofMap,
    full_dim: usize,
    full_nnz: usize,
    full_fingerprint: u64,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    scatter: Vec<u32>,
}

impl ReducedSystem {
    /// Builds the reduced pattern and scatter map for matrices with the pattern of `full`.
    pub fn new(full: &SymmetricMatrix, dof_map: DofMap) -> FemResult<Self> {
        Self::from_structure(full.col_ptr(), full.row_idx(), dof_map)
    }

    /// [`Self::new`] for the matrices that [`crate::assemble_stiffness`] builds on `pattern`,
    /// before any is assembled (e.g. to run the symbolic analysis of K_red, through
    /// [`Self::zero_matrix`], while K is assembled).
    pub fn from_pattern(pattern: &StiffnessPattern, dof_map: DofMap) -> FemResult<Self> {
        Self::from_structure(&pattern.col_ptr, &pattern.row_idx, dof_map)
    }

    /// The reduced pattern of full upper CSC structure (`cp`, `ri`).
    fn from_structure(cp: &[usize], ri: &[usize], dof_map: DofMap) -> FemResult<Self> {
        let n = cp.len() - 1;
        if n != dof_map.full_count() {
            return Err(FemError::DimensionMismatch {
                what: "DOF map vs stiffness matrix",
                expected: n,
                found: dof_map.full_count(),
            });
        }
        let m = dof_map.reduced_count();
        if m >= PRESCRIBED as usize {
            return Err(FemError::SparseBackend(format!(
                "{m} reduced unknowns exceed 32-bit indices"
            )));
        }
        // Reduced unknown of every full DOF as a compact table (PRESCRIBED: none).
        let reduced = reduced_table(&dof_map);
        let (col_ptr, rows, scatter) = if is_selection(&dof_map) {
            selected_pattern(m, cp, ri, &reduced)
        } else {
            let clean = clean_columns(cp, ri, &reduced, &dof_map);
            // Passes 1–2: the reduced pattern (rows of every reduced column, sorted, unique);
            // clean columns copied, the others bucketed.
            let (col_ptr, rows) = match &clean {
                Some(clean) => mostly_selected_pattern(m, cp, ri, &reduced, &dof_map, clean)?,
                None => reduced_pattern(m, cp, ri, &reduced, None)?,
            };
            // Pass 3: scatter map of every full upper entry (blocks of full columns in parallel).
            let scatter = scatter_map(cp, ri, &reduced, clean.as_deref(), &col_ptr, &rows);
            (col_ptr, rows, scatter)
        };
        let write = rows.len();
        if write >= DOUBLE as usize {
            return Err(FemError::SparseBackend(format!(
                "reduced matrix has {write} entries, more than the 2^31 supported"
            )));
        }
        Ok(Self {
            dof_map,
            full_dim: n,
            full_nnz: ri.len(),
            full_fingerprint: fingerprint(n, cp, ri),
            col_ptr,
            row_idx: rows,
            scatter,
        })
    }

    /// The DOF map.
    pub fn dof_map(&self) -> &DofMap {
        &self.dof_map
    }

    /// Number of reduced unknowns.
    pub fn dim(&self) -> usize {
        self.dof_map.reduced_count()
    }

    fn check_full(&self, full: &SymmetricMatrix) -> FemResult<()> {
        if full.dim() != self.full_dim
            || full.nnz_upper() != self.full_nnz
            || fingerprint(full.dim(), full.col_ptr(), full.row_idx()) != self.full_fingerprint
        {
            return Err(FemError::PatternMismatch {
                detail: "matrix to reduce does not have the pattern the reduction was built for"
                    .into(),
            });
        }
        Ok(())
    }

    /// A matrix with the reduced pattern and zero values: the structure for a symbolic
    /// analysis, and the storage for [`Self::reduce_matrix_into`].
    pub fn zero_matrix(&self) -> SymmetricMatrix {
        SymmetricMatrix::from_trusted_parts(
            self.dim(),
            self.col_ptr.clone(),
            self.row_idx.clone(),
            vec![0.0; self.row_idx.len()],
        )
    }

    /// K_red = Tᵀ K T as a new matrix.
    pub fn reduce_matrix(&self, full: &SymmetricMatrix) -> FemResult<SymmetricMatrix> {
        let mut out = self.zero_matrix();
        self.reduce_matrix_into(full, &mut out)?;
        Ok(out)
    }

    /// K_red = Tᵀ K T into an existing reduced matrix (same pattern), reusing its storage.
    pub fn reduce_matrix_into(
        &self,
        full: &SymmetricMatrix,
        out: &mut SymmetricMatrix,
    ) -> FemResult<()> {
        self.check_full(full)?;
        if out.dim() != self.dim() || out.col_ptr() != self.col_ptr.as_slice() {
            return Err(FemError::PatternMismatch {
                detail: "output matrix does not have the reduced pattern".into(),
            });
        }
        let dst = out.values_mut();
        dst.fill(0.0);
        self.add_reduced_values(full, dst);
        Ok(())
    }

    /// The layout of K_red's full-row CSR (both triangles), for [`Self::reduce_csr_values`].
    pub fn csr_layout(&self) -> FemResult<CsrLayout> {
        CsrLayout::of_upper(&self.col_ptr, &self.row_idx)
    }

    /// K_red = Tᵀ K T as the values of the iterative path's full-row CSR (`layout` from
    /// [`Self::csr_layout`]): the upper values in a plain vector (no pattern copy), then
    /// gathered into rows in parallel. Pure copies after the reduction: the same bits as
    /// [`CsrMatrix::from_symmetric`] of [`Self::reduce_matrix`].
    pub fn reduce_csr_values(
        &self,
        full: &SymmetricMatrix,
        layout: &CsrLayout,
    ) -> FemResult<Vec<f64>> {
        self.check_full(full)?;
        if layout.upper_nnz() != self.row_idx.len() {
            return Err(FemError::PatternMismatch {
                detail: "CSR layout was built for another reduced pattern".into(),
            });
        }
        let mut upper = vec![0.0; self.row_idx.len()];
        self.add_reduced_values(full, &mut upper);
        Ok(layout.gather(&upper))
    }

    /// Adds K's values into the reduced upper values `dst` through the scatter map.
    fn add_reduced_values(&self, full: &SymmetricMatrix, dst: &mut [f64]) {
        for (v, &s) in full.values().iter().zip(&self.scatter) {
            if s == DROPPED {
                continue;
            }
            let pos = (s & !DOUBLE) as usize;
            dst[pos] += if s & DOUBLE != 0 { 2.0 * v } else { *v };
        }
    }

    /// K_red as the iterative path's full-row CSR, built without the upper-triangle copy
    /// ([`Self::csr_layout`] and [`Self::reduce_csr_values`] in one; keep those two to reduce
    /// several matrices with one layout).
    pub fn reduce_matrix_csr(&self, full: &SymmetricMatrix) -> FemResult<CsrMatrix> {
        let layout = self.csr_layout()?;
        let values = self.reduce_csr_values(full, &layout)?;
        Ok(layout.into_matrix(values))
    }

    /// f_red = Tᵀ (f − K u_p) + F_rigid for the full load `f` (N).
    pub fn reduce_load(&self, full: &SymmetricMatrix, f: &[f64]) -> FemResult<Vec<f64>> {
        self.check_full(full)?;
        if f.len() != self.full_dim {
            return Err(FemError::DimensionMismatch {
                what: "load vector",
                expected: self.full_dim,
                found: f.len(),
            });
        }
        if let Some(i) = f.iter().position(|v| !v.is_finite()) {
            return Err(FemError::NonFiniteInput {
                what: "load vector",
                node: i / 3,
                component: i % 3,
            });
        }
        let up = self.dof_map.prescribed_vector();
        let mut ku = vec![0.0; self.full_dim];
        full.mul_vec(&up, &mut ku);
        let r: Vec<f64> = f.iter().zip(&ku).map(|(a, b)| a - b).collect();
        let mut out = self.dof_map.restrict(&r)?;
        for (o, g) in out.iter_mut().zip(self.dof_map.rigid_face_forces()) {
            *o += g;
        }
        Ok(out)
    }

    /// u = T q + u_p.
    pub fn expand(&self, q: &[f64]) -> FemResult<Vec<f64>> {
        self.dof_map.expand(q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::Dirichlet;
    use crate::mesh_gen::{BoxFace, BoxMesh};
    use crate::{Material, Model, StiffnessPattern};

    #[test]
    fn one_pass_selection_gives_the_general_reduced_pattern_and_scatter_map() {
        let mesh = BoxMesh::tet10([2.0, 1.0, 1.0], [4, 3, 2]);
        let material = Material::isotropic(200e9, 0.3).expect("valid material");
        let model = Model::new(mesh.nodes.clone(), mesh.connectivity.clone(), material)
            .expect("valid box mesh");
        let constraints = Constraints {
            dirichlet: vec![
                Dirichlet::clamped(mesh.face_nodes(BoxFace::XMin)),
                Dirichlet::component(mesh.face_nodes(BoxFace::XMax), 2, 1e-6),
            ],
            ..Default::default()
        };
        let dof_map = DofMap::new(model.node_count(), &constraints).expect("valid constraints");
        assert!(is_selection(&dof_map));
        let pattern = StiffnessPattern::build(&model);
        let (cp, ri) = (&pattern.col_ptr, &pattern.row_idx);
        let reduced = reduced_table(&dof_map);
        let m = dof_map.reduced_count();
        let (col_ptr, rows) = reduced_pattern(m, cp, ri, &reduced, None).expect("pattern");
        let scatter = scatter_map(cp, ri, &reduced, None, &col_ptr, &rows);
        assert_eq!(
            selected_pattern(m, cp, ri, &reduced),
            (col_ptr, rows, scatter)
        );
    }

    #[test]
    fn tied_dofs_are_not_a_selection() {
        let mesh = BoxMesh::tet4([1.0, 1.0, 1.0], [2, 2, 2]);
        let constraints = Constraints {
            rigid_faces: vec![crate::RigidFace {
                nodes: mesh.face_nodes(BoxFace::XMax),
                components: [
                    RigidComponent::Loaded { force_n: 1.0 },
                    RigidComponent::Free,
                    RigidComponent::Free,
                ],
            }],
            ..Default::default()
        };
        let dof_map = DofMap::new(mesh.nodes.len(), &constraints).expect("valid constraints");
        assert!(!is_selection(&dof_map));
    }

    /// A strip-like set-up: a clamped top, a roller plane, and tied "tips" (z of two patches on
    /// the bottom, one of them with x bonded): most columns are clean, the rest go through the
    /// general passes, and the result equals the general passes on every column.
    #[test]
    fn mostly_selected_reduction_equals_the_general_one_with_tied_tips() {
        let mesh = BoxMesh::tet10([4.0, 1.0, 1.0], [8, 2, 3]);
        let material = Material::isotropic(200e9, 0.3).expect("valid material");
        let model = Model::new(mesh.nodes.clone(), mesh.connectivity.clone(), material)
            .expect("valid box mesh");
        let bottom = mesh.face_nodes(BoxFace::ZMin);
        let patch = |x0: f64, x1: f64| -> Vec<usize> {
            bottom
                .iter()
                .copied()
                .filter(|&n| (x0..=x1).contains(&mesh.nodes[n][0]))
                .collect()
        };
        let tip = |nodes: Vec<usize>, x: RigidComponent| crate::RigidFace {
            nodes,
            components: [
                x,
                RigidComponent::Free,
                RigidComponent::Loaded { force_n: 1.0 },
            ],
        };
        let constraints = Constraints {
            dirichlet: vec![
                Dirichlet::clamped(mesh.face_nodes(BoxFace::ZMax)),
                Dirichlet::component(mesh.face_nodes(BoxFace::YMin), 1, 0.0),
            ],
            rigid_faces: vec![
                tip(patch(0.9, 1.6), RigidComponent::Free),
                tip(
                    patch(2.4, 3.1),
                    RigidComponent::Prescribed {
                        displacement_m: 0.0,
                    },
                ),
            ],
            ..Default::default()
        };
        let dof_map = DofMap::new(model.node_count(), &constraints).expect("valid constraints");
        let pattern = StiffnessPattern::build(&model);
        let (cp, ri) = (&pattern.col_ptr, &pattern.row_idx);
        let reduced = reduced_table(&dof_map);
        let m = dof_map.reduced_count();
        let clean = clean_columns(cp, ri, &reduced, &dof_map).expect("first-DOF numbering");
        let clean_count = clean.iter().filter(|&&c| c).count();
        assert!(
            clean_count > m / 2 && clean_count < m,
            "{clean_count} clean columns of {m}: both paths are exercised"
        );
        let general = reduced_pattern(m, cp, ri, &reduced, None).expect("pattern");
        let mostly =
            mostly_selected_pattern(m, cp, ri, &reduced, &dof_map, &clean).expect("pattern");
        assert_eq!(mostly, general, "reduced pattern");
        let (col_ptr, rows) = general;
        assert_eq!(
            scatter_map(cp, ri, &reduced, Some(&clean), &col_ptr, &rows),
            scatter_map(cp, ri, &reduced, None, &col_ptr, &rows),
            "scatter map"
        );
    }
}
