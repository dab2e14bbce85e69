//! Splitting an MSH file into `$Name ... $EndName` sections, the `$MeshFormat` header and the
//! section-order rules of MSH 4.1.

use super::cursor::{Encoding, Source, describe_bytes};
use crate::error::{MeshError, Result};

/// One `$Name ... $EndName` section.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Section {
    /// Name without `$`.
    pub name: String,
    /// Offset of the `$` of the opening tag.
    pub tag_offset: usize,
    /// First byte after the opening tag's line.
    pub content_start: usize,
    /// Offset of the `$` of the closing tag (content ends here).
    pub content_end: usize,
}

/// Longest section name accepted (gmsh's longest is `ElementNodeData`).
const MAX_SECTION_NAME_BYTES: usize = 64;

/// The name of the section tag `$Name` at `pos` (its line ends at `line_end`): letters, digits
/// and `_`, at most [`MAX_SECTION_NAME_BYTES`], not a closing tag.
fn tag_name(source: Source<'_>, pos: usize, line_end: usize) -> Result<String> {
    let bytes = source.bytes;
    let tag_offset = pos;
    let name_bytes = trim_ascii(&bytes[pos + 1..line_end]);
    let name = match std::str::from_utf8(name_bytes) {
        Ok(name)
            if !name.is_empty()
                && name.len() <= MAX_SECTION_NAME_BYTES
                && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_') =>
        {
            name.to_string()
        }
        _ => {
            return Err(source.syntax(
                "",
                tag_offset,
                "a section tag \"$Name\" on a line of its own",
                describe_bytes(&bytes[pos..line_end.min(pos + MAX_SECTION_NAME_BYTES)]),
            ));
        }
    };
    if let Some(opened) = name.strip_prefix("End") {
        return Err(source.syntax(
            "",
            tag_offset,
            "a section opening tag",
            format!("closing tag \"$End{opened}\" without a matching \"${opened}\""),
        ));
    }
    Ok(name)
}

/// Where the section `name` opened on the line ending at `line_end` closes: the end of its
/// content (the `$End{name}` line's start) and the end of the closing tag's line, which must
/// hold nothing else.
fn section_end(source: Source<'_>, name: &str, line_end: usize) -> Result<(usize, usize)> {
    let bytes = source.bytes;
    let closing = format!("\n$End{name}");
    let content_end = match find(&bytes[line_end..], closing.as_bytes()) {
        Some(i) => line_end + i + 1,
        None => {
            return Err(source.truncated(
                name,
                bytes.len(),
                format!("\"$End{name}\" closing the section"),
            ));
        }
    };
    // The closing tag must end its line.
    let after = content_end + closing.len() - 1;
    let closing_line_end = bytes[after..]
        .iter()
        .position(|&b| b == b'\n')
        .map_or(bytes.len(), |i| after + i);
    if !trim_ascii(&bytes[after..closing_line_end]).is_empty() {
        return Err(source.syntax(
            name,
            after,
            format!("end of line after \"$End{name}\""),
            describe_bytes(&bytes[after..closing_line_end.min(after + MAX_SECTION_NAME_BYTES)]),
        ));
    }
    Ok((content_end, closing_line_end))
}

/// Split `source` into sections. Text between sections other than whitespace is an error.
pub(crate) fn scan_sections(source: Source<'_>) -> Result<Vec<Section>> {
    let bytes = source.bytes;
    let mut sections = Vec::new();
    let mut pos = 0;
    loop {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if pos >= bytes.len() {
            break;
        }
        let section_name = sections
            .last()
            .map(|s: &Section| s.name.as_str())
            .unwrap_or("");
        if bytes[pos] != b'$' {
            let end = bytes.len().min(pos + MAX_SECTION_NAME_BYTES);
            return Err(source.syntax(
                "",
                pos,
                if section_name.is_empty() {
                    "\"$MeshFormat\" at the start of an MSH file".to_string()
                } else {
                    format!("a section tag \"$Name\" after $End{section_name}")
                },
                describe_bytes(&bytes[pos..end]),
            ));
        }
        let tag_offset = pos;
        let line_end = bytes[pos..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |i| pos + i);
        let name = tag_name(source, pos, line_end)?;
        if line_end >= bytes.len() {
            return Err(source.truncated(
                &name,
                bytes.len(),
                format!("content and \"$End{name}\""),
            ));
        }
        let content_start = line_end + 1;
        let (content_end, closing_line_end) = section_end(source, &name, line_end)?;
        sections.push(Section {
            name,
            tag_offset,
            content_start,
            content_end,
        });
        pos = closing_line_end;
    }
    Ok(sections)
}

/// What the `$MeshFormat` section says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct MeshFormat {
    pub encoding: Encoding,
}

/// MSH format version this reader accepts.
pub(crate) const SUPPORTED_VERSION: &str = "4.1";

/// A binary `$MeshFormat`: the little-endian integer 1 after the format line (ending at
/// `line_end`), and `data_size`-byte sizes.
fn binary_encoding(
    source: Source<'_>,
    section: &Section,
    line_end: usize,
    data_size: usize,
) -> Result<Encoding> {
    let bytes = source.bytes;
    let one_start = line_end + 1;
    if section.content_end < one_start + 4 {
        return Err(source.truncated(
            "MeshFormat",
            one_start,
            "the binary integer 1 (endianness check)",
        ));
    }
    let mut word = [0u8; 4];
    word.copy_from_slice(&bytes[one_start..one_start + 4]);
    if i32::from_le_bytes(word) != 1 {
        let found = if i32::from_be_bytes(word) == 1 {
            "a big-endian file (only little-endian binary MSH is read)".to_string()
        } else {
            describe_bytes(&word)
        };
        return Err(source.syntax(
            "MeshFormat",
            one_start,
            "the little-endian binary integer 1",
            found,
        ));
    }
    Ok(Encoding::Binary {
        size_t_bytes: data_size,
    })
}

/// Parse `$MeshFormat`: version 4.1, file type 0 (ASCII) or 1 (binary), data size 4 or 8, and in
/// binary files the little-endian integer 1.
pub(crate) fn parse_mesh_format(source: Source<'_>, section: &Section) -> Result<MeshFormat> {
    let bytes = source.bytes;
    let line_end = bytes[section.content_start..section.content_end]
        .iter()
        .position(|&b| b == b'\n')
        .map_or(section.content_end, |i| section.content_start + i);
    let line = std::str::from_utf8(&bytes[section.content_start..line_end]).map_err(|_| {
        source.syntax(
            "MeshFormat",
            section.content_start,
            "\"version file-type data-size\" as text",
            describe_bytes(&bytes[section.content_start..line_end]),
        )
    })?;
    let fields: Vec<&str> = line.split_ascii_whitespace().collect();
    let Some(&version) = fields.first() else {
        return Err(source.truncated(
            "MeshFormat",
            section.content_start,
            "\"version file-type data-size\"",
        ));
    };
    if version != SUPPORTED_VERSION {
        let known = version.parse::<f64>().is_ok();
        if !known {
            return Err(source.syntax(
                "MeshFormat",
                section.content_start,
                "a version number such as 4.1",
                format!("\"{version}\""),
            ));
        }
        return Err(MeshError::UnsupportedVersion {
            file: source.name.to_string(),
            found: version.to_string(),
            at: source.location("MeshFormat", section.content_start),
        });
    }
    if fields.len() != 3 {
        return Err(source.syntax(
            "MeshFormat",
            section.content_start,
            "three fields \"4.1 file-type data-size\"",
            format!("\"{line}\""),
        ));
    }
    let data_size: usize = match fields[2].parse() {
        Ok(size @ (4 | 8)) => size,
        _ => {
            return Err(source.syntax(
                "MeshFormat",
                section.content_start,
                "data-size 8 (or 4), the width of size_t",
                format!("\"{}\"", fields[2]),
            ));
        }
    };
    let encoding = match fields[1] {
        "0" => Encoding::Ascii,
        "1" => binary_encoding(source, section, line_end, data_size)?,
        other => {
            return Err(source.syntax(
                "MeshFormat",
                section.content_start,
                "file-type 0 (ASCII) or 1 (binary)",
                format!("\"{other}\""),
            ));
        }
    };
    Ok(MeshFormat { encoding })
}

/// Rank of a known section in the order MSH 4.1 prescribes; `None` for unknown sections.
fn section_rank(name: &str) -> Option<u8> {
    Some(match name {
        "MeshFormat" => 0,
        "PhysicalNames" => 1,
        "Entities" => 2,
        "PartitionedEntities" => 3,
        "Nodes" => 4,
        "Elements" => 5,
        "Periodic" => 6,
        "GhostElements" => 7,
        "Parametrizations" => 8,
        "NodeData" | "ElementData" | "ElementNodeData" | "InterpolationScheme" => 9,
        _ => return None,
    })
}

/// Sections that must appear exactly once.
const REQUIRED_SECTIONS: [&str; 4] = ["MeshFormat", "Entities", "Nodes", "Elements"];
/// Sections that may appear at most once.
const SINGLE_SECTIONS: [&str; 7] = [
    "MeshFormat",
    "PhysicalNames",
    "Entities",
    "PartitionedEntities",
    "Nodes",
    "Elements",
    "Periodic",
];

/// Check the order of the sections: `$MeshFormat` first, then the mesh sections in the order of
/// the MSH 4.1 specification, each at most once; unknown sections are allowed anywhere after
/// the header (and are skipped by the reader).
pub(crate) fn check_section_order(source: Source<'_>, sections: &[Section]) -> Result<()> {
    let order_error = |detail: String| MeshError::SectionOrder {
        file: source.name.to_string(),
        detail,
    };
    match sections.first() {
        None => {
            return Err(source.truncated("", 0, "\"$MeshFormat\" (the file is empty)"));
        }
        Some(first) if first.name != "MeshFormat" => {
            let hint = if first.name == "NOD" || first.name == "NOE" {
                " (this looks like the MSH 1 format; only MSH 4.1 is read)"
            } else {
                ""
            };
            return Err(order_error(format!(
                "the first section must be $MeshFormat, found ${} at byte offset {}{hint}",
                first.name, first.tag_offset
            )));
        }
        Some(_) => {}
    }
    for single in SINGLE_SECTIONS {
        let copies: Vec<&Section> = sections.iter().filter(|s| s.name == single).collect();
        if copies.len() > 1 {
            return Err(order_error(format!(
                "${single} appears {} times (byte offsets {} and {}); it may appear once",
                copies.len(),
                copies[0].tag_offset,
                copies[1].tag_offset
            )));
        }
    }
    let mut previous: Option<(&Section, u8)> = None;
    for section in sections {
        let Some(rank) = section_rank(&section.name) else {
            continue;
        };
        if let Some((before, before_rank)) = previous
            && rank < before_rank
        {
            return Err(order_error(format!(
                "${} (byte offset {}) must come before ${} (byte offset {}); MSH 4.1 order is \
                 MeshFormat, PhysicalNames, Entities, PartitionedEntities, Nodes, Elements, Periodic, ...",
                section.name, section.tag_offset, before.name, before.tag_offset
            )));
        }
        previous = Some((section, rank));
    }
    for required in REQUIRED_SECTIONS {
        if !sections.iter().any(|s| s.name == required) {
            let last_end = sections.last().map_or(0, |s| s.content_end);
            return Err(source.truncated(
                "",
                last_end,
                format!(
                    "a ${required} section (required; the file has {})",
                    list_names(sections)
                ),
            ));
        }
    }
    Ok(())
}

fn list_names(sections: &[Section]) -> String {
    sections
        .iter()
        .map(|s| format!("${}", s.name))
        .collect::<Vec<_>>()
        .join(", ")
}

fn trim_ascii(bytes: &[u8]) -> &[u8] {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    let end = bytes
        .iter()
        .rposition(|b| !b.is_ascii_whitespace())
        .map_or(start, |i| i + 1);
    &bytes[start..end]
}

/// First occurrence of `needle` in `haystack`.
fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    if needle.is_empty() || haystack.len() < needle.len() {
        return None;
    }
    let first = needle[0];
    let mut start = 0;
    while let Some(i) = haystack[start..].iter().position(|&b| b == first) {
        let at = start + i;
        if at + needle.len() > haystack.len() {
            return None;
        }
        if &haystack[at..at + needle.len()] == needle {
            return Some(at);
        }
        start = at + 1;
    }
    None
}
