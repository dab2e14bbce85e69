//! Constraint data: Dirichlet conditions, rigid faces, periodic node pairs. Pure data; the
//! reduction u = T q + u_p that enforces them lives in [`crate::reduction`].

use std::collections::HashMap;

use crate::error::{FemError, FemResult};

/// Prescribed displacements on a node set, per component (`None` = free).
#[derive(Debug, Clone, PartialEq)]
pub struct Dirichlet {
    /// Node indices.
    pub nodes: Vec<usize>,
    /// Prescribed displacement per component x, y, z (m), or `None`.
    pub displacement_m: [Option<f64>; 3],
}

impl Dirichlet {
    /// All three components fixed to zero (clamped).
    pub fn clamped(nodes: Vec<usize>) -> Self {
        Self {
            nodes,
            displacement_m: [Some(0.0); 3],
        }
    }

    /// One component (0 = x, 1 = y, 2 = z) prescribed to `value_m`.
    pub fn component(nodes: Vec<usize>, component: usize, value_m: f64) -> Self {
        let mut displacement_m = [None; 3];
        displacement_m[component] = Some(value_m);
        Self {
            nodes,
            displacement_m,
        }
    }
}

/// How one displacement component of a rigid face behaves.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum RigidComponent {
    /// Not tied: the nodes move independently in this component.
    #[default]
    Free,
    /// All nodes share one displacement; a total external force `force_n` (N) acts on it
    /// (0 for a free-floating tie).
    Loaded {
        /// Total force on the face in this component (N).
        force_n: f64,
    },
    /// All nodes share one prescribed displacement (m); the face force is a reaction.
    Prescribed {
        /// Face displacement (m).
        displacement_m: f64,
    },
}

/// A rigid face: per selected component, all its nodes share one displacement (a rigid
/// translation; rotations of the face are not modelled). Its total force is reported.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidFace {
    /// Node indices of the face.
    pub nodes: Vec<usize>,
    /// Behaviour per component x, y, z.
    pub components: [RigidComponent; 3],
}

/// Periodic pairs: u(slave) = u(master) for the selected components.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicPairs {
    /// `[slave, master]` node pairs.
    pub pairs: Vec<[usize; 2]>,
    /// Components tied (x, y, z).
    pub components: [bool; 3],
}

impl PeriodicPairs {
    /// Pairs every slave node with the master node at `x_slave − translation_m`, within
    /// `tolerance_m` (m). Errors name the first unmatched or ambiguous slave node.
    pub fn match_by_translation(
        nodes: &[[f64; 3]],
        slave_nodes: &[usize],
        master_nodes: &[usize],
        translation_m: [f64; 3],
        tolerance_m: f64,
        components: [bool; 3],
    ) -> FemResult<Self> {
        if !(tolerance_m > 0.0 && tolerance_m.is_finite()) {
            return Err(FemError::InvalidMaterialParameter {
                parameter: "tolerance_m",
                value: tolerance_m,
                reason: "periodic matching tolerance must be positive and finite",
            });
        }
        let node_count = nodes.len();
        for &n in slave_nodes.iter().chain(master_nodes) {
            if n >= node_count {
                return Err(FemError::ConstraintNodeOutOfRange {
                    context: "periodic pairs".into(),
                    node: n,
                    node_count,
                });
            }
        }
        // Hash masters into cells of edge 2 × tolerance; search the 27 neighbour cells.
        let cell = 2.0 * tolerance_m;
        let key = |x: [f64; 3]| x.map(|v| (v / cell).floor() as i64);
        let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for &m in master_nodes {
            grid.entry(key(nodes[m])).or_default().push(m);
        }
        let mut pairs = Vec::with_capacity(slave_nodes.len());
        for &s in slave_nodes {
            let target: [f64; 3] = std::array::from_fn(|j| nodes[s][j] - translation_m[j]);
            let k = key(target);
            let mut found: Option<usize> = None;
            for dz in -1..=1 {
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        let Some(cands) = grid.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) else {
                            continue;
                        };
                        for &m in cands {
                            let d2: f64 = (0..3).map(|j| (nodes[m][j] - target[j]).powi(2)).sum();
                            if d2 <= tolerance_m * tolerance_m {
                                if let Some(first) = found
                                    && first != m
                                {
                                    return Err(FemError::AmbiguousPeriodicMatch {
                                        slave_node: s,
                                        first_master: first,
                                        second_master: m,
                                        tolerance_m,
                                    });
                                }
                                found = Some(m);
                            }
                        }
                    }
                }
            }
            match found {
                Some(m) if m != s => pairs.push([s, m]),
                Some(_) => {}
                None => {
                    return Err(FemError::UnmatchedPeriodicNode {
                        slave_node: s,
                        position: nodes[s],
                        translation_m,
                        tolerance_m,
                    });
                }
            }
        }
        Ok(Self { pairs, components })
    }
}

/// All constraints of a static problem.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Constraints {
    /// Prescribed displacements.
    pub dirichlet: Vec<Dirichlet>,
    /// Rigid faces (per-component shared displacement).
    pub rigid_faces: Vec<RigidFace>,
    /// Periodic ties.
    pub periodic: Vec<PeriodicPairs>,
}
