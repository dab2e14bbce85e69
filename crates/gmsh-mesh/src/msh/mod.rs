//! MSH 4.1 file parsing (ASCII and binary) into raw blocks; no mesh semantics here.

mod content;
mod cursor;
pub(crate) mod element_types;
mod sections;

pub(crate) use content::{
    EntityPhysicals, RawElementBlock, RawNodeBlock, RawPeriodicLink, RawPhysicalName,
};
pub(crate) use cursor::Source;
pub(crate) use sections::SUPPORTED_VERSION;

use crate::error::{MeshError, Result};
use cursor::{Cursor, Encoding};

/// Everything the reader takes from an MSH 4.1 file.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawMsh {
    pub binary: bool,
    pub physical_names: Vec<RawPhysicalName>,
    pub entity_physicals: EntityPhysicals,
    pub declared_node_count: usize,
    pub node_blocks: Vec<RawNodeBlock>,
    pub declared_element_count: usize,
    pub element_blocks: Vec<RawElementBlock>,
    pub periodic: Vec<RawPeriodicLink>,
    /// Sections present but not read (post-processing data, partitions, ...).
    pub skipped_sections: Vec<String>,
}

/// Parse the bytes of an MSH 4.1 file. `source.name` is used in error messages only.
pub(crate) fn parse(source: Source<'_>) -> Result<RawMsh> {
    let sections = sections::scan_sections(source)?;
    // The version is checked before the order so that an MSH 2.2 file is reported as such.
    if let Some(first) = sections.first().filter(|s| s.name == "MeshFormat") {
        sections::parse_mesh_format(source, first)?;
    }
    sections::check_section_order(source, &sections)?;
    let format = sections::parse_mesh_format(source, &sections[0])?;

    let mut raw = RawMsh {
        binary: matches!(format.encoding, Encoding::Binary { .. }),
        physical_names: Vec::new(),
        entity_physicals: EntityPhysicals::new(),
        declared_node_count: 0,
        node_blocks: Vec::new(),
        declared_element_count: 0,
        element_blocks: Vec::new(),
        periodic: Vec::new(),
        skipped_sections: Vec::new(),
    };
    for section in &sections[1..] {
        let (name, encoding): (&'static str, Encoding) = match section.name.as_str() {
            "PhysicalNames" => ("PhysicalNames", Encoding::Ascii),
            "Entities" => ("Entities", format.encoding),
            "Nodes" => ("Nodes", format.encoding),
            "Elements" => ("Elements", format.encoding),
            "Periodic" => ("Periodic", format.encoding),
            other => {
                raw.skipped_sections.push(other.to_string());
                continue;
            }
        };
        let mut cursor = Cursor::new(
            source,
            name,
            encoding,
            section.content_start,
            section.content_end,
        );
        match name {
            "PhysicalNames" => raw.physical_names = content::parse_physical_names(&mut cursor)?,
            "Entities" => raw.entity_physicals = content::parse_entities(&mut cursor)?,
            "Nodes" => {
                (raw.declared_node_count, raw.node_blocks) = content::parse_nodes(&mut cursor)?
            }
            "Elements" => {
                (raw.declared_element_count, raw.element_blocks) =
                    content::parse_elements(&mut cursor)?
            }
            _ => raw.periodic = content::parse_periodic(&mut cursor)?,
        }
    }
    check_declared_counts(source, &raw)?;
    Ok(raw)
}

fn check_declared_counts(source: Source<'_>, raw: &RawMsh) -> Result<()> {
    let nodes: usize = raw.node_blocks.iter().map(|b| b.tags.len()).sum();
    let elements: usize = raw.element_blocks.iter().map(|b| b.tags.len()).sum();
    let invalid = |detail: String| MeshError::Invalid {
        file: source.name.to_string(),
        detail,
    };
    if nodes != raw.declared_node_count {
        return Err(invalid(format!(
            "$Nodes header declares {} nodes but its blocks hold {nodes}",
            raw.declared_node_count
        )));
    }
    if elements != raw.declared_element_count {
        return Err(invalid(format!(
            "$Elements header declares {} elements but its blocks hold {elements}",
            raw.declared_element_count
        )));
    }
    Ok(())
}
