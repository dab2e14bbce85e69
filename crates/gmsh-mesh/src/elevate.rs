//! Tet4 → Tet10: one midside node per edge of a linear mesh, placed on the true geometry where
//! the boundary is a cylinder, so that gmsh need not run its own order elevation (about a quarter
//! of its time on the default 100-post strip, half of that in `pruneMeshVertexAssociations`).
//!
//! Placement (the same as gmsh's curvilinear order 2, `Mesh.SecondOrderLinear = 0`, without
//! `HighOrderOptimize`):
//! - an edge of a triangle of a cylinder-wall group (the wall, and the circles and straight lines
//!   bounding it), or an edge on the rim of a disk group (a boundary edge of the group with both
//!   ends on the circle; [`CylinderWalls::rims_only`]): the chord midpoint m = (a + b)/2 moved
//!   radially onto the cylinder,
//!   q = c + (m − c)∥ + R (m − c)⊥ / |(m − c)⊥|, with c a point of the axis, ∥ and ⊥ the parts
//!   along and across the axis. For a cylinder parametrised by (angle, height) this is gmsh's
//!   parametric midpoint (mean angle, mean height): the chord midpoint of two points of the same
//!   radius lies on the bisecting half-plane, at the mean height. Valid while an edge spans less
//!   than half a turn (|(m − c)⊥| > 0), which [`MIN_CHORD_MIDPOINT_RADIUS`] checks;
//! - every other edge (volume, plane faces): the midpoint (a + b)/2.
//!
//! New nodes follow the corner nodes, numbered in the order their edges first appear in the tets
//! (tet by tet, edges in gmsh's order 0-1, 1-2, 2-0, 3-0, 3-2, 3-1): the same input gives the
//! same mesh, bit for bit. Their gmsh tags continue after the largest corner tag.

use std::collections::HashMap;

use crate::error::{MeshError, Result};
use crate::geometry::{Point, TET10_EDGES};
use crate::mesh::{Faces, TetMesh, Tets};

/// Version of this placement rule, for caches keyed by the mesh it makes: change it whenever the
/// position or numbering of the added nodes changes.
pub const ELEVATION_VERSION: u32 = 1;

/// Largest distance of a wall node from its cylinder, relative to the radius. Default 1e-6:
/// gmsh puts the nodes on the OpenCASCADE surface to ≈ 1e-12; a larger gap means the cylinders
/// passed do not describe the mesh's walls.
pub const WALL_TOLERANCE: f64 = 1e-6;

/// Smallest distance of a wall edge's chord midpoint from the axis, relative to the radius, for
/// the radial projection to be defined (an edge spanning half a turn has its midpoint on the
/// axis). Default 0.5 (an edge spanning 120°).
pub const MIN_CHORD_MIDPOINT_RADIUS: f64 = 0.5;

/// A circular cylinder (the wall of a post): a point of its axis, the axis direction (need not be
/// unit length) and the radius, in the mesh's units (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    /// A point of the axis (m).
    pub axis_point: Point,
    /// Direction of the axis (any non-zero length).
    pub axis_direction: Point,
    /// Radius (m).
    pub radius: f64,
}

impl Cylinder {
    /// The part of `p − axis_point` across the axis, and `axis_point` plus the part along it.
    fn split(&self, p: Point) -> (Point, Point) {
        let d = self.axis_direction;
        let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let v = [
            p[0] - self.axis_point[0],
            p[1] - self.axis_point[1],
            p[2] - self.axis_point[2],
        ];
        let s = (v[0] * d[0] + v[1] * d[1] + v[2] * d[2]) / dd;
        let along = [
            self.axis_point[0] + s * d[0],
            self.axis_point[1] + s * d[1],
            self.axis_point[2] + s * d[2],
        ];
        ([p[0] - along[0], p[1] - along[1], p[2] - along[2]], along)
    }

    /// Distance of `p` from the axis.
    fn axis_distance(&self, p: Point) -> f64 {
        norm(self.split(p).0)
    }

    /// `p` moved radially onto the cylinder, or `None` if `p` is too close to the axis.
    fn project(&self, p: Point) -> Option<Point> {
        let (across, along) = self.split(p);
        let r = norm(across);
        (r > MIN_CHORD_MIDPOINT_RADIUS * self.radius).then(|| {
            let k = self.radius / r;
            [
                along[0] + k * across[0],
                along[1] + k * across[1],
                along[2] + k * across[2],
            ]
        })
    }
}

fn norm(v: Point) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The triangles of the surface group `group` lie on the cylinders `cylinders` (each triangle on
/// the one whose axis is nearest to it), or, with `rims_only`, the group is made of flat disks
/// whose rims are circles of those cylinders.
#[derive(Debug, Clone, PartialEq)]
pub struct CylinderWalls {
    /// Physical surface group of the wall (or disk) triangles.
    pub group: String,
    /// The cylinders (for posts: one per post).
    pub cylinders: Vec<Cylinder>,
    /// `false`: every edge of the group's triangles is on its cylinder (a wall; all nodes must
    /// lie on it). `true`: the group is flat disks (e.g. the tip circles imprinted on a stator);
    /// only its boundary edges with both ends on the cylinder are curved (a half disk's straight
    /// edge stays straight).
    pub rims_only: bool,
}

/// Edge `[a, b]` with a < b.
fn edge_key(a: usize, b: usize) -> (usize, usize) {
    if a < b { (a, b) } else { (b, a) }
}

/// The Tet10 mesh of the Tet4 mesh `mesh` (see the module documentation), with Tri6 faces in
/// every surface group and midside pairs added to the periodic pairs. Errors: the mesh is not
/// Tet4, a wall group is missing, a wall node lies off every cylinder, a wall edge spans half a
/// turn, or an element comes out inverted ([`MeshError::Invalid`], [`MeshError::MissingGroup`],
/// [`MeshError::BadElements`]).
pub fn elevate_to_tet10(mesh: &TetMesh, walls: &[CylinderWalls]) -> Result<TetMesh> {
    let invalid = |detail: String| MeshError::Invalid {
        file: mesh.source.clone(),
        detail,
    };
    let Tets::Linear(tets) = &mesh.tets else {
        return Err(invalid(
            "asked to add midside nodes to a mesh that is not Tet4".into(),
        ));
    };
    let mut nodes = mesh.nodes.clone();
    let mut node_tags = mesh.node_tags.clone();
    let mut next_tag = node_tags.iter().copied().max().unwrap_or(0);
    let mut midside: HashMap<(usize, usize), usize> = HashMap::with_capacity(tets.len() * 2);
    let mut tet10 = Vec::with_capacity(tets.len());
    for t in tets {
        let mut n = [0usize; 10];
        n[..4].copy_from_slice(t);
        for (k, [i, j]) in TET10_EDGES.iter().enumerate() {
            let (a, b) = edge_key(t[*i], t[*j]);
            n[4 + k] = *midside.entry((a, b)).or_insert_with(|| {
                let (p, q) = (nodes[a], nodes[b]);
                nodes.push([
                    0.5 * (p[0] + q[0]),
                    0.5 * (p[1] + q[1]),
                    0.5 * (p[2] + q[2]),
                ]);
                next_tag += 1;
                node_tags.push(next_tag);
                nodes.len() - 1
            });
        }
        tet10.push(n);
    }
    let curved = curve_wall_edges(mesh, walls, &midside, &mut nodes)?;
    let mut surface_groups = std::collections::BTreeMap::new();
    for (name, faces) in &mesh.surface_groups {
        surface_groups.insert(name.clone(), tri6_faces(mesh, name, faces, &midside)?);
    }
    let mut notes = mesh.notes.clone();
    notes.push(format!(
        "Tet10 midside nodes added to the Tet4 mesh by gmsh_mesh::elevate (version \
         {ELEVATION_VERSION}): {} nodes, {curved} of them on cylinder walls",
        midside.len()
    ));
    let elevated = TetMesh {
        source: mesh.source.clone(),
        nodes,
        node_tags,
        tets: Tets::Quadratic(tet10),
        tet_tags: mesh.tet_tags.clone(),
        tet_groups: mesh.tet_groups.clone(),
        surface_groups,
        groups: mesh.groups.clone(),
        periodic_node_pairs: periodic_midside_pairs(&mesh.periodic_node_pairs, &midside),
        binary: mesh.binary,
        notes,
    };
    elevated.check_elements()?;
    Ok(elevated)
}

/// Move the midside nodes of the wall triangles' edges onto their cylinders; returns how many.
fn curve_wall_edges(
    mesh: &TetMesh,
    walls: &[CylinderWalls],
    midside: &HashMap<(usize, usize), usize>,
    nodes: &mut [Point],
) -> Result<usize> {
    let invalid = |detail: String| MeshError::Invalid {
        file: mesh.source.clone(),
        detail,
    };
    let mut moved = std::collections::BTreeSet::new();
    for wall in walls {
        let faces = mesh.group_faces(&wall.group)?;
        let rim_edges = wall.rims_only.then(|| boundary_edges(faces));
        for f in 0..faces.len() {
            let c = faces.corners(f);
            let centroid =
                [0, 1, 2].map(|k| (nodes[c[0]][k] + nodes[c[1]][k] + nodes[c[2]][k]) / 3.0);
            let cylinder = wall
                .cylinders
                .iter()
                .min_by(|x, y| {
                    x.axis_distance(centroid)
                        .total_cmp(&y.axis_distance(centroid))
                })
                .ok_or_else(|| invalid(format!("no cylinder given for group {}", wall.group)))?;
            let on = |p: Point| {
                (cylinder.axis_distance(p) - cylinder.radius).abs()
                    <= WALL_TOLERANCE * cylinder.radius
            };
            for &node in c.iter().filter(|_| !wall.rims_only) {
                let gap = (cylinder.axis_distance(nodes[node]) - cylinder.radius).abs();
                if gap > WALL_TOLERANCE * cylinder.radius {
                    return Err(invalid(format!(
                        "node {} of surface group {} is {gap:.3e} m off its cylinder \
                         (radius {:.3e} m): the cylinders do not describe the walls",
                        mesh.node_tags[node], wall.group, cylinder.radius
                    )));
                }
            }
            for [i, j] in [[0, 1], [1, 2], [2, 0]] {
                let key = edge_key(c[i], c[j]);
                if let Some(rims) = &rim_edges
                    && !(rims.contains(&key) && on(nodes[key.0]) && on(nodes[key.1]))
                {
                    continue;
                }
                let Some(&m) = midside.get(&key) else {
                    return Err(invalid(format!(
                        "edge of nodes {} and {} of group {} is no tet edge",
                        mesh.node_tags[key.0], mesh.node_tags[key.1], wall.group
                    )));
                };
                if moved.insert(m) {
                    nodes[m] = cylinder.project(nodes[m]).ok_or_else(|| {
                        invalid(format!(
                            "edge of nodes {} and {} of group {} spans half a turn of its \
                             cylinder: its curved midside node is undefined",
                            mesh.node_tags[key.0], mesh.node_tags[key.1], wall.group
                        ))
                    })?;
                }
            }
        }
    }
    Ok(moved.len())
}

/// The edges of exactly one triangle of `faces` (the group's boundary).
fn boundary_edges(faces: &Faces) -> std::collections::HashSet<(usize, usize)> {
    let mut count: HashMap<(usize, usize), u32> = HashMap::new();
    for f in 0..faces.len() {
        let c = faces.corners(f);
        for [i, j] in [[0, 1], [1, 2], [2, 0]] {
            *count.entry(edge_key(c[i], c[j])).or_insert(0) += 1;
        }
    }
    count
        .into_iter()
        .filter(|&(_, n)| n == 1)
        .map(|(e, _)| e)
        .collect()
}

/// The Tri6 faces of a group's Tri3 faces (midside nodes 3:(0,1) 4:(1,2) 5:(2,0)).
fn tri6_faces(
    mesh: &TetMesh,
    name: &str,
    faces: &Faces,
    midside: &HashMap<(usize, usize), usize>,
) -> Result<Faces> {
    let mut out = Vec::with_capacity(faces.len());
    for f in 0..faces.len() {
        let c = faces.corners(f);
        let mut n = [c[0], c[1], c[2], 0, 0, 0];
        for (k, [i, j]) in [[0, 1], [1, 2], [2, 0]].iter().enumerate() {
            n[3 + k] = *midside
                .get(&edge_key(c[*i], c[*j]))
                .ok_or_else(|| MeshError::Invalid {
                    file: mesh.source.clone(),
                    detail: format!("a triangle of surface group {name} has an edge of no tet"),
                })?;
        }
        out.push(n);
    }
    Ok(Faces::Quadratic(out))
}

/// The corner pairs plus, for every edge whose two corners are slaves of an edge of masters, the
/// pair of their midside nodes; sorted.
fn periodic_midside_pairs(
    pairs: &[[usize; 2]],
    midside: &HashMap<(usize, usize), usize>,
) -> Vec<[usize; 2]> {
    let master: HashMap<usize, usize> = pairs.iter().map(|&[s, m]| (s, m)).collect();
    let mut out = pairs.to_vec();
    for (&(a, b), &mid) in midside {
        if let (Some(&ma), Some(&mb)) = (master.get(&a), master.get(&b))
            && let Some(&mmid) = midside.get(&edge_key(ma, mb))
        {
            out.push([mid, mmid]);
        }
    }
    out.sort_unstable();
    out
}

/// Refuse an elevated mesh with inverted or degenerate curved elements.
#[cfg(test)]
mod tests {
    use super::*;

    /// One tet (positive volume) whose face 0-1-2 lies on the cylinder of radius 1 about the z axis (group "wall").
    fn one_tet_on_a_cylinder() -> TetMesh {
        let angle = |deg: f64| [deg.to_radians().cos(), deg.to_radians().sin()];
        let ([x0, y0], [x1, y1]) = (angle(0.0), angle(30.0));
        TetMesh::linear_for_tests(
            vec![[x0, y0, 0.0], [x1, y1, 0.0], [x0, y0, 0.5], [2.0, 0.0, 0.0]],
            vec![[0, 1, 2, 3]],
            &[("wall", vec![[0, 1, 2]])],
        )
    }

    fn z_cylinder(radius: f64) -> Vec<CylinderWalls> {
        vec![CylinderWalls {
            group: "wall".into(),
            cylinders: vec![Cylinder {
                axis_point: [0.0, 0.0, 0.0],
                axis_direction: [0.0, 0.0, 2.0],
                radius,
            }],
            rims_only: false,
        }]
    }

    #[test]
    fn wall_edges_get_the_mean_angle_point_and_other_edges_the_midpoint() {
        let mesh = one_tet_on_a_cylinder();
        let tet10 = elevate_to_tet10(&mesh, &z_cylinder(1.0)).expect("elevated tet");
        let Tets::Quadratic(t) = &tet10.tets else {
            panic!("Tet10 expected");
        };
        let p = |local: usize| tet10.nodes[t[0][local]];
        let (c, s) = (15f64.to_radians().cos(), 15f64.to_radians().sin());
        // Edge 0-1 (node 4): the arc's mean angle, 15°, on the radius-1 circle.
        let gap01 = (p(4)[0] - c).abs() + (p(4)[1] - s).abs() + p(4)[2].abs();
        assert!(
            gap01 < 1e-15,
            "midside node of the arc 0-1 off the circle by {gap01:e}"
        );
        // Edge 3-0 (node 7) is on no wall: the straight midpoint.
        assert_eq!(p(7), [1.5, 0.0, 0.0], "midside node of the edge 3-0");
        // Edge 2-0 (node 6) is a vertical line of the wall: its midpoint, which is on it.
        assert!((p(6)[0] - 1.0).abs() < 1e-15 && (p(6)[2] - 0.25).abs() < 1e-15);
        let Faces::Quadratic(f) = &tet10.surface_groups["wall"] else {
            panic!("Tri6 wall expected");
        };
        assert_eq!(
            f[0][3], t[0][4],
            "the wall's Tri6 shares the tet's midside node 0-1"
        );
        assert_eq!(tet10.nodes.len(), 10, "4 corners and 6 midside nodes");
        assert_eq!(tet10.node_tags[4..], [5, 6, 7, 8, 9, 10], "new node tags");
    }

    #[test]
    fn a_wall_node_off_the_cylinder_is_refused() {
        let err = elevate_to_tet10(&one_tet_on_a_cylinder(), &z_cylinder(1.1))
            .expect_err("cylinder of the wrong radius");
        assert!(
            err.to_string().contains("off its cylinder"),
            "error names the wall node: {err}"
        );
    }
}
