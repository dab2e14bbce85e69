//! Parsers for the content of the MSH 4.1 sections this crate uses: `$PhysicalNames`,
//! `$Entities`, `$Nodes`, `$Elements`, `$Periodic`. Layouts follow the gmsh reference manual,
//! section "MSH file format" (version 4.1).

use std::collections::HashMap;

use super::cursor::Cursor;
use super::element_types::nodes_per_element;

/// A `$PhysicalNames` entry.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawPhysicalName {
    pub dim: i32,
    pub tag: i32,
    pub name: String,
}

/// Geometric entities: (dim, tag) -> physical tags.
pub(crate) type EntityPhysicals = HashMap<(i32, i32), Vec<i32>>;

/// One block of nodes (all on one geometric entity).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawNodeBlock {
    pub tags: Vec<u64>,
    pub coords: Vec<[f64; 3]>,
}

/// One block of elements of one type on one entity; `connectivity` holds
/// `tags.len() * nodes_per_element` node tags.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawElementBlock {
    pub entity_dim: i32,
    pub entity_tag: i32,
    pub element_type: i32,
    pub nodes_per_element: usize,
    pub tags: Vec<u64>,
    pub connectivity: Vec<u64>,
}

/// A `$Periodic` link: node tags of the slave entity with their master node tags.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawPeriodicLink {
    pub entity_dim: i32,
    pub entity_tag: i32,
    pub master_tag: i32,
    pub node_pairs: Vec<(u64, u64)>,
}

/// Longest physical name accepted by gmsh (its `$PhysicalNames` limit is 127 characters).
const MAX_PHYSICAL_NAME_CHARS: usize = 256;

/// `$PhysicalNames` (always ASCII): count, then lines `dim tag "name"`.
pub(crate) fn parse_physical_names(
    cursor: &mut Cursor<'_>,
) -> crate::error::Result<Vec<RawPhysicalName>> {
    // Smallest entry: `0 1 ""` plus a newline.
    let count_offset = cursor.pos;
    let count: u64 = cursor.ascii("number of physical names")?;
    let count = cursor.check_count(count_offset, count, "number of physical names", 7)?;
    let mut names = Vec::with_capacity(count);
    for index in 0..count {
        let what = |field: &str| format!("{field} of physical name {} of {count}", index + 1);
        let dim: i32 = cursor.ascii(|| what("dimension"))?;
        if !(0..=3).contains(&dim) {
            return Err(cursor.syntax_at(cursor.pos, what("dimension 0..3"), dim.to_string()));
        }
        let tag: i32 = cursor.ascii(|| what("tag"))?;
        let name = quoted_string(cursor, &what("quoted name"))?;
        names.push(RawPhysicalName { dim, tag, name });
    }
    cursor.finish()?;
    Ok(names)
}

fn quoted_string(cursor: &mut Cursor<'_>, expected: &str) -> crate::error::Result<String> {
    let bytes = cursor.source.bytes;
    while cursor.pos < cursor.end && (bytes[cursor.pos] == b' ' || bytes[cursor.pos] == b'\t') {
        cursor.pos += 1;
    }
    if cursor.pos >= cursor.end {
        return Err(cursor.truncated(expected));
    }
    let open = cursor.pos;
    if bytes[open] != b'"' {
        return Err(cursor.syntax_at(
            open,
            expected,
            super::cursor::describe_bytes(&bytes[open..cursor.end.min(open + 20)]),
        ));
    }
    let close = bytes[open + 1..cursor.end]
        .iter()
        .position(|&b| b == b'"' || b == b'\n')
        .map(|i| open + 1 + i);
    match close {
        Some(close) if bytes[close] == b'"' && close - open - 1 <= MAX_PHYSICAL_NAME_CHARS => {
            cursor.pos = close + 1;
            String::from_utf8(bytes[open + 1..close].to_vec())
                .map_err(|_| cursor.syntax_at(open, expected, "a name that is not UTF-8"))
        }
        Some(close) if bytes[close] == b'"' => {
            Err(cursor.syntax_at(open, expected, "a name longer than 256 bytes"))
        }
        _ => Err(cursor.syntax_at(open, expected, "an unterminated quoted name")),
    }
}

/// `$Entities`: points, curves, surfaces, volumes with their physical tags.
pub(crate) fn parse_entities(cursor: &mut Cursor<'_>) -> crate::error::Result<EntityPhysicals> {
    // A point: tag, 3 doubles, a count; a curve/surface/volume additionally 3 doubles and a count.
    let min_point =
        cursor.min_int_bytes() + 3 * cursor.min_double_bytes() + cursor.min_size_t_bytes();
    let min_other = min_point + 3 * cursor.min_double_bytes() + cursor.min_size_t_bytes();
    let mut counts = [0usize; 4];
    let kinds = ["points", "curves", "surfaces", "volumes"];
    let mut total_min_bytes: usize = 0;
    for dim in 0..4 {
        let min_item = if dim == 0 { min_point } else { min_other };
        counts[dim] = cursor.count(|| format!("number of {}", kinds[dim]), min_item)?;
        total_min_bytes = total_min_bytes.saturating_add(counts[dim].saturating_mul(min_item));
    }
    cursor.check_count(cursor.pos, total_min_bytes as u64, "entities", 1)?;
    let mut physicals = EntityPhysicals::new();
    for (dim, &count) in counts.iter().enumerate() {
        let singular = &kinds[dim][..kinds[dim].len() - 1];
        for index in 0..count {
            let what = |field: &str| format!("{field} of {singular} {} of {count}", index + 1);
            let tag = cursor.int(|| what("tag"))?;
            let coordinate_count = if dim == 0 { 3 } else { 6 };
            for _ in 0..coordinate_count {
                cursor.double(|| what("bounding-box coordinate"))?;
            }
            let physical_count =
                cursor.count(|| what("number of physical tags"), cursor.min_int_bytes())?;
            let mut tags = Vec::with_capacity(physical_count);
            for _ in 0..physical_count {
                tags.push(cursor.int(|| what("physical tag"))?);
            }
            if dim > 0 {
                let bounding_count = cursor.count(
                    || what("number of bounding entities"),
                    cursor.min_int_bytes(),
                )?;
                for _ in 0..bounding_count {
                    cursor.int(|| what("bounding entity tag"))?;
                }
            }
            if physicals.insert((dim as i32, tag), tags).is_some() {
                return Err(cursor.syntax_at(
                    cursor.pos,
                    what("a tag not used before"),
                    format!("duplicate {singular} tag {tag}"),
                ));
            }
        }
    }
    cursor.finish()?;
    Ok(physicals)
}

/// `$Nodes`: node blocks with tags and coordinates (parametric coordinates are skipped).
pub(crate) fn parse_nodes(
    cursor: &mut Cursor<'_>,
) -> crate::error::Result<(usize, Vec<RawNodeBlock>)> {
    let min_block_header = 3 * cursor.min_int_bytes() + cursor.min_size_t_bytes();
    let min_node = cursor.min_size_t_bytes() + 3 * cursor.min_double_bytes();
    let block_count = cursor.count("number of node entity blocks", min_block_header)?;
    let declared_nodes = cursor.count("number of nodes", min_node)?;
    cursor.size_t("minimum node tag")?;
    cursor.size_t("maximum node tag")?;
    let mut blocks = Vec::with_capacity(block_count);
    for block_index in 0..block_count {
        let what =
            |field: &str| format!("{field} of node block {} of {block_count}", block_index + 1);
        let entity_dim = cursor.int(|| what("entity dimension"))?;
        if !(0..=3).contains(&entity_dim) {
            return Err(cursor.syntax_at(
                cursor.pos,
                what("entity dimension 0..3"),
                entity_dim.to_string(),
            ));
        }
        cursor.int(|| what("entity tag"))?;
        let parametric_offset = cursor.pos;
        let parametric = cursor.int(|| what("parametric flag"))?;
        let parameter_count = match parametric {
            0 => 0,
            1 => entity_dim as usize,
            other => {
                return Err(cursor.syntax_at(
                    parametric_offset,
                    what("parametric flag 0 or 1"),
                    other.to_string(),
                ));
            }
        };
        let node_min = min_node + parameter_count * cursor.min_double_bytes();
        let count = cursor.count(|| what("number of nodes"), node_min)?;
        let mut tags = Vec::with_capacity(count);
        for index in 0..count {
            tags.push(cursor.size_t(|| {
                format!(
                    "tag of node {} in node block {}",
                    index + 1,
                    block_index + 1
                )
            })?);
        }
        let mut coords = Vec::with_capacity(count);
        for &tag in &tags {
            let x = cursor.double(|| format!("x coordinate of node {tag}"))?;
            let y = cursor.double(|| format!("y coordinate of node {tag}"))?;
            let z = cursor.double(|| format!("z coordinate of node {tag}"))?;
            for _ in 0..parameter_count {
                cursor.double(|| format!("parametric coordinate of node {tag}"))?;
            }
            coords.push([x, y, z]);
        }
        blocks.push(RawNodeBlock { tags, coords });
    }
    cursor.finish()?;
    Ok((declared_nodes, blocks))
}

/// `$Elements`: element blocks with tags and node tags.
pub(crate) fn parse_elements(
    cursor: &mut Cursor<'_>,
) -> crate::error::Result<(usize, Vec<RawElementBlock>)> {
    let min_block_header = 3 * cursor.min_int_bytes() + cursor.min_size_t_bytes();
    let block_count = cursor.count("number of element entity blocks", min_block_header)?;
    let declared = cursor.count("number of elements", 2 * cursor.min_size_t_bytes())?;
    cursor.size_t("minimum element tag")?;
    cursor.size_t("maximum element tag")?;
    let mut blocks = Vec::with_capacity(block_count);
    for block_index in 0..block_count {
        let what = |field: &str| {
            format!(
                "{field} of element block {} of {block_count}",
                block_index + 1
            )
        };
        let entity_dim = cursor.int(|| what("entity dimension"))?;
        if !(0..=3).contains(&entity_dim) {
            return Err(cursor.syntax_at(
                cursor.pos,
                what("entity dimension 0..3"),
                entity_dim.to_string(),
            ));
        }
        let entity_tag = cursor.int(|| what("entity tag"))?;
        let type_offset = cursor.pos;
        let element_type = cursor.int(|| what("element type"))?;
        let Some(nodes_per_element) = nodes_per_element(element_type) else {
            return Err(cursor.syntax_at(
                type_offset,
                what("a gmsh element type this reader knows (1-31, 92, 93)"),
                format!("element type {element_type}"),
            ));
        };
        let min_element = (1 + nodes_per_element) * cursor.min_size_t_bytes();
        let count = cursor.count(|| what("number of elements"), min_element)?;
        let mut tags = Vec::with_capacity(count);
        let mut connectivity = Vec::with_capacity(count * nodes_per_element);
        for index in 0..count {
            let tag = cursor.size_t(|| {
                format!(
                    "tag of element {} in element block {}",
                    index + 1,
                    block_index + 1
                )
            })?;
            tags.push(tag);
            for local in 0..nodes_per_element {
                connectivity
                    .push(cursor.size_t(|| format!("node {} of element {tag}", local + 1))?);
            }
        }
        blocks.push(RawElementBlock {
            entity_dim,
            entity_tag,
            element_type,
            nodes_per_element,
            tags,
            connectivity,
        });
    }
    cursor.finish()?;
    Ok((declared, blocks))
}

/// `$Periodic`: links between slave and master entities with their node correspondences.
pub(crate) fn parse_periodic(
    cursor: &mut Cursor<'_>,
) -> crate::error::Result<Vec<RawPeriodicLink>> {
    let min_link = 3 * cursor.min_int_bytes() + 2 * cursor.min_size_t_bytes();
    let link_count = cursor.count("number of periodic links", min_link)?;
    let mut links = Vec::with_capacity(link_count);
    for link_index in 0..link_count {
        let what = |field: &str| {
            format!(
                "{field} of periodic link {} of {link_count}",
                link_index + 1
            )
        };
        let entity_dim = cursor.int(|| what("entity dimension"))?;
        let entity_tag = cursor.int(|| what("entity tag"))?;
        let master_tag = cursor.int(|| what("master entity tag"))?;
        let affine_count = cursor.count(
            || what("number of affine values"),
            cursor.min_double_bytes(),
        )?;
        for _ in 0..affine_count {
            cursor.double(|| what("affine transform value"))?;
        }
        let pair_count = cursor.count(
            || what("number of node pairs"),
            2 * cursor.min_size_t_bytes(),
        )?;
        let mut node_pairs = Vec::with_capacity(pair_count);
        for _ in 0..pair_count {
            let slave = cursor.size_t(|| what("slave node tag"))?;
            let master = cursor.size_t(|| what("master node tag"))?;
            node_pairs.push((slave, master));
        }
        links.push(RawPeriodicLink {
            entity_dim,
            entity_tag,
            master_tag,
            node_pairs,
        });
    }
    cursor.finish()?;
    Ok(links)
}
