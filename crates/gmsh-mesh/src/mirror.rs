//! The whole mesh from the half meshed up to a mirror plane x = x_m: the half's nodes, elements
//! and faces, and their reflections x → 2·x_m − x. A body symmetric about that plane (the strip of
//! an even number of posts about its middle, `slider-strip.geo` `mirror_x`) is meshed by gmsh in
//! about half the time, and its mesh comes out exactly symmetric.
//!
//! - Nodes on the plane (those of the [`MirrorPlane::groups`] faces) are shared by both halves;
//!   every other node gets its image, numbered after all nodes of the half, in the half's order
//!   (gmsh tags continue after the largest).
//! - A reflection reverses orientation: an image tet lists its corners as (0, 2, 1, 3) (Tet10
//!   midside nodes permuted to match), an image triangle as (0, 2, 1), so image tets keep a
//!   positive volume and image faces an outward normal.
//! - The plane's faces become interior and are dropped; a face group named in
//!   [`MirrorPlane::renames`] (e.g. the end x = 0, whose image is the end x = 2·x_m) puts its
//!   images in a group of its own; every other group holds its faces and their images.
//!
//! The same half gives the same whole mesh, bit for bit.

use std::collections::BTreeMap;

use crate::error::{MeshError, Result};
use crate::mesh::{Faces, PhysicalGroup, TetMesh, Tets};

/// Version of this construction, for caches keyed by the mesh it makes: change it whenever the
/// numbering or position of the image nodes or elements changes.
pub const MIRROR_VERSION: u32 = 1;

/// Largest distance of a node from the mirror plane on the far side, or of a plane node from the
/// plane, relative to the mesh's extent in x. Default 1e-9 (gmsh puts plane nodes on it to
/// ≈ 1e-15).
pub const PLANE_TOLERANCE: f64 = 1e-9;

/// Corner order of an image tet: Tet4 (0, 2, 1, 3); Tet10 with the midside nodes of the swapped
/// edges (0-1 ↔ 2-0, 3-2 ↔ 3-1) exchanged (gmsh order 4:(0,1) 5:(1,2) 6:(2,0) 7:(3,0) 8:(3,2)
/// 9:(3,1)).
const TET4_IMAGE: [usize; 4] = [0, 2, 1, 3];
const TET10_IMAGE: [usize; 10] = [0, 2, 1, 3, 6, 5, 4, 7, 9, 8];
/// Corner order of an image triangle: Tri3 (0, 2, 1); Tri6 midside 3:(0,1) ↔ 5:(2,0).
const TRI3_IMAGE: [usize; 3] = [0, 2, 1];
const TRI6_IMAGE: [usize; 6] = [0, 2, 1, 5, 4, 3];

/// A surface group of the half whose images form a group of their own in the whole mesh.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MirrorRename {
    /// The group of the half (e.g. "slider_x0").
    pub from: String,
    /// The group of its images (e.g. "slider_x1"); must not exist in the half.
    pub to: String,
    /// Physical tag of the new group.
    pub tag: i32,
}

/// The mirror plane x = x_m of a half mesh.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MirrorPlane {
    /// Surface groups lying on the plane (the half's cut faces); their nodes are the shared ones
    /// and x_m is their x.
    pub groups: Vec<String>,
    /// Groups whose images get a name of their own.
    pub renames: Vec<MirrorRename>,
}

/// The whole mesh: `half` and its reflection in the plane of `plane` (see the module
/// documentation). Errors ([`MeshError::Invalid`], [`MeshError::MissingGroup`]): a plane group
/// is missing or its nodes do not lie on one plane x = const, a node lies beyond the plane, the
/// half has periodic node pairs, a renamed group's new name exists already; and
/// [`MeshError::BadElements`] if an image element came out inverted.
pub fn mirror_in_x(half: &TetMesh, plane: &MirrorPlane) -> Result<TetMesh> {
    let invalid = |detail: String| MeshError::Invalid {
        file: half.source.clone(),
        detail,
    };
    if !half.periodic_node_pairs.is_empty() {
        return Err(invalid(
            "a mesh with periodic node pairs cannot be mirrored".into(),
        ));
    }
    let (x_m, on_plane) = plane_position(half, plane)?;
    let (nodes, node_tags, image) = image_nodes(half, x_m, &on_plane);
    let tets = image_tets(&half.tets, &image);
    let max_tet_tag = half.tet_tags.iter().copied().max().unwrap_or(0);
    let tet_tags = half
        .tet_tags
        .iter()
        .copied()
        .chain((1..=half.tet_tags.len() as u64).map(|k| max_tet_tag + k))
        .collect();
    let tet_groups = half.tet_groups.repeat(2);
    let surface_groups = image_faces(half, plane, &image)?;
    let groups = whole_groups(half, plane);
    let shared = image.iter().enumerate().filter(|(i, j)| i == *j).count();
    let mut notes = half.notes.clone();
    notes.push(format!(
        "whole mesh made by reflecting the half in the plane x = {x_m:e} m (gmsh_mesh::mirror \
         version {MIRROR_VERSION}): {} nodes, {shared} of them on the plane",
        nodes.len()
    ));
    let whole = TetMesh {
        source: half.source.clone(),
        nodes,
        node_tags,
        tets,
        tet_tags,
        tet_groups,
        surface_groups,
        groups,
        periodic_node_pairs: Vec::new(),
        binary: half.binary,
        notes,
    };
    whole.check_elements()?;
    Ok(whole)
}

/// x_m and the plane groups' nodes, checked to lie on one plane x = x_m with every node of the
/// half on its side.
fn plane_position(half: &TetMesh, plane: &MirrorPlane) -> Result<(f64, Vec<usize>)> {
    let invalid = |detail: String| MeshError::Invalid {
        file: half.source.clone(),
        detail,
    };
    let mut on_plane = Vec::new();
    for group in &plane.groups {
        on_plane.extend(half.group_nodes(group)?);
    }
    let Some(&first) = on_plane.first() else {
        return Err(invalid(format!(
            "the mirror plane groups {:?} have no nodes",
            plane.groups
        )));
    };
    let [lo, hi] = half.bounding_box().unwrap_or([[0.0; 3]; 2]);
    let tolerance = PLANE_TOLERANCE * (hi[0] - lo[0]);
    let x_m = half.nodes[first][0];
    if let Some(&n) = on_plane
        .iter()
        .find(|&&n| (half.nodes[n][0] - x_m).abs() > tolerance)
    {
        return Err(invalid(format!(
            "mirror plane node {} at x = {:e} m is off the plane x = {x_m:e} m of node {}",
            half.node_tags[n], half.nodes[n][0], half.node_tags[first]
        )));
    }
    if let Some(n) = (0..half.nodes.len()).find(|&n| half.nodes[n][0] > x_m + tolerance) {
        return Err(invalid(format!(
            "node {} at x = {:e} m lies beyond the mirror plane x = {x_m:e} m",
            half.node_tags[n], half.nodes[n][0]
        )));
    }
    Ok((x_m, on_plane))
}

/// Nodes, tags and `image[n]` (the index of node n's reflection; n itself for the nodes
/// `plane_nodes` on the plane).
fn image_nodes(
    half: &TetMesh,
    x_m: f64,
    plane_nodes: &[usize],
) -> (Vec<[f64; 3]>, Vec<u64>, Vec<usize>) {
    let n = half.nodes.len();
    let mut on_plane = vec![false; n];
    for &v in plane_nodes {
        on_plane[v] = true;
    }
    let mut nodes = half.nodes.clone();
    let mut node_tags = half.node_tags.clone();
    let mut next_tag = node_tags.iter().copied().max().unwrap_or(0);
    let image = (0..n)
        .map(|v| {
            if on_plane[v] {
                return v;
            }
            let [x, y, z] = half.nodes[v];
            nodes.push([2.0 * x_m - x, y, z]);
            next_tag += 1;
            node_tags.push(next_tag);
            nodes.len() - 1
        })
        .collect();
    (nodes, node_tags, image)
}

/// The half's tets followed by their images.
fn image_tets(tets: &Tets, image: &[usize]) -> Tets {
    fn both<const N: usize>(
        tets: &[[usize; N]],
        order: [usize; N],
        image: &[usize],
    ) -> Vec<[usize; N]> {
        let images = tets.iter().map(|t| order.map(|k| image[t[k]]));
        tets.iter().copied().chain(images).collect()
    }
    match tets {
        Tets::Linear(t) => Tets::Linear(both(t, TET4_IMAGE, image)),
        Tets::Quadratic(t) => Tets::Quadratic(both(t, TET10_IMAGE, image)),
    }
}

/// Image triangles of `faces`.
fn reflected(faces: &Faces, image: &[usize]) -> Faces {
    match faces {
        Faces::Linear(f) => {
            Faces::Linear(f.iter().map(|t| TRI3_IMAGE.map(|k| image[t[k]])).collect())
        }
        Faces::Quadratic(f) => {
            Faces::Quadratic(f.iter().map(|t| TRI6_IMAGE.map(|k| image[t[k]])).collect())
        }
    }
}

/// Faces and their images appended.
fn with_images(faces: &Faces, images: Faces) -> Faces {
    match (faces, images) {
        (Faces::Linear(f), Faces::Linear(g)) => Faces::Linear([f.as_slice(), &g].concat()),
        (Faces::Quadratic(f), Faces::Quadratic(g)) => Faces::Quadratic([f.as_slice(), &g].concat()),
        _ => unreachable!("an image has the order of its faces"),
    }
}

/// The whole mesh's face groups (see the module documentation).
fn image_faces(
    half: &TetMesh,
    plane: &MirrorPlane,
    image: &[usize],
) -> Result<BTreeMap<String, Faces>> {
    let mut groups = BTreeMap::new();
    for (name, faces) in &half.surface_groups {
        if plane.groups.contains(name) {
            continue;
        }
        let images = reflected(faces, image);
        match plane.renames.iter().find(|r| &r.from == name) {
            Some(rename) => {
                if half.group(&rename.to).is_some() {
                    return Err(MeshError::Invalid {
                        file: half.source.clone(),
                        detail: format!(
                            "the images of group \"{name}\" would go to \"{}\", which the half \
                             mesh has already",
                            rename.to
                        ),
                    });
                }
                groups.insert(name.clone(), faces.clone());
                groups.insert(rename.to.clone(), images);
            }
            None => {
                groups.insert(name.clone(), with_images(faces, images));
            }
        }
    }
    Ok(groups)
}

/// The whole mesh's physical groups: the plane groups dropped, renamed images added, element
/// and entity counts of the others doubled (curves and points, which the reader keeps no
/// elements of, unchanged).
fn whole_groups(half: &TetMesh, plane: &MirrorPlane) -> Vec<PhysicalGroup> {
    let mut groups: Vec<PhysicalGroup> = Vec::new();
    for group in &half.groups {
        if group.dim == 2 && plane.groups.contains(&group.name) {
            continue;
        }
        let rename = plane.renames.iter().find(|r| r.from == group.name);
        let doubled = group.dim >= 2 && rename.is_none();
        groups.push(PhysicalGroup {
            entity_count: group.entity_count * if doubled { 2 } else { 1 },
            element_count: group.element_count * if doubled { 2 } else { 1 },
            ..group.clone()
        });
        if let Some(rename) = rename.filter(|_| group.dim == 2) {
            groups.push(PhysicalGroup {
                tag: rename.tag,
                name: rename.to.clone(),
                ..group.clone()
            });
        }
    }
    groups.sort_by_key(|g| (g.dim, g.tag));
    groups
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One tet on x ≤ 1 with its face 0-1-2 on the plane x = 1 (group "cut"), the slanted face
    /// 1-3-2 in group "end" (renamed), the face 0-3-1 on z = 0 in group "floor" (kept).
    fn half_tet() -> TetMesh {
        let faces = [
            ("cut", vec![[0, 1, 2]]),
            ("end", vec![[1, 3, 2]]),
            ("floor", vec![[0, 3, 1]]),
        ];
        TetMesh {
            source: "half".into(),
            node_tags: vec![10, 11, 12, 13],
            tet_tags: vec![5],
            groups: faces
                .iter()
                .enumerate()
                .map(|(k, (name, _))| PhysicalGroup {
                    dim: 2,
                    tag: k as i32 + 1,
                    name: name.to_string(),
                    named: true,
                    entity_count: 1,
                    element_count: 1,
                })
                .collect(),
            ..TetMesh::linear_for_tests(
                vec![
                    [1.0, 0.0, 0.0],
                    [1.0, 1.0, 0.0],
                    [1.0, 0.0, 1.0],
                    [0.0, 0.0, 0.0],
                ],
                vec![[0, 2, 1, 3]],
                &faces,
            )
        }
    }

    fn plane() -> MirrorPlane {
        MirrorPlane {
            groups: vec!["cut".into()],
            renames: vec![MirrorRename {
                from: "end".into(),
                to: "end_image".into(),
                tag: 9,
            }],
        }
    }

    #[test]
    fn the_reflection_shares_the_plane_nodes_and_keeps_volumes_and_normals_outward() {
        let half = half_tet();
        assert!(half.tet_volume(0) > 0.0);
        let whole = mirror_in_x(&half, &plane()).unwrap();
        assert_eq!(whole.nodes.len(), 5, "three plane nodes shared, one image");
        assert_eq!(whole.nodes[4], [2.0, 0.0, 0.0]);
        assert_eq!(whole.node_tags[4], 14);
        assert_eq!(whole.tet_tags, vec![5, 6]);
        assert_eq!(whole.tet_groups, vec![Some(1), Some(1)]);
        assert!(whole.tet_volume(1) > 0.0);
        assert_eq!(whole.volume(), 2.0 * half.volume());
        assert!(
            !whole.surface_groups.contains_key("cut"),
            "the cut is interior"
        );
        assert_eq!(
            whole.face_area("end").unwrap(),
            half.face_area("end").unwrap()
        );
        assert_eq!(
            whole.face_area("end_image").unwrap(),
            half.face_area("end").unwrap()
        );
        assert_eq!(
            whole.face_area("floor").unwrap(),
            2.0 * half.face_area("floor").unwrap()
        );
        // Outward normals: the half's "end" faces -x, its image +x; "floor" faces -z both times.
        let normal = |faces: &Faces, i: usize| {
            let [a, b, c] = faces.corners(i).map(|n| whole.nodes[n]);
            let (u, v) = (
                [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
                [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
            );
            [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ]
        };
        assert!(normal(whole.group_faces("end").unwrap(), 0)[0] < 0.0);
        assert!(normal(whole.group_faces("end_image").unwrap(), 0)[0] > 0.0);
        let floor = whole.group_faces("floor").unwrap();
        assert!(normal(floor, 0)[2] < 0.0 && normal(floor, 1)[2] < 0.0);
        let names: Vec<(i32, &str)> = whole
            .groups
            .iter()
            .map(|g| (g.tag, g.name.as_str()))
            .collect();
        assert_eq!(names, vec![(2, "end"), (3, "floor"), (9, "end_image")]);
        assert_eq!(whole.group("floor").unwrap().element_count, 2);
    }

    #[test]
    fn tet10_images_permute_their_midside_nodes_with_their_corners() {
        for (k, &[a, b]) in crate::geometry::TET10_EDGES.iter().enumerate() {
            let image_edge = [TET4_IMAGE[a], TET4_IMAGE[b]];
            let [c, d] = crate::geometry::TET10_EDGES[TET10_IMAGE[4 + k] - 4];
            assert!(
                image_edge == [c, d] || image_edge == [d, c],
                "midside node {} of the image sits on edge {image_edge:?}",
                4 + k
            );
        }
        for (k, [a, b]) in [[0, 1], [1, 2], [2, 0]].into_iter().enumerate() {
            let image_edge = [TRI3_IMAGE[a], TRI3_IMAGE[b]];
            let [c, d] = [[0, 1], [1, 2], [2, 0]][TRI6_IMAGE[3 + k] - 3];
            assert!(image_edge == [c, d] || image_edge == [d, c]);
        }
    }

    #[test]
    fn a_node_beyond_the_plane_or_a_bent_plane_is_refused_by_tag() {
        let mut beyond = half_tet();
        beyond.nodes[3][0] = 1.5;
        let e = mirror_in_x(&beyond, &plane()).unwrap_err().to_string();
        assert!(
            e.contains("node 13") && e.contains("beyond the mirror plane"),
            "{e}"
        );
        let mut bent = half_tet();
        bent.nodes[2][0] = 1.001;
        let e = mirror_in_x(&bent, &plane()).unwrap_err().to_string();
        assert!(e.contains("node 12") && e.contains("off the plane"), "{e}");
        let mut periodic = half_tet();
        periodic.periodic_node_pairs = vec![[0, 1]];
        assert!(mirror_in_x(&periodic, &plane()).is_err());
        let missing = MirrorPlane {
            groups: vec!["nowhere".into()],
            renames: Vec::new(),
        };
        let e = mirror_in_x(&half_tet(), &missing).unwrap_err().to_string();
        assert!(e.contains("nowhere"), "{e}");
    }
}
