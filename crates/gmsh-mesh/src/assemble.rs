//! From the raw blocks of an MSH file to a validated [`TetMesh`]: tag lookup, renumbering,
//! physical groups, boundary-face orientation and conformity, periodic pairs.

use std::collections::{BTreeMap, HashMap, HashSet};

use crate::error::{MeshError, Result};
use crate::geometry::{self, tet10_edge_node};
use crate::mesh::{Faces, PhysicalGroup, TetMesh, Tets};
use crate::msh::RawMsh;
use crate::msh::element_types::{TET4, TET10, TRI3, TRI6, element_type_name};

/// Name of a dimension, used for unnamed groups (`surface_7`) and messages.
fn dim_kind(dim: i32) -> &'static str {
    match dim {
        0 => "point",
        1 => "curve",
        2 => "surface",
        _ => "volume",
    }
}

/// Tri6 with the orientation reversed: corners (0, 2, 1), midside nodes (2-0, 1-2, 0-1).
fn flip_tri6(f: [usize; 6]) -> [usize; 6] {
    [f[0], f[2], f[1], f[5], f[4], f[3]]
}

struct Builder<'a> {
    file: &'a str,
    notes: Vec<String>,
}

impl Builder<'_> {
    fn invalid(&self, detail: String) -> MeshError {
        MeshError::Invalid {
            file: self.file.to_string(),
            detail,
        }
    }
}

/// Build the mesh. Quality is not checked here (see `crate::read`).
pub(crate) fn assemble(file: &str, raw: RawMsh) -> Result<TetMesh> {
    let mut b = Builder {
        file,
        notes: Vec::new(),
    };
    for skipped in &raw.skipped_sections {
        b.notes.push(format!(
            "section ${skipped} skipped (not used by this reader)"
        ));
    }

    // Nodes: tag -> position in file order.
    let total_nodes: usize = raw.node_blocks.iter().map(|blk| blk.tags.len()).sum();
    let mut file_index: HashMap<u64, usize> = HashMap::with_capacity(total_nodes);
    let mut file_tags = Vec::with_capacity(total_nodes);
    let mut file_coords = Vec::with_capacity(total_nodes);
    for block in &raw.node_blocks {
        for (&tag, &xyz) in block.tags.iter().zip(&block.coords) {
            if !xyz.iter().all(|c| c.is_finite()) {
                return Err(b.invalid(format!("node {tag} has a non-finite coordinate {xyz:?}")));
            }
            if file_index.insert(tag, file_tags.len()).is_some() {
                return Err(b.invalid(format!("node tag {tag} appears twice in $Nodes")));
            }
            file_tags.push(tag);
            file_coords.push(xyz);
        }
    }

    // Elements.
    let mut seen_element_tags: HashSet<u64> = HashSet::new();
    let mut tet_type: Option<i32> = None;
    let mut tet_tags = Vec::new();
    let mut tet_nodes_file: Vec<usize> = Vec::new(); // flat, file node indices
    let mut tet_groups = Vec::new();
    // (physical surface tag) -> (element tags, flat file node indices)
    let mut surface_faces: BTreeMap<i32, (Vec<u64>, Vec<usize>)> = BTreeMap::new();
    let mut tri_type: Option<i32> = None;
    let mut skipped_types: BTreeMap<i32, usize> = BTreeMap::new();
    let mut unassigned_triangles = 0usize;
    let mut multi_volume_entities = Vec::new();
    for block in &raw.element_blocks {
        let Some(physicals) = raw
            .entity_physicals
            .get(&(block.entity_dim, block.entity_tag))
        else {
            return Err(b.invalid(format!(
                "element block of {} on {} entity {} which $Entities does not declare",
                element_type_name(block.element_type),
                dim_kind(block.entity_dim),
                block.entity_tag
            )));
        };
        for &tag in &block.tags {
            if !seen_element_tags.insert(tag) {
                return Err(b.invalid(format!("element tag {tag} appears twice in $Elements")));
            }
        }
        let expected_dim = match block.element_type {
            TET4 | TET10 => Some(3),
            TRI3 | TRI6 => Some(2),
            _ => None,
        };
        let Some(expected_dim) = expected_dim else {
            *skipped_types.entry(block.element_type).or_default() += block.tags.len();
            continue;
        };
        if block.entity_dim != expected_dim {
            return Err(b.invalid(format!(
                "element {} (gmsh type {}) lies on a {} entity {}; expected a {}",
                block.tags.first().copied().unwrap_or_default(),
                block.element_type,
                dim_kind(block.entity_dim),
                block.entity_tag,
                dim_kind(expected_dim)
            )));
        }
        let lookup = |b: &Builder<'_>, element: u64, node: u64| -> Result<usize> {
            file_index.get(&node).copied().ok_or_else(|| {
                b.invalid(format!(
                    "element {element} refers to node tag {node}, which $Nodes does not define"
                ))
            })
        };
        let npe = block.nodes_per_element;
        if expected_dim == 3 {
            match tet_type {
                Some(t) if t != block.element_type => {
                    return Err(b.invalid(format!(
                        "mixed tetrahedron orders: gmsh types {t} and {} (element {}); mesh with one Mesh.ElementOrder",
                        block.element_type,
                        block.tags.first().copied().unwrap_or_default()
                    )));
                }
                _ => tet_type = Some(block.element_type),
            }
            let volume_tags: Vec<i32> = physicals.clone();
            if volume_tags.len() > 1 {
                multi_volume_entities.push(block.entity_tag);
            }
            for (k, &tag) in block.tags.iter().enumerate() {
                for &node in &block.connectivity[k * npe..(k + 1) * npe] {
                    tet_nodes_file.push(lookup(&b, tag, node)?);
                }
                tet_tags.push(tag);
                tet_groups.push(volume_tags.first().copied());
            }
        } else {
            match tri_type {
                Some(t) if t != block.element_type => {
                    return Err(b.invalid(format!(
                        "mixed triangle orders: gmsh types {t} and {} (element {})",
                        block.element_type,
                        block.tags.first().copied().unwrap_or_default()
                    )));
                }
                _ => tri_type = Some(block.element_type),
            }
            if physicals.is_empty() {
                unassigned_triangles += block.tags.len();
                continue;
            }
            for (k, &tag) in block.tags.iter().enumerate() {
                let mut local = Vec::with_capacity(npe);
                for &node in &block.connectivity[k * npe..(k + 1) * npe] {
                    local.push(lookup(&b, tag, node)?);
                }
                for &physical in physicals {
                    let entry = surface_faces.entry(physical).or_default();
                    entry.0.push(tag);
                    entry.1.extend_from_slice(&local);
                }
            }
        }
    }
    for (element_type, count) in &skipped_types {
        b.notes.push(format!(
            "{count} elements of gmsh type {element_type} ({}) skipped",
            element_type_name(*element_type)
        ));
    }
    if unassigned_triangles > 0 {
        b.notes.push(format!(
            "{unassigned_triangles} triangles on surfaces without a physical group skipped"
        ));
    }
    if !multi_volume_entities.is_empty() {
        b.notes.push(format!(
            "volume entities {multi_volume_entities:?} carry several physical volume tags; tets take the first"
        ));
    }
    let Some(tet_type) = tet_type else {
        return Err(b.invalid(
            "no tetrahedra (Tet4 or Tet10) in $Elements; mesh in 3D (gmsh -3) and put the volume in a physical group"
                .to_string(),
        ));
    };
    if let Some(tri_type) = tri_type {
        let consistent =
            (tet_type == TET4 && tri_type == TRI3) || (tet_type == TET10 && tri_type == TRI6);
        if !consistent {
            return Err(b.invalid(format!(
                "triangles of gmsh type {tri_type} do not match tetrahedra of gmsh type {tet_type} (expected Tri3 with Tet4, Tri6 with Tet10)"
            )));
        }
    }

    // Renumber: keep nodes used by tets, in file order.
    let mut new_index = vec![usize::MAX; file_tags.len()];
    for &n in &tet_nodes_file {
        new_index[n] = 0;
    }
    let mut nodes = Vec::new();
    let mut node_tags = Vec::new();
    for (i, slot) in new_index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = nodes.len();
            nodes.push(file_coords[i]);
            node_tags.push(file_tags[i]);
        }
    }
    let dropped = file_tags.len() - nodes.len();
    if dropped > 0 {
        b.notes.push(format!(
            "{dropped} nodes belong to no tetrahedron and were dropped"
        ));
    }
    let npt = if tet_type == TET4 { 4 } else { 10 };
    let tets = if npt == 4 {
        Tets::Linear(
            tet_nodes_file
                .chunks_exact(4)
                .map(|c| [0, 1, 2, 3].map(|k| new_index[c[k]]))
                .collect(),
        )
    } else {
        Tets::Quadratic(
            tet_nodes_file
                .chunks_exact(10)
                .map(|c| std::array::from_fn(|k| new_index[c[k]]))
                .collect(),
        )
    };

    // Physical groups.
    let names: HashMap<(i32, i32), &str> = raw
        .physical_names
        .iter()
        .map(|p| ((p.dim, p.tag), p.name.as_str()))
        .collect();
    let mut entity_counts: BTreeMap<(i32, i32), usize> = BTreeMap::new();
    for (&(dim, _), physicals) in &raw.entity_physicals {
        for &p in physicals {
            *entity_counts.entry((dim, p)).or_default() += 1;
        }
    }
    for p in &raw.physical_names {
        entity_counts.entry((p.dim, p.tag)).or_default();
    }
    let mut groups = Vec::new();
    for (&(dim, tag), &entity_count) in &entity_counts {
        let (name, named) = match names.get(&(dim, tag)) {
            Some(name) => (name.to_string(), true),
            None => (format!("{}_{tag}", dim_kind(dim)), false),
        };
        let element_count = match dim {
            3 => tet_groups.iter().filter(|g| **g == Some(tag)).count(),
            2 => surface_faces.get(&tag).map_or(0, |f| f.0.len()),
            _ => 0,
        };
        groups.push(PhysicalGroup {
            dim: dim as u8,
            tag,
            name,
            named,
            entity_count,
            element_count,
        });
    }
    for dim in [2u8, 3] {
        let mut seen = HashSet::new();
        for g in groups.iter().filter(|g| g.dim == dim) {
            if !seen.insert(g.name.as_str()) {
                return Err(b.invalid(format!(
                    "two {} physical groups are named \"{}\"; names must be unique per dimension",
                    dim_kind(dim as i32),
                    g.name
                )));
            }
        }
    }

    // Boundary faces: renumber, check they lie on tets, orient outward.
    let mut surface_groups = BTreeMap::new();
    let adjacency = FaceAdjacency::build(
        &tets,
        surface_faces.values().flat_map(|(_, flat)| {
            flat.chunks_exact(if npt == 4 { 3 } else { 6 })
                .map(|c| [new_index[c[0]], new_index[c[1]], new_index[c[2]]])
        }),
    );
    for (&physical, (element_tags, flat)) in &surface_faces {
        let name = groups
            .iter()
            .find(|g| g.dim == 2 && g.tag == physical)
            .map(|g| g.name.clone())
            .unwrap_or_default();
        let npf = if npt == 4 { 3 } else { 6 };
        let mut interface_faces = 0usize;
        let mut linear = Vec::new();
        let mut quadratic = Vec::new();
        for (k, chunk) in flat.chunks_exact(npf).enumerate() {
            let element = element_tags[k];
            let mut face = Vec::with_capacity(npf);
            for &n in chunk {
                let index = new_index[n];
                if index == usize::MAX {
                    return Err(b.invalid(format!(
                        "triangle {element} of surface group \"{name}\" uses node {} which belongs to no tetrahedron",
                        file_tags[n]
                    )));
                }
                face.push(index);
            }
            let corners = [face[0], face[1], face[2]];
            let Some(adjacent) = adjacency.get(corners) else {
                return Err(b.invalid(format!(
                    "triangle {element} of surface group \"{name}\" is not a face of any tetrahedron"
                )));
            };
            if adjacent.count > 1 {
                interface_faces += 1;
            }
            let flip = adjacent.count == 1 && {
                let p = corners.map(|c| nodes[c]);
                let normal = geometry::triangle_normal(p);
                geometry::dot(normal, geometry::sub(nodes[adjacent.opposite_node], p[0])) > 0.0
            };
            if npf == 3 {
                linear.push(if flip {
                    [corners[0], corners[2], corners[1]]
                } else {
                    corners
                });
            } else {
                let face6: [usize; 6] = std::array::from_fn(|i| face[i]);
                check_midside_nodes(&b, &tets, adjacent.tet, &face6, element, &name)?;
                quadratic.push(if flip { flip_tri6(face6) } else { face6 });
            }
        }
        if interface_faces > 0 {
            b.notes.push(format!(
                "surface group \"{name}\": {interface_faces} triangles lie between two tetrahedra (internal interface); gmsh orientation kept"
            ));
        }
        let faces = if npf == 3 {
            Faces::Linear(linear)
        } else {
            Faces::Quadratic(quadratic)
        };
        surface_groups.insert(name, faces);
    }

    // Periodic node pairs.
    let mut periodic_node_pairs = Vec::new();
    let mut outside_pairs = 0usize;
    for link in &raw.periodic {
        for &(slave, master) in &link.node_pairs {
            let find = |tag: u64| {
                file_index.get(&tag).copied().ok_or_else(|| {
                    b.invalid(format!(
                        "$Periodic link of {} entity {} (master {}) refers to node tag {tag}, which $Nodes does not define",
                        dim_kind(link.entity_dim),
                        link.entity_tag,
                        link.master_tag
                    ))
                })
            };
            let (s, m) = (new_index[find(slave)?], new_index[find(master)?]);
            if s == usize::MAX || m == usize::MAX {
                outside_pairs += 1;
            } else {
                periodic_node_pairs.push([s, m]);
            }
        }
    }
    periodic_node_pairs.sort_unstable();
    periodic_node_pairs.dedup();
    if outside_pairs > 0 {
        b.notes.push(format!(
            "{outside_pairs} periodic node pairs involve nodes of no tetrahedron and were skipped"
        ));
    }

    Ok(TetMesh {
        source: file.to_string(),
        nodes,
        node_tags,
        tets,
        tet_tags,
        tet_groups,
        surface_groups,
        groups,
        periodic_node_pairs,
        binary: raw.binary,
        notes: b.notes,
    })
}

/// Check that a Tri6's midside nodes are the adjacent Tet10's midside nodes on the same edges.
fn check_midside_nodes(
    b: &Builder<'_>,
    tets: &Tets,
    tet: usize,
    face: &[usize; 6],
    element: u64,
    group: &str,
) -> Result<()> {
    let tet_nodes = tets.nodes(tet);
    let local = |global: usize| tet_nodes[..4].iter().position(|&n| n == global);
    for (e, [i, j]) in [[0, 1], [1, 2], [2, 0]].iter().enumerate() {
        let expected = match (local(face[*i]), local(face[*j])) {
            (Some(a), Some(c)) => tet10_edge_node(a, c).map(|k| tet_nodes[k]),
            _ => None,
        };
        if expected != Some(face[3 + e]) {
            return Err(b.invalid(format!(
                "midside node {} of triangle {element} (surface group \"{group}\") is not the midside node of the adjacent tetrahedron's edge",
                3 + e
            )));
        }
    }
    Ok(())
}

/// For each boundary triangle (by sorted corners): one adjacent tet, its corner opposite the
/// face, and how many tets share the face.
struct FaceAdjacency {
    map: HashMap<[usize; 3], Adjacent>,
}

#[derive(Clone, Copy)]
struct Adjacent {
    tet: usize,
    opposite_node: usize,
    count: usize,
}

impl FaceAdjacency {
    fn build(tets: &Tets, faces: impl Iterator<Item = [usize; 3]>) -> Self {
        let mut map: HashMap<[usize; 3], Adjacent> = HashMap::new();
        for corners in faces {
            map.insert(
                sorted(corners),
                Adjacent {
                    tet: usize::MAX,
                    opposite_node: usize::MAX,
                    count: 0,
                },
            );
        }
        if !map.is_empty() {
            const TET_FACES: [([usize; 3], usize); 4] = [
                ([1, 2, 3], 0),
                ([0, 2, 3], 1),
                ([0, 1, 3], 2),
                ([0, 1, 2], 3),
            ];
            for t in 0..tets.len() {
                let c = tets.corners(t);
                for (face, opposite) in TET_FACES {
                    if let Some(entry) = map.get_mut(&sorted(face.map(|k| c[k]))) {
                        if entry.count == 0 {
                            entry.tet = t;
                            entry.opposite_node = c[opposite];
                        }
                        entry.count += 1;
                    }
                }
            }
        }
        FaceAdjacency { map }
    }

    fn get(&self, corners: [usize; 3]) -> Option<Adjacent> {
        self.map
            .get(&sorted(corners))
            .copied()
            .filter(|a| a.count > 0)
    }
}

fn sorted(mut k: [usize; 3]) -> [usize; 3] {
    k.sort_unstable();
    k
}
