//! Meshes of the automatic mesh cache are verified before reuse: a swapped, edited or truncated
//! cached mesh is detected (its SHA-256 differs from the one recorded when gmsh made it) and
//! regenerated; a cached mesh that still cannot be read names the cache file and how to clear
//! it. Needs gmsh (CI installs it); without it the tests print a note and return.

use static_contact::mesh_source::{file_sha256, resolve_mesh_verified};
use static_contact::params::StaticParams;
use static_contact::{ContactError, prepare_strip};

fn gmsh_available() -> bool {
    let found = std::process::Command::new("gmsh")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        println!("note: gmsh not installed; skipping");
    }
    found
}

/// A two-post Tet4 strip of the default slider (no committed mesh: gmsh makes it, ≈ 1 s).
fn two_post_strip(cache: &std::path::Path) -> StaticParams {
    StaticParams {
        strip_posts: Some(2),
        element_order: 1,
        mesh_cache_dir: Some(cache.to_path_buf()),
        ..StaticParams::default()
    }
}

#[test]
fn a_swapped_or_truncated_cached_mesh_is_detected_and_regenerated() {
    if !gmsh_available() {
        return;
    }
    let cache = tempfile::tempdir().expect("temp dir");
    let params = two_post_strip(cache.path());
    let made = resolve_mesh_verified(&params).expect("gmsh makes the strip mesh");
    assert!(made.notes.is_empty(), "fresh mesh: {:?}", made.notes);
    let good = file_sha256(&made.path).expect("hash");
    let reused = resolve_mesh_verified(&params).expect("cached mesh");
    assert_eq!(reused.path, made.path, "same cache entry reused");
    assert!(
        reused.notes.is_empty(),
        "an intact cached mesh is reused silently"
    );

    let committed = static_contact::mesh_source::workspace_root()
        .join("meshes/slider-strip_p40um_d20um_n10_tet4_10k.msh");
    let bytes = std::fs::read(&made.path).expect("mesh bytes");
    for (what, damaged) in [
        (
            "swapped",
            std::fs::read(&committed).expect("committed mesh"),
        ),
        ("truncated", bytes[..bytes.len() / 2].to_vec()),
    ] {
        std::fs::write(&made.path, damaged).expect("damage the cached mesh");
        let again = resolve_mesh_verified(&params).expect("regenerated mesh");
        assert_eq!(
            again.notes.len(),
            1,
            "{what} cached mesh reported in one line: {:?}",
            again.notes
        );
        assert!(
            again.notes[0].contains(&made.path.display().to_string())
                && again.notes[0].contains("content hash differs"),
            "the note names the cache file and why: {}",
            again.notes[0]
        );
        assert_eq!(
            file_sha256(&again.path).expect("hash"),
            good,
            "the {what} mesh was regenerated (gmsh is deterministic on one thread)"
        );
    }
}

#[test]
fn an_unreadable_cached_mesh_names_the_file_and_how_to_clear_the_cache() {
    if !gmsh_available() {
        return;
    }
    let cache = tempfile::tempdir().expect("temp dir");
    let params = two_post_strip(cache.path());
    let made = resolve_mesh_verified(&params).expect("gmsh makes the strip mesh");
    // A truncated mesh whose recorded hash was rewritten to match (e.g. a copy of a damaged
    // cache): it passes the hash check and fails in the reader.
    let bytes = std::fs::read(&made.path).expect("mesh bytes");
    std::fs::write(&made.path, &bytes[..bytes.len() / 2]).expect("truncate");
    let mut record = made.path.as_os_str().to_owned();
    record.push(".sha256");
    std::fs::write(&record, file_sha256(&made.path).expect("hash")).expect("rewrite record");
    let err = prepare_strip(&params).expect_err("a truncated mesh cannot be read");
    let text = err.to_string();
    assert!(
        matches!(err, ContactError::CachedMesh { .. })
            && text.contains(&made.path.display().to_string())
            && text.contains("clear the mesh cache")
            && text.contains(&cache.path().display().to_string()),
        "error names the cache file, the cache folder and how to clear it: {text}"
    );
}
