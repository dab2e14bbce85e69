//! Truncated and corrupted files must give errors, never panics or hangs.
//!
//! Every parser loop is bounded by a count that was first checked against the bytes left in the
//! section, so a hang would show up here as a test that does not finish.

mod common;

use common::fixture;
use gmsh_mesh::{BadElementPolicy, ReadOptions, TetMesh, parse_msh};
use proptest::prelude::*;

/// The small fixtures fuzzed here: ASCII Tet4 by hand, binary Tet4 and ASCII Tet10 from gmsh.
const FUZZED_FIXTURES: [&str; 3] = [
    "sparse_tags_two_tets.msh",
    "box_coarse_tet4_binary.msh",
    "box_coarse_tet10.msh",
];

fn read_fixture(name: &str) -> Vec<u8> {
    std::fs::read(fixture(name)).expect("fixture exists")
}

/// Options that load inverted tets too, so that corruption reaches every later stage.
fn lenient() -> ReadOptions {
    ReadOptions {
        bad_elements: BadElementPolicy::Report,
    }
}

/// Whatever loads must be internally consistent (indices in range, one group per tet).
fn assert_consistent(mesh: &TetMesh) {
    let n = mesh.nodes.len();
    assert_eq!(mesh.node_tags.len(), n, "one tag per node");
    assert_eq!(mesh.tet_tags.len(), mesh.tets.len(), "one tag per tet");
    assert_eq!(mesh.tet_groups.len(), mesh.tets.len(), "one group per tet");
    for t in 0..mesh.tets.len() {
        assert!(
            mesh.tets.nodes(t).iter().all(|&i| i < n),
            "tet node index in range"
        );
    }
    for faces in mesh.surface_groups.values() {
        for f in 0..faces.len() {
            assert!(
                faces.nodes(f).iter().all(|&i| i < n),
                "face node index in range"
            );
        }
    }
    for pair in &mesh.periodic_node_pairs {
        assert!(pair[0] < n && pair[1] < n, "periodic pair in range");
    }
    let _ = mesh.quality();
    let _ = mesh.volume();
}

/// Offset just past `$EndElements` (the last section these fixtures need; anything after it is
/// optional): any cut before it loses a required closing tag.
fn elements_end(bytes: &[u8]) -> usize {
    find(bytes, b"\n$EndElements").expect("has $EndElements") + "\n$EndElements".len()
}

#[test]
fn truncation_at_every_offset_is_an_error() {
    for name in FUZZED_FIXTURES {
        let bytes = read_fixture(name);
        parse_msh(&bytes, name, &ReadOptions::default()).expect("the intact fixture reads");
        let complete = elements_end(&bytes);
        for cut in 0..complete {
            let result = parse_msh(&bytes[..cut], name, &lenient());
            assert!(
                result.is_err(),
                "{name} truncated to {cut} of {} bytes must not load",
                bytes.len()
            );
            let message = result.unwrap_err().to_string();
            assert!(message.contains(name), "error names the file: {message}");
        }
    }
}

/// Byte ranges of the sections of an MSH file (from `$Name` to the end of `$EndName`'s line).
fn section_ranges(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut ranges = Vec::new();
    let mut pos = 0;
    while let Some(i) = bytes[pos..].iter().position(|&b| b == b'$') {
        let start = pos + i;
        let name_end = start
            + bytes[start..]
                .iter()
                .position(|&b| b == b'\n')
                .expect("tag line");
        let name = String::from_utf8_lossy(&bytes[start + 1..name_end])
            .trim()
            .to_string();
        let closing = format!("\n$End{name}\n");
        let close =
            start + find(&bytes[start..], closing.as_bytes()).expect("closing tag") + closing.len();
        ranges.push((start, close));
        pos = close;
    }
    ranges
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 192, ..ProptestConfig::default() })]

    #[test]
    fn random_byte_flips_never_panic(
        fixture_index in 0..FUZZED_FIXTURES.len(),
        flips in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
    ) {
        let name = FUZZED_FIXTURES[fixture_index];
        let mut bytes = read_fixture(name);
        for (index, value) in flips {
            let at = index.index(bytes.len());
            bytes[at] = value;
        }
        if let Ok(mesh) = parse_msh(&bytes, name, &lenient()) {
            assert_consistent(&mesh);
        }
    }

    #[test]
    fn random_digit_and_sign_edits_never_panic(
        fixture_index in 0..FUZZED_FIXTURES.len(),
        edits in proptest::collection::vec((any::<prop::sample::Index>(), prop::sample::select(b"0123456789-.e \n".to_vec())), 1..6),
    ) {
        // Edits that keep ASCII files plausible reach deeper into the parser than random bytes.
        let name = FUZZED_FIXTURES[fixture_index];
        let mut bytes = read_fixture(name);
        for (index, value) in edits {
            let at = index.index(bytes.len());
            bytes[at] = value;
        }
        if let Ok(mesh) = parse_msh(&bytes, name, &lenient()) {
            assert_consistent(&mesh);
        }
    }

    #[test]
    fn swapped_sections_are_an_order_error(
        fixture_index in 0..FUZZED_FIXTURES.len(),
        first in any::<prop::sample::Index>(),
        second in any::<prop::sample::Index>(),
    ) {
        let name = FUZZED_FIXTURES[fixture_index];
        let bytes = read_fixture(name);
        let ranges = section_ranges(&bytes);
        let i = first.index(ranges.len() - 1);
        let j = i + 1 + second.index(ranges.len() - 1 - i);
        let (a, b) = (ranges[i], ranges[j]);
        let mut swapped = bytes[..a.0].to_vec();
        swapped.extend_from_slice(&bytes[b.0..b.1]);
        swapped.extend_from_slice(&bytes[a.1..b.0]);
        swapped.extend_from_slice(&bytes[a.0..a.1]);
        swapped.extend_from_slice(&bytes[b.1..]);
        let result = parse_msh(&swapped, name, &lenient());
        let section_name = |r: (usize, usize)| String::from_utf8_lossy(&bytes[r.0 + 1..r.0 + 8]).to_string();
        // Unknown sections (e.g. $Comments) may stand anywhere after $MeshFormat.
        let involves_unknown = [a, b].iter().any(|r| section_name(*r).starts_with("Comment"));
        if !involves_unknown {
            prop_assert!(result.is_err(), "{name} with sections {i} and {j} swapped must not load");
        }
    }

    #[test]
    fn truncated_and_padded_garbage_never_panics(
        fixture_index in 0..FUZZED_FIXTURES.len(),
        cut in any::<prop::sample::Index>(),
        garbage in proptest::collection::vec(any::<u8>(), 0..64),
    ) {
        let name = FUZZED_FIXTURES[fixture_index];
        let bytes = read_fixture(name);
        let mut damaged = bytes[..cut.index(bytes.len())].to_vec();
        damaged.extend_from_slice(&garbage);
        if let Ok(mesh) = parse_msh(&damaged, name, &lenient()) {
            assert_consistent(&mesh);
        }
    }
}

#[test]
fn huge_declared_counts_fail_fast_without_allocating() {
    let text = String::from_utf8(read_fixture("sparse_tags_two_tets.msh")).expect("utf8");
    for (from, to) in [
        (
            "$Nodes\n4 6 5 1000",
            "$Nodes\n4 18446744073709551615 5 1000",
        ),
        ("$Elements\n7 7", "$Elements\n99999999999999 7"),
    ] {
        let damaged = text.replacen(from, to, 1);
        let message = parse_msh(damaged.as_bytes(), "huge.msh", &ReadOptions::default())
            .expect_err("huge count")
            .to_string();
        assert!(
            message.contains("remain in the section"),
            "count checked against the bytes left: {message}"
        );
    }
}

#[test]
fn empty_and_non_msh_inputs_are_errors() {
    for (bytes, expected) in [
        (&b""[..], "empty"),
        (&b"\n\n  \n"[..], "empty"),
        (&b"solid cube\nfacet normal 0 0 1\n"[..], "$MeshFormat"),
        (&b"$NOD\n1\n1 0 0 0\n$ENDNOD\n"[..], "$NOD"),
        (&b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"[..], "$Entities"),
    ] {
        let message = parse_msh(bytes, "odd.msh", &ReadOptions::default())
            .expect_err("not a mesh")
            .to_string();
        assert!(
            message.contains(expected),
            "message mentions {expected}: {message}"
        );
    }
}
