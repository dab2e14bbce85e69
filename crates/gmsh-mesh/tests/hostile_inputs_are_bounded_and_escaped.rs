//! Inputs that are not meshes are refused before they are read (a device such as /dev/zero, a
//! directory, a file over the size limit), and error messages that quote bytes of a mesh escape
//! control bytes, so a file cannot drive the terminal that shows the error.

mod common;

use gmsh_mesh::{MeshError, ReadOptions, mesh_info, parse_msh, read_file_bounded, read_msh};

#[test]
fn a_device_is_refused_without_reading_it() {
    let zero = std::path::Path::new("/dev/zero");
    if !zero.exists() {
        return;
    }
    let err = read_msh(zero).expect_err("/dev/zero is not a mesh");
    assert!(
        matches!(err, MeshError::NotAFile { .. }),
        "/dev/zero refused as not a regular file: {err}"
    );
    assert!(
        err.to_string().contains("/dev/zero"),
        "error names the path: {err}"
    );
}

#[test]
fn a_directory_is_refused_by_name() {
    let dir = tempfile::tempdir().expect("temp dir");
    let err = read_msh(dir.path()).expect_err("a directory is not a mesh");
    assert!(
        err.to_string().contains("a directory"),
        "error says what the path is: {err}"
    );
}

#[test]
fn a_file_over_the_limit_is_refused_before_it_is_read() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("big.msh");
    std::fs::write(&path, vec![b' '; 1000]).expect("write");
    let err = read_file_bounded(&path, 999).expect_err("1000 bytes over a 999-byte limit");
    assert!(
        matches!(err, MeshError::TooLarge { limit: 999, .. }),
        "size limit named: {err}"
    );
    assert_eq!(
        read_file_bounded(&path, 1000).expect("at the limit").len(),
        1000,
        "a file of exactly the limit is read whole"
    );
}

fn assert_escaped(text: &str) {
    assert!(
        !text.bytes().any(|b| b == 0x1b || b == 0x07),
        "no raw ESC or BEL byte in the message: {text:?}"
    );
    assert!(text.contains("\\x1b"), "ESC shown as \\x1b: {text}");
}

#[test]
fn a_syntax_error_quoting_escape_bytes_shows_them_escaped() {
    let bytes = b"$MeshFormat\n\x1b[2J\x07 0 8\n$EndMeshFormat\n";
    let err = parse_msh(bytes, "evil.msh", &ReadOptions::default()).expect_err("bad version");
    assert_escaped(&err.to_string());
}

#[test]
fn physical_names_with_escape_bytes_are_escaped_in_errors_and_in_mesh_info() {
    let original = std::fs::read(common::fixture("sparse_tags_two_tets.msh")).expect("fixture");
    let text = String::from_utf8(original).expect("ASCII fixture");
    let evil = text.replace("\"body\"", "\"\x1b]0;owned\x07body\"");
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("evil.msh");
    std::fs::write(&path, evil).expect("write");
    let mesh = read_msh(&path).expect("a name with control bytes still parses");
    let err = mesh.group_tets("missing").expect_err("no such group");
    assert_escaped(&err.to_string());
    let info = mesh_info(&path).expect("mesh info").to_string();
    assert_escaped(&info);
}

/// Peak resident memory of this process (kB), from /proc (Linux).
fn peak_rss_kb() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

#[test]
fn a_large_file_that_is_not_a_mesh_is_refused_from_its_first_bytes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("disk.img");
    let file = std::fs::File::create(&path).expect("file");
    std::fs::write(&path, b"not a mesh").expect("head");
    // 1.5 GiB, sparse: reading it whole would raise the peak memory by as much.
    file.set_len(3 << 29).expect("sparse length");
    let before = peak_rss_kb();
    let err = read_msh(&path).expect_err("not a mesh");
    assert!(
        err.to_string().contains("$MeshFormat"),
        "names what an MSH file starts with: {err}"
    );
    if let (Some(before), Some(after)) = (before, peak_rss_kb()) {
        assert!(
            after - before < 100_000,
            "read only the head: peak memory grew by {} kB",
            after - before
        );
    }
}
