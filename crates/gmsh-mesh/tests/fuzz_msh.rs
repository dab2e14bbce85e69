//! Fuzz target (proptest) for the MSH reader on the committed meshes (`meshes/*.msh`, real gmsh
//! output, ASCII): random bytes, truncation, byte flips and huge counts must give an error (or a
//! consistent mesh), never a panic, and never an allocation out of proportion to the input.
//!
//! The case count is bounded so that the target runs in seconds in every `cargo test`; run it
//! longer with `PROPTEST_CASES=20000 cargo test --release -p gmsh-mesh --test fuzz_msh`.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use gmsh_mesh::{BadElementPolicy, ReadOptions, parse_msh};
use proptest::prelude::*;

/// Records the largest single allocation of the current thread while armed.
struct TrackingAllocator;

thread_local! {
    static LARGEST_ALLOCATION: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for TrackingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = LARGEST_ALLOCATION.try_with(|m| m.set(m.get().max(layout.size())));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = LARGEST_ALLOCATION.try_with(|m| m.set(m.get().max(new_size)));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: TrackingAllocator = TrackingAllocator;

/// Largest single allocation the reader may make per input byte: a node line of ≥ 8 bytes becomes
/// 24 bytes of coordinates, a tag and its map entries; 64 bytes per input byte is generous.
const ALLOCATION_PER_INPUT_BYTE: usize = 64;
/// Allocation allowed regardless of the input size (bytes).
const ALLOCATION_FLOOR: usize = 1 << 20;

/// Cases per property in the default test run (one parse of a ≈ 200 kB mesh each). Overridden
/// by `PROPTEST_CASES`.
const DEFAULT_CASES: u32 = 256;

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_CASES)
}

/// The two smallest committed meshes (ASCII, Tet4 with periodic nodes and Tet10).
const MESHES: [&str; 2] = [
    "slider-strip-periodic_p40um_d20um_n1_tet4_1k.msh",
    "slider-body_5x5x0.5mm_tet10_2k.msh",
];

fn committed(name: &str) -> Vec<u8> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/");
    std::fs::read(format!("{path}{name}")).expect("committed mesh exists")
}

fn lenient() -> ReadOptions {
    ReadOptions {
        bad_elements: BadElementPolicy::Report,
    }
}

/// Parse `bytes`; a loaded mesh must be consistent, and no allocation may exceed the bound.
fn parse_checked(bytes: &[u8], name: &str) -> Result<(), TestCaseError> {
    LARGEST_ALLOCATION.with(|m| m.set(0));
    let result = parse_msh(bytes, name, &lenient());
    let largest = LARGEST_ALLOCATION.with(Cell::get);
    let bound = ALLOCATION_FLOOR + ALLOCATION_PER_INPUT_BYTE * bytes.len();
    prop_assert!(
        largest <= bound,
        "{name}: largest allocation {largest} B for {} B of input (bound {bound} B)",
        bytes.len()
    );
    match result {
        Ok(mesh) => {
            let n = mesh.nodes.len();
            prop_assert!(
                (0..mesh.tets.len()).all(|t| mesh.tets.nodes(t).iter().all(|&i| i < n)),
                "{name}: tet node index in range"
            );
        }
        Err(error) => prop_assert!(error.to_string().contains(name), "error names the file"),
    }
    Ok(())
}

/// Byte offsets just after each line break that starts a section's count line (after `$Name\n`),
/// where a huge count does the most damage.
fn count_offsets(bytes: &[u8]) -> Vec<usize> {
    let mut offsets = Vec::new();
    for (i, window) in bytes.windows(2).enumerate() {
        if window == b"\n$"
            && !bytes[i + 2..].starts_with(b"$End")
            && let Some(eol) = bytes[i + 1..].iter().position(|&b| b == b'\n')
        {
            offsets.push(i + 1 + eol + 1);
        }
    }
    offsets
}

#[test]
fn committed_meshes_read_within_the_allocation_bound() {
    for name in MESHES {
        parse_checked(&committed(name), name).unwrap();
        let largest = LARGEST_ALLOCATION.with(Cell::get);
        assert!(
            largest > 10_000,
            "{name}: the allocation tracker sees the node arrays ({largest} B)"
        );
        parse_msh(&committed(name), name, &ReadOptions::default()).expect("intact mesh reads");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_are_an_error(bytes in proptest::collection::vec(any::<u8>(), 0..4096)) {
        parse_checked(&bytes, "random.msh")?;
    }

    #[test]
    fn random_bytes_after_a_valid_header_are_an_error(
        bytes in proptest::collection::vec(any::<u8>(), 0..4096),
    ) {
        let mut input = b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n".to_vec();
        input.extend_from_slice(&bytes);
        parse_checked(&input, "header.msh")?;
    }

    #[test]
    fn truncated_committed_meshes_are_an_error(mesh in 0..MESHES.len(), cut in any::<prop::sample::Index>()) {
        let bytes = committed(MESHES[mesh]);
        let cut = cut.index(bytes.len());
        parse_checked(&bytes[..cut], MESHES[mesh])?;
        // A cut before `$EndElements` loses required data.
        let elements_end = bytes.windows(13).position(|w| w == b"\n$EndElements").unwrap() + 13;
        prop_assert!(
            cut >= elements_end || parse_msh(&bytes[..cut], MESHES[mesh], &lenient()).is_err(),
            "{} cut at {cut} of {} bytes must not load", MESHES[mesh], bytes.len()
        );
    }

    #[test]
    fn byte_flips_in_committed_meshes_never_panic(
        mesh in 0..MESHES.len(),
        flips in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..16),
    ) {
        let mut bytes = committed(MESHES[mesh]);
        for (index, value) in flips {
            let at = index.index(bytes.len());
            bytes[at] = value;
        }
        parse_checked(&bytes, MESHES[mesh])?;
    }

    #[test]
    fn huge_counts_in_committed_meshes_fail_without_allocating(
        mesh in 0..MESHES.len(),
        section in any::<prop::sample::Index>(),
        count in prop::sample::select(vec![
            "18446744073709551615", "9223372036854775807", "4294967295", "2147483648",
            "99999999999", "-1", "1e30",
        ]),
        replace_first_field in any::<bool>(),
    ) {
        let bytes = committed(MESHES[mesh]);
        let offsets = count_offsets(&bytes);
        let at = offsets[section.index(offsets.len())];
        // Replace the first (or the last) number of the count line with the huge count.
        let eol = at + bytes[at..].iter().position(|&b| b == b'\n').unwrap_or(bytes.len() - at);
        let line = String::from_utf8_lossy(&bytes[at..eol]).into_owned();
        let fields: Vec<&str> = line.split_whitespace().collect();
        prop_assume!(!fields.is_empty());
        let mut new_fields = fields.clone();
        let which = if replace_first_field { 0 } else { fields.len() - 1 };
        new_fields[which] = count;
        let mut damaged = bytes[..at].to_vec();
        damaged.extend_from_slice(new_fields.join(" ").as_bytes());
        damaged.extend_from_slice(&bytes[eol..]);
        parse_checked(&damaged, MESHES[mesh])?;
    }
}
