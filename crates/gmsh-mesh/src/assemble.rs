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

/// Build the mesh, stage by stage: nodes, elements, renumbering, physical groups, boundary
/// faces, periodic pairs. Quality is not checked here (see `crate::read`).
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
    let file_nodes = FileNodes::read(&b, &raw)?;
    let mut elements = Elements::default();
    for block in &raw.element_blocks {
        elements.add_block(&b, &raw, block, &file_nodes)?;
    }
    let tet_type = elements.check_types(&mut b)?;
    let numbered = Renumbered::new(&mut b, &file_nodes, &elements, tet_type);
    let groups = physical_groups(&b, &raw, &elements)?;
    let surface_groups = boundary_faces(&mut b, &file_nodes, &elements, &numbered, &groups)?;
    let periodic_node_pairs = periodic_pairs(&mut b, &raw, &file_nodes, &numbered.new_index)?;
    Ok(TetMesh {
        source: file.to_string(),
        nodes: numbered.nodes,
        node_tags: numbered.node_tags,
        tets: numbered.tets,
        tet_tags: elements.tet_tags,
        tet_groups: elements.tet_groups,
        surface_groups,
        groups,
        periodic_node_pairs,
        binary: raw.binary,
        notes: b.notes,
    })
}

/// The `$Nodes` section: tag → position in file order, tags and coordinates.
struct FileNodes {
    index: HashMap<u64, usize>,
    tags: Vec<u64>,
    coords: Vec<[f64; 3]>,
}

impl FileNodes {
    /// Every node in file order; a non-finite coordinate or a repeated tag is refused.
    fn read(b: &Builder<'_>, raw: &RawMsh) -> Result<Self> {
        let total_nodes: usize = raw.node_blocks.iter().map(|blk| blk.tags.len()).sum();
        let mut nodes = FileNodes {
            index: HashMap::with_capacity(total_nodes),
            tags: Vec::with_capacity(total_nodes),
            coords: Vec::with_capacity(total_nodes),
        };
        for block in &raw.node_blocks {
            for (&tag, &xyz) in block.tags.iter().zip(&block.coords) {
                if !xyz.iter().all(|c| c.is_finite()) {
                    return Err(
                        b.invalid(format!("node {tag} has a non-finite coordinate {xyz:?}"))
                    );
                }
                if nodes.index.insert(tag, nodes.tags.len()).is_some() {
                    return Err(b.invalid(format!("node tag {tag} appears twice in $Nodes")));
                }
                nodes.tags.push(tag);
                nodes.coords.push(xyz);
            }
        }
        Ok(nodes)
    }

    /// The file index of node `node` of element `element`.
    fn lookup(&self, b: &Builder<'_>, element: u64, node: u64) -> Result<usize> {
        self.index.get(&node).copied().ok_or_else(|| {
            b.invalid(format!(
                "element {element} refers to node tag {node}, which $Nodes does not define"
            ))
        })
    }
}

/// The `$Elements` section: the tetrahedra (file node indices), the triangles of each physical
/// surface, and what was skipped.
#[derive(Default)]
struct Elements {
    seen_tags: HashSet<u64>,
    tet_type: Option<i32>,
    tet_tags: Vec<u64>,
    /// Flat, file node indices.
    tet_nodes_file: Vec<usize>,
    tet_groups: Vec<Option<i32>>,
    /// (physical surface tag) -> (element tags, flat file node indices)
    surface_faces: BTreeMap<i32, (Vec<u64>, Vec<usize>)>,
    tri_type: Option<i32>,
    skipped_types: BTreeMap<i32, usize>,
    unassigned_triangles: usize,
    multi_volume_entities: Vec<i32>,
}

impl Elements {
    /// One element block: tetrahedra and triangles kept, other types counted and skipped.
    fn add_block(
        &mut self,
        b: &Builder<'_>,
        raw: &RawMsh,
        block: &crate::msh::RawElementBlock,
        nodes: &FileNodes,
    ) -> Result<()> {
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
            if !self.seen_tags.insert(tag) {
                return Err(b.invalid(format!("element tag {tag} appears twice in $Elements")));
            }
        }
        let expected_dim = match block.element_type {
            TET4 | TET10 => 3,
            TRI3 | TRI6 => 2,
            _ => {
                *self.skipped_types.entry(block.element_type).or_default() += block.tags.len();
                return Ok(());
            }
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
        if expected_dim == 3 {
            self.add_tets(b, block, physicals, nodes)
        } else {
            self.add_triangles(b, block, physicals, nodes)
        }
    }

    /// A block of tetrahedra (one order per mesh), in the first physical volume of its entity.
    fn add_tets(
        &mut self,
        b: &Builder<'_>,
        block: &crate::msh::RawElementBlock,
        physicals: &[i32],
        nodes: &FileNodes,
    ) -> Result<()> {
        match self.tet_type {
            Some(t) if t != block.element_type => {
                return Err(b.invalid(format!(
                    "mixed tetrahedron orders: gmsh types {t} and {} (element {}); mesh with one Mesh.ElementOrder",
                    block.element_type,
                    block.tags.first().copied().unwrap_or_default()
                )));
            }
            _ => self.tet_type = Some(block.element_type),
        }
        if physicals.len() > 1 {
            self.multi_volume_entities.push(block.entity_tag);
        }
        let npe = block.nodes_per_element;
        for (k, &tag) in block.tags.iter().enumerate() {
            for &node in &block.connectivity[k * npe..(k + 1) * npe] {
                self.tet_nodes_file.push(nodes.lookup(b, tag, node)?);
            }
            self.tet_tags.push(tag);
            self.tet_groups.push(physicals.first().copied());
        }
        Ok(())
    }

    /// A block of triangles (one order per mesh), in every physical surface of its entity;
    /// triangles of no physical surface are counted and skipped.
    fn add_triangles(
        &mut self,
        b: &Builder<'_>,
        block: &crate::msh::RawElementBlock,
        physicals: &[i32],
        nodes: &FileNodes,
    ) -> Result<()> {
        match self.tri_type {
            Some(t) if t != block.element_type => {
                return Err(b.invalid(format!(
                    "mixed triangle orders: gmsh types {t} and {} (element {})",
                    block.element_type,
                    block.tags.first().copied().unwrap_or_default()
                )));
            }
            _ => self.tri_type = Some(block.element_type),
        }
        if physicals.is_empty() {
            self.unassigned_triangles += block.tags.len();
            return Ok(());
        }
        let npe = block.nodes_per_element;
        for (k, &tag) in block.tags.iter().enumerate() {
            let mut local = Vec::with_capacity(npe);
            for &node in &block.connectivity[k * npe..(k + 1) * npe] {
                local.push(nodes.lookup(b, tag, node)?);
            }
            for &physical in physicals {
                let entry = self.surface_faces.entry(physical).or_default();
                entry.0.push(tag);
                entry.1.extend_from_slice(&local);
            }
        }
        Ok(())
    }

    /// Notes on what was skipped; the tetrahedron type (some are needed), and triangles of
    /// the matching order.
    fn check_types(&self, b: &mut Builder<'_>) -> Result<i32> {
        for (element_type, count) in &self.skipped_types {
            b.notes.push(format!(
                "{count} elements of gmsh type {element_type} ({}) skipped",
                element_type_name(*element_type)
            ));
        }
        if self.unassigned_triangles > 0 {
            b.notes.push(format!(
                "{} triangles on surfaces without a physical group skipped",
                self.unassigned_triangles
            ));
        }
        if !self.multi_volume_entities.is_empty() {
            b.notes.push(format!(
                "volume entities {:?} carry several physical volume tags; tets take the first",
                self.multi_volume_entities
            ));
        }
        let Some(tet_type) = self.tet_type else {
            return Err(b.invalid(
                "no tetrahedra (Tet4 or Tet10) in $Elements; mesh in 3D (gmsh -3) and put the volume in a physical group"
                    .to_string(),
            ));
        };
        if let Some(tri_type) = self.tri_type {
            let consistent =
                (tet_type == TET4 && tri_type == TRI3) || (tet_type == TET10 && tri_type == TRI6);
            if !consistent {
                return Err(b.invalid(format!(
                    "triangles of gmsh type {tri_type} do not match tetrahedra of gmsh type {tet_type} (expected Tri3 with Tet4, Tri6 with Tet10)"
                )));
            }
        }
        Ok(tet_type)
    }
}

/// The nodes the tetrahedra use, renumbered in file order, and the tetrahedra on them.
struct Renumbered {
    /// File index → new index (`usize::MAX`: dropped).
    new_index: Vec<usize>,
    nodes: Vec<[f64; 3]>,
    node_tags: Vec<u64>,
    tets: Tets,
    /// Nodes per tetrahedron (4 or 10).
    npt: usize,
}

impl Renumbered {
    fn new(b: &mut Builder<'_>, file: &FileNodes, elements: &Elements, tet_type: i32) -> Self {
        let mut new_index = vec![usize::MAX; file.tags.len()];
        for &n in &elements.tet_nodes_file {
            new_index[n] = 0;
        }
        let mut nodes = Vec::new();
        let mut node_tags = Vec::new();
        for (i, slot) in new_index.iter_mut().enumerate() {
            if *slot == 0 {
                *slot = nodes.len();
                nodes.push(file.coords[i]);
                node_tags.push(file.tags[i]);
            }
        }
        let dropped = file.tags.len() - nodes.len();
        if dropped > 0 {
            b.notes.push(format!(
                "{dropped} nodes belong to no tetrahedron and were dropped"
            ));
        }
        let npt = if tet_type == TET4 { 4 } else { 10 };
        let flat = &elements.tet_nodes_file;
        let tets = if npt == 4 {
            Tets::Linear(
                flat.chunks_exact(4)
                    .map(|c| [0, 1, 2, 3].map(|k| new_index[c[k]]))
                    .collect(),
            )
        } else {
            Tets::Quadratic(
                flat.chunks_exact(10)
                    .map(|c| std::array::from_fn(|k| new_index[c[k]]))
                    .collect(),
            )
        };
        Renumbered {
            new_index,
            nodes,
            node_tags,
            tets,
            npt,
        }
    }
}

/// Every physical group of `$PhysicalNames` or `$Entities` with its entity and element
/// counts; names are unique per dimension.
fn physical_groups(
    b: &Builder<'_>,
    raw: &RawMsh,
    elements: &Elements,
) -> Result<Vec<PhysicalGroup>> {
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
            3 => elements
                .tet_groups
                .iter()
                .filter(|g| **g == Some(tag))
                .count(),
            2 => elements.surface_faces.get(&tag).map_or(0, |f| f.0.len()),
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
    Ok(groups)
}

/// Boundary faces of every physical surface: renumbered, each a face of a tetrahedron,
/// oriented outward (faces between two tetrahedra keep gmsh's orientation, with a note).
fn boundary_faces(
    b: &mut Builder<'_>,
    file: &FileNodes,
    elements: &Elements,
    numbered: &Renumbered,
    groups: &[PhysicalGroup],
) -> Result<BTreeMap<String, Faces>> {
    let npf = if numbered.npt == 4 { 3 } else { 6 };
    let new_index = &numbered.new_index;
    let adjacency = FaceAdjacency::build(
        &numbered.tets,
        elements.surface_faces.values().flat_map(|(_, flat)| {
            flat.chunks_exact(npf)
                .map(|c| [new_index[c[0]], new_index[c[1]], new_index[c[2]]])
        }),
    );
    let mut surface_groups = BTreeMap::new();
    for (&physical, (element_tags, flat)) in &elements.surface_faces {
        let name = groups
            .iter()
            .find(|g| g.dim == 2 && g.tag == physical)
            .map(|g| g.name.clone())
            .unwrap_or_default();
        let surface = SurfaceFaces {
            name: &name,
            element_tags,
            flat,
            npf,
        };
        let (faces, interface_faces) = surface.oriented(b, file, numbered, &adjacency)?;
        if interface_faces > 0 {
            b.notes.push(format!(
                "surface group \"{name}\": {interface_faces} triangles lie between two tetrahedra (internal interface); gmsh orientation kept"
            ));
        }
        surface_groups.insert(name, faces);
    }
    Ok(surface_groups)
}

/// The triangles of one physical surface as read (file node indices).
struct SurfaceFaces<'a> {
    name: &'a str,
    element_tags: &'a [u64],
    flat: &'a [usize],
    /// Nodes per face (3 or 6).
    npf: usize,
}

impl SurfaceFaces<'_> {
    /// The faces renumbered and oriented outward, and how many lie between two tetrahedra.
    fn oriented(
        &self,
        b: &Builder<'_>,
        file: &FileNodes,
        numbered: &Renumbered,
        adjacency: &FaceAdjacency,
    ) -> Result<(Faces, usize)> {
        let (name, npf) = (self.name, self.npf);
        let mut interface_faces = 0usize;
        let mut linear = Vec::new();
        let mut quadratic = Vec::new();
        for (k, chunk) in self.flat.chunks_exact(npf).enumerate() {
            let element = self.element_tags[k];
            let mut face = Vec::with_capacity(npf);
            for &n in chunk {
                let index = numbered.new_index[n];
                if index == usize::MAX {
                    return Err(b.invalid(format!(
                        "triangle {element} of surface group \"{name}\" uses node {} which belongs to no tetrahedron",
                        file.tags[n]
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
                let p = corners.map(|c| numbered.nodes[c]);
                let normal = geometry::triangle_normal(p);
                let inward = geometry::sub(numbered.nodes[adjacent.opposite_node], p[0]);
                geometry::dot(normal, inward) > 0.0
            };
            if npf == 3 {
                linear.push(if flip {
                    [corners[0], corners[2], corners[1]]
                } else {
                    corners
                });
            } else {
                let face6: [usize; 6] = std::array::from_fn(|i| face[i]);
                check_midside_nodes(b, &numbered.tets, adjacent.tet, &face6, element, name)?;
                quadratic.push(if flip { flip_tri6(face6) } else { face6 });
            }
        }
        let faces = if npf == 3 {
            Faces::Linear(linear)
        } else {
            Faces::Quadratic(quadratic)
        };
        Ok((faces, interface_faces))
    }
}

/// `$Periodic` node pairs (slave, master) in the new numbering, sorted and deduplicated;
/// pairs with a node of no tetrahedron are skipped with a note.
fn periodic_pairs(
    b: &mut Builder<'_>,
    raw: &RawMsh,
    file: &FileNodes,
    new_index: &[usize],
) -> Result<Vec<[usize; 2]>> {
    let mut periodic_node_pairs = Vec::new();
    let mut outside_pairs = 0usize;
    for link in &raw.periodic {
        for &(slave, master) in &link.node_pairs {
            let find = |tag: u64| {
                file.index.get(&tag).copied().ok_or_else(|| {
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
    Ok(periodic_node_pairs)
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
