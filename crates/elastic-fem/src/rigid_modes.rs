//! Detection of rigid-body modes left free by the constraints, before any factorisation.
//!
//! Each connected body (elements sharing nodes) has six rigid modes: translations t_x, t_y,
//! t_z and rotations ω about the body centroid c, u(x) = t + ω × (x − c)/L (L = RMS radius of
//! the body, so all six columns have comparable size). A mode combination a ∈ ℝ^{6B} survives
//! the constraints iff it vanishes at every prescribed DOF and takes equal values on DOFs tied
//! into one reduced unknown. With C the matrix of those conditions, the free combinations
//! are the null space of G = Cᵀ C (6B × 6B), found by a symmetric eigen-decomposition and
//! named by reduced row-echelon form (rotations first, so a body fixed in z only reports
//! "translation x, translation y, rotation about z").

use nalgebra::{DMatrix, SymmetricEigen};

use crate::error::{FemError, FemResult};
use crate::model::Model;
use crate::reduction::{DofMap, DofTarget};

/// Eigenvalue of G below which a rigid-mode combination counts as unconstrained.
/// Dimensionless (modes scaled to unit size); default 1e-9.
pub const RIGID_MODE_TOLERANCE: f64 = 1e-9;

/// Smallest pivot accepted when naming null-space vectors by row reduction. Dimensionless;
/// default 1e-6.
const NAMING_PIVOT_TOLERANCE: f64 = 1e-6;

/// Largest Gram matrix (6 × bodies coupled by ties) analysed; larger groups of tied bodies are
/// skipped by the pre-check (the factorisation's pivot check still catches a singular system).
/// Default 1200 (200 bodies).
pub const MAX_GROUP_DIMENSION: usize = 1200;

const MODE_NAMES: [&str; 6] = [
    "rotation about x",
    "rotation about y",
    "rotation about z",
    "translation x",
    "translation y",
    "translation z",
];

/// One unconstrained rigid-body motion.
#[derive(Debug, Clone, PartialEq)]
pub struct FreeRigidMode {
    /// Body index (connected component of the mesh).
    pub body: usize,
    /// A node of that body (its smallest index), to identify it.
    pub body_node: usize,
    /// Name, e.g. "translation z" or "rotation about x".
    pub name: &'static str,
}

struct Bodies {
    /// Body of each node, `usize::MAX` for nodes in no element.
    of_node: Vec<usize>,
    first_node: Vec<usize>,
    centroid: Vec<[f64; 3]>,
    scale: Vec<f64>,
}

fn find_bodies(model: &Model) -> Bodies {
    let n = model.node_count();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    let mut in_element = vec![false; n];
    let conn = model.connectivity();
    for e in 0..conn.len() {
        let en = conn.element_nodes(e);
        for &node in en {
            in_element[node] = true;
            // Both roots are looked up afresh: the first node's root changes as links are made.
            let (r0, r) = (find(&mut parent, en[0]), find(&mut parent, node));
            if r != r0 {
                let (lo, hi) = (r.min(r0), r.max(r0));
                parent[hi] = lo;
            }
        }
    }
    let mut body_of_root = vec![usize::MAX; n];
    let mut of_node = vec![usize::MAX; n];
    let mut first_node = Vec::new();
    for node in 0..n {
        if !in_element[node] {
            continue;
        }
        let r = find(&mut parent, node);
        if body_of_root[r] == usize::MAX {
            body_of_root[r] = first_node.len();
            first_node.push(node);
        }
        of_node[node] = body_of_root[r];
    }
    let nb = first_node.len();
    let mut centroid = vec![[0.0; 3]; nb];
    let mut count = vec![0usize; nb];
    for node in 0..n {
        let b = of_node[node];
        if b != usize::MAX {
            for j in 0..3 {
                centroid[b][j] += model.nodes()[node][j];
            }
            count[b] += 1;
        }
    }
    for b in 0..nb {
        centroid[b] = centroid[b].map(|v| v / count[b] as f64);
    }
    let mut scale = vec![0.0; nb];
    for node in 0..n {
        let b = of_node[node];
        if b != usize::MAX {
            scale[b] += (0..3)
                .map(|j| (model.nodes()[node][j] - centroid[b][j]).powi(2))
                .sum::<f64>();
        }
    }
    for b in 0..nb {
        let s = (scale[b] / count[b] as f64).sqrt();
        scale[b] = if s > 0.0 { s } else { 1.0 };
    }
    Bodies {
        of_node,
        first_node,
        centroid,
        scale,
    }
}

/// Values of the six scaled modes (ω_x, ω_y, ω_z, t_x, t_y, t_z) at full DOF `dof`.
fn mode_values(model: &Model, bodies: &Bodies, dof: usize) -> Option<(usize, [f64; 6])> {
    let node = dof / 3;
    let k = dof % 3;
    let b = bodies.of_node[node];
    if b == usize::MAX {
        return None;
    }
    let x = model.nodes()[node];
    let d: [f64; 3] = std::array::from_fn(|j| (x[j] - bodies.centroid[b][j]) / bodies.scale[b]);
    let mut v = [0.0; 6];
    // (e_j × d)_k for rotation about axis j.
    for j in 0..3 {
        let mut e = [0.0; 3];
        e[j] = 1.0;
        let cross = [
            e[1] * d[2] - e[2] * d[1],
            e[2] * d[0] - e[0] * d[2],
            e[0] * d[1] - e[1] * d[0],
        ];
        v[j] = cross[k];
    }
    v[3 + k] = 1.0;
    Some((b, v))
}

/// Lists the rigid-body modes (per body) that the DOF map leaves free. Nodes outside every
/// element with free DOFs are reported as an error (their stiffness is zero).
pub fn free_rigid_body_modes(model: &Model, dof_map: &DofMap) -> FemResult<Vec<FreeRigidMode>> {
    if dof_map.full_count() != model.dof_count() {
        return Err(FemError::DimensionMismatch {
            what: "DOF map vs model",
            expected: model.dof_count(),
            found: dof_map.full_count(),
        });
    }
    let bodies = find_bodies(model);
    let groups = BodyGroups::new(&bodies, dof_map)?;
    let grams = groups.grams(model, &bodies, dof_map);
    let mut modes = Vec::new();
    for (group, gram) in grams.into_iter().enumerate() {
        let Some(gram) = gram else { continue };
        for col in null_space_pivots(gram) {
            let body = groups.bodies[group][col / 6];
            modes.push(FreeRigidMode {
                body,
                body_node: bodies.first_node[body],
                name: MODE_NAMES[col % 6],
            });
        }
    }
    // Report translations before rotations within a body.
    modes.sort_by_key(|m| {
        (
            m.body,
            if m.name.starts_with("translation") {
                0
            } else {
                1
            },
            m.name,
        )
    });
    Ok(modes)
}

/// Bodies coupled by ties (a reduced unknown shared by DOFs of two bodies) form groups; each
/// group is analysed on its own.
struct BodyGroups {
    /// The bodies of each group.
    bodies: Vec<Vec<usize>>,
    /// Each body's index within its group.
    local: Vec<usize>,
    /// Each body's group.
    group_of_body: Vec<usize>,
}

impl BodyGroups {
    /// The groups of `bodies` under `dof_map`'s ties; free nodes of no element are an error.
    fn new(bodies: &Bodies, dof_map: &DofMap) -> FemResult<Self> {
        let nb = bodies.first_node.len();
        let body_of = |dof: usize| Some(bodies.of_node[dof / 3]).filter(|&b| b != usize::MAX);
        let mut group_parent: Vec<usize> = (0..nb).collect();
        fn root(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        let mut orphans = Vec::new();
        for (dof, target) in dof_map.targets().iter().enumerate() {
            if let DofTarget::Reduced(j) = target {
                let rep = dof_map.representative_dof(*j);
                match (body_of(dof), body_of(rep)) {
                    (None, _) if rep == dof => orphans.push(dof / 3),
                    (Some(a), Some(b)) if a != b => {
                        let (ra, rb) = (root(&mut group_parent, a), root(&mut group_parent, b));
                        group_parent[ra.max(rb)] = ra.min(rb);
                    }
                    _ => {}
                }
            }
        }
        if let Some(&node) = orphans.first() {
            orphans.dedup();
            return Err(FemError::UnconstrainedRigidBodyModes {
                modes: format!(
                    "{} node(s) belong to no element and are not fixed, first node {node}",
                    orphans.len()
                ),
            });
        }
        let mut group_of_root = vec![usize::MAX; nb];
        let mut groups = BodyGroups {
            bodies: Vec::new(),
            local: vec![0usize; nb],
            group_of_body: vec![0usize; nb],
        };
        for b in 0..nb {
            let r = root(&mut group_parent, b);
            if group_of_root[r] == usize::MAX {
                group_of_root[r] = groups.bodies.len();
                groups.bodies.push(Vec::new());
            }
            let g = group_of_root[r];
            groups.local[b] = groups.bodies[g].len();
            groups.group_of_body[b] = g;
            groups.bodies[g].push(b);
        }
        Ok(groups)
    }

    /// Each group's Gram matrix of the constraint rows on its bodies' rigid modes (`None` for
    /// a group above [`MAX_GROUP_DIMENSION`]).
    fn grams(&self, model: &Model, bodies: &Bodies, dof_map: &DofMap) -> Vec<Option<DMatrix<f64>>> {
        let mut grams: Vec<Option<DMatrix<f64>>> = self
            .bodies
            .iter()
            .map(|bs| {
                (6 * bs.len() <= MAX_GROUP_DIMENSION)
                    .then(|| DMatrix::zeros(6 * bs.len(), 6 * bs.len()))
            })
            .collect();
        let mut row: Vec<(usize, f64)> = Vec::with_capacity(12);
        for (dof, target) in dof_map.targets().iter().enumerate() {
            row.clear();
            let Some(group) = self.constraint_row(model, bodies, dof_map, dof, target, &mut row)
            else {
                continue;
            };
            if let Some(g) = grams[group].as_mut() {
                for &(i, a) in &row {
                    for &(j, b) in &row {
                        g[(i, j)] += a * b;
                    }
                }
            }
        }
        grams
    }

    /// The constraint row of `dof` on its group's modes (a prescribed DOF: its mode values; a
    /// tied DOF: its values minus its representative's) and the group; `None`: no row.
    fn constraint_row(
        &self,
        model: &Model,
        bodies: &Bodies,
        dof_map: &DofMap,
        dof: usize,
        target: &DofTarget,
        row: &mut Vec<(usize, f64)>,
    ) -> Option<usize> {
        let local = &self.local;
        match target {
            DofTarget::Prescribed(_) => {
                let (b, v) = mode_values(model, bodies, dof)?;
                row.extend((0..6).map(|m| (6 * local[b] + m, v[m])));
                Some(self.group_of_body[b])
            }
            DofTarget::Reduced(j) => {
                let rep = dof_map.representative_dof(*j);
                if rep == dof {
                    return None;
                }
                let (Some((b, v)), Some((br, vr))) = (
                    mode_values(model, bodies, dof),
                    mode_values(model, bodies, rep),
                ) else {
                    return None;
                };
                row.extend((0..6).map(|m| (6 * local[b] + m, v[m])));
                for m in 0..6 {
                    let col = 6 * local[br] + m;
                    match row.iter_mut().find(|(i, _)| *i == col) {
                        Some(entry) => entry.1 -= vr[m],
                        None => row.push((col, -vr[m])),
                    }
                }
                Some(self.group_of_body[b])
            }
        }
    }
}

/// Null space of the Gram matrix G, named by the pivot columns of its row-reduced basis
/// (columns ordered ω_x, ω_y, ω_z, t_x, t_y, t_z per body).
fn null_space_pivots(g: DMatrix<f64>) -> Vec<usize> {
    let dim = g.nrows();
    if dim == 0 {
        return Vec::new();
    }
    let eigen = SymmetricEigen::new(g);
    let null: Vec<usize> = (0..dim)
        .filter(|&i| eigen.eigenvalues[i] < RIGID_MODE_TOLERANCE)
        .collect();
    let mut rows: Vec<Vec<f64>> = null
        .iter()
        .map(|&i| eigen.eigenvectors.column(i).iter().copied().collect())
        .collect();
    let mut pivots = Vec::new();
    let mut next = 0usize;
    for col in 0..dim {
        if next == rows.len() {
            break;
        }
        let (best, val) = (next..rows.len())
            .map(|r| (r, rows[r][col].abs()))
            .fold((next, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        if val < NAMING_PIVOT_TOLERANCE {
            continue;
        }
        rows.swap(next, best);
        let p = rows[next][col];
        rows[next].iter_mut().for_each(|v| *v /= p);
        let pivot_row = rows[next].clone();
        for (r, row) in rows.iter_mut().enumerate() {
            if r != next {
                let factor = row[col];
                if factor != 0.0 {
                    row.iter_mut()
                        .zip(&pivot_row)
                        .for_each(|(v, q)| *v -= factor * q);
                }
            }
        }
        pivots.push(col);
        next += 1;
    }
    pivots
}

/// Fails with [`FemError::UnconstrainedRigidBodyModes`] naming every free mode, e.g.
/// "body 0 (node 0): translation z, rotation about x".
pub fn check_rigid_body_modes(model: &Model, dof_map: &DofMap) -> FemResult<()> {
    let modes = free_rigid_body_modes(model, dof_map)?;
    if modes.is_empty() {
        return Ok(());
    }
    let mut text = String::new();
    let mut current = usize::MAX;
    for m in &modes {
        if m.body != current {
            if current != usize::MAX {
                text.push_str("; ");
            }
            text.push_str(&format!(
                "body {} (node {}): {}",
                m.body, m.body_node, m.name
            ));
            current = m.body;
        } else {
            text.push_str(&format!(", {}", m.name));
        }
    }
    Err(FemError::UnconstrainedRigidBodyModes { modes: text })
}
