//! Consistent nodal load vectors: surface tractions and pressures on boundary triangles
//! (Tri3/Tri6), body forces, point forces. Every function *adds* into a full load vector `f`
//! of length 3 × nodes (N), DOF `3 n + c`.
//!
//! f_a = ∫_Γ N_a t dA (traction t in Pa), f_a = −∫_Γ N_a p n dA (pressure p in Pa pushing
//! against the triangle normal n = (x1−x0)×(x2−x0)/|…|, i.e. into the body when n is the
//! outward normal), f_a = ∫_Ω N_a b dV (body force b in N/m³).

use rayon::prelude::*;

use crate::error::{FemError, FemResult};
use crate::model::{Connectivity, Model};
use crate::quadrature::{tet_degree5, triangle_degree4};
use crate::shape::{Tet4, Tet10, TetShape, triangle_shape};

/// Boundary triangles (0-based node indices, gmsh order for Tri6).
#[derive(Debug, Clone, PartialEq)]
pub enum SurfaceTriangles {
    /// Linear triangles.
    Tri3(Vec<[usize; 3]>),
    /// Quadratic triangles: vertices, then edges (0,1), (1,2), (2,0).
    Tri6(Vec<[usize; 6]>),
}

impl SurfaceTriangles {
    /// Number of triangles.
    pub fn len(&self) -> usize {
        match self {
            SurfaceTriangles::Tri3(t) => t.len(),
            SurfaceTriangles::Tri6(t) => t.len(),
        }
    }

    /// Whether there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// All node indices used (sorted, unique).
    pub fn nodes(&self) -> Vec<usize> {
        let mut v: Vec<usize> = match self {
            SurfaceTriangles::Tri3(t) => t.iter().flatten().copied().collect(),
            SurfaceTriangles::Tri6(t) => t.iter().flatten().copied().collect(),
        };
        v.sort_unstable();
        v.dedup();
        v
    }
}

fn check_load_vector(f: &[f64], node_count: usize) -> FemResult<()> {
    if f.len() != 3 * node_count {
        return Err(FemError::DimensionMismatch {
            what: "load vector",
            expected: 3 * node_count,
            found: f.len(),
        });
    }
    Ok(())
}

/// Integrates `integrand(N_a, area_normal)` (area_normal = ∂x/∂ξ × ∂x/∂η, |·| = dA/dξdη) over
/// one triangle and adds N_a-weighted vectors into `f`.
fn integrate_triangle<const N: usize>(
    nodes: &[[f64; 3]],
    tri: &[usize; N],
    index: usize,
    load: &dyn Fn([f64; 3]) -> [f64; 3],
    f: &mut [f64],
) -> FemResult<()> {
    for &n in tri {
        if n >= nodes.len() {
            return Err(FemError::ConstraintNodeOutOfRange {
                context: format!("surface triangle {index}"),
                node: n,
                node_count: nodes.len(),
            });
        }
    }
    let rule = triangle_degree4();
    for (xi, w) in rule.points.iter().zip(&rule.weights) {
        let (shape, grad) = triangle_shape::<N>(*xi);
        let mut t1 = [0.0; 3];
        let mut t2 = [0.0; 3];
        for a in 0..N {
            for j in 0..3 {
                t1[j] += grad[a][0] * nodes[tri[a]][j];
                t2[j] += grad[a][1] * nodes[tri[a]][j];
            }
        }
        let area_normal = [
            t1[1] * t2[2] - t1[2] * t2[1],
            t1[2] * t2[0] - t1[0] * t2[2],
            t1[0] * t2[1] - t1[1] * t2[0],
        ];
        let v = load(area_normal);
        for a in 0..N {
            for j in 0..3 {
                f[3 * tri[a] + j] += w * shape[a] * v[j];
            }
        }
    }
    Ok(())
}

fn integrate_surface(
    nodes: &[[f64; 3]],
    triangles: &SurfaceTriangles,
    load: &dyn Fn([f64; 3]) -> [f64; 3],
    f: &mut [f64],
) -> FemResult<()> {
    check_load_vector(f, nodes.len())?;
    match triangles {
        SurfaceTriangles::Tri3(t) => t
            .iter()
            .enumerate()
            .try_for_each(|(i, tri)| integrate_triangle(nodes, tri, i, load, f)),
        SurfaceTriangles::Tri6(t) => t
            .iter()
            .enumerate()
            .try_for_each(|(i, tri)| integrate_triangle(nodes, tri, i, load, f)),
    }
}

/// Adds the consistent nodal forces of a uniform traction `traction_pa` (Pa) on the triangles.
pub fn add_surface_traction(
    nodes: &[[f64; 3]],
    triangles: &SurfaceTriangles,
    traction_pa: [f64; 3],
    f: &mut [f64],
) -> FemResult<()> {
    if traction_pa.iter().any(|v| !v.is_finite()) {
        return Err(FemError::NonFiniteInput {
            what: "surface traction",
            node: 0,
            component: 0,
        });
    }
    integrate_surface(
        nodes,
        triangles,
        &|an| {
            let da = (an[0] * an[0] + an[1] * an[1] + an[2] * an[2]).sqrt();
            traction_pa.map(|t| t * da)
        },
        f,
    )
}

/// Adds the consistent nodal forces of a uniform pressure `pressure_pa` (Pa, positive pushes
/// against the triangle normal).
pub fn add_pressure(
    nodes: &[[f64; 3]],
    triangles: &SurfaceTriangles,
    pressure_pa: f64,
    f: &mut [f64],
) -> FemResult<()> {
    if !pressure_pa.is_finite() {
        return Err(FemError::NonFiniteInput {
            what: "pressure",
            node: 0,
            component: 0,
        });
    }
    integrate_surface(nodes, triangles, &|an| an.map(|v| -pressure_pa * v), f)
}

/// Total area of the triangles (m²).
pub fn surface_area(nodes: &[[f64; 3]], triangles: &SurfaceTriangles) -> FemResult<f64> {
    // Integrate the traction (1, 0, 0) Pa and sum the x forces.
    let mut f = vec![0.0; 3 * nodes.len()];
    add_surface_traction(nodes, triangles, [1.0, 0.0, 0.0], &mut f)?;
    Ok(f.iter().step_by(3).sum())
}

fn body_force_element<const N: usize, S: TetShape<N>>(
    x: &[[f64; 3]; N],
    body_force: &(dyn Fn([f64; 3]) -> [f64; 3] + Sync),
) -> [[f64; 3]; N] {
    let rule = tet_degree5();
    let mut fe = [[0.0; 3]; N];
    for (xi, w) in rule.points.iter().zip(&rule.weights) {
        let shape = S::values(*xi);
        let Some((_, det)) = crate::element::physical_gradients::<N, S>(x, *xi) else {
            continue;
        };
        let mut pos = [0.0; 3];
        for a in 0..N {
            for j in 0..3 {
                pos[j] += shape[a] * x[a][j];
            }
        }
        let b = body_force(pos);
        for a in 0..N {
            for j in 0..3 {
                fe[a][j] += w * det * shape[a] * b[j];
            }
        }
    }
    fe
}

/// Adds ∫ N_a b(x) dV for a body force density `body_force(x)` (N/m³), integrated with the
/// degree-5 tetrahedron rule.
pub fn add_body_force(
    model: &Model,
    body_force: impl Fn([f64; 3]) -> [f64; 3] + Sync,
    f: &mut [f64],
) -> FemResult<()> {
    check_load_vector(f, model.node_count())?;
    let per_element: Vec<(Vec<usize>, Vec<[f64; 3]>)> = match model.connectivity() {
        Connectivity::Tet4(conn) => conn
            .par_iter()
            .map(|el| {
                (
                    el.to_vec(),
                    body_force_element::<4, Tet4>(&model.element_coords(el), &body_force).to_vec(),
                )
            })
            .collect(),
        Connectivity::Tet10(conn) => conn
            .par_iter()
            .map(|el| {
                (
                    el.to_vec(),
                    body_force_element::<10, Tet10>(&model.element_coords(el), &body_force)
                        .to_vec(),
                )
            })
            .collect(),
    };
    for (nodes, fe) in per_element {
        for (n, v) in nodes.iter().zip(fe) {
            for j in 0..3 {
                f[3 * n + j] += v[j];
            }
        }
    }
    if let Some(i) = f.iter().position(|v| !v.is_finite()) {
        return Err(FemError::NonFiniteInput {
            what: "body force load",
            node: i / 3,
            component: i % 3,
        });
    }
    Ok(())
}

/// Adds a point force `force_n` (N) at `node`.
pub fn add_nodal_force(node: usize, force_n: [f64; 3], f: &mut [f64]) -> FemResult<()> {
    if 3 * node + 2 >= f.len() {
        return Err(FemError::ConstraintNodeOutOfRange {
            context: "nodal force".into(),
            node,
            node_count: f.len() / 3,
        });
    }
    for j in 0..3 {
        f[3 * node + j] += force_n[j];
    }
    Ok(())
}
