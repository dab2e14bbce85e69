//! The fill-reducing ordering of a cached mesh's stiffness, stored beside the mesh.
//!
//! METIS nested dissection of the default strip (316 k unknowns) costs ≈ 2 s of CPU and gives
//! the same permutation on every run of the same mesh: it depends on the sparsity pattern only
//! (elastic-fem [`fill_reducing_order`](elastic_fem::sparse::fill_reducing_order)). It is stored
//! in the mesh cache as `MESH.msh.BODY.order-PATTERN`, PATTERN being the 64-bit fingerprint of
//! the reduced stiffness pattern (hex), so that other constraints or another mesh never reuse
//! it. A file that is not a permutation of the right size is ignored and rewritten. Even a valid
//! permutation of another pattern could only change the fill, never the result: every
//! permutation gives the exact factor.
//!
//! Format: the magic [`MAGIC`], the ordering used (one byte: 0 METIS, 1 AMD, 2 natural), the
//! dimension (u64 little-endian), then `forward[new] = old` as u32 little-endian.

use std::path::{Path, PathBuf};

use elastic_fem::sparse::Ordering;

/// First bytes of an ordering file (format version 1).
pub const MAGIC: &[u8; 16] = b"sawdrive-order1\n";

/// The ordering file of body `body` of the mesh `mesh_file` in the folder `dir`, for the
/// reduced pattern with fingerprint `pattern`.
pub fn order_file(dir: &Path, mesh_file: &str, body: &str, pattern: u64) -> PathBuf {
    let stem = Path::new(mesh_file)
        .file_name()
        .map_or_else(|| "mesh".into(), |n| n.to_string_lossy().into_owned());
    dir.join(format!("{stem}.{body}.order-{pattern:016x}"))
}

fn code(ordering: Ordering) -> u8 {
    match ordering {
        Ordering::Metis => 0,
        Ordering::Amd => 1,
        Ordering::Natural => 2,
    }
}

/// The stored ordering (forward permutation and the ordering that made it) if `path` holds a
/// permutation of `dim` unknowns in the format above; `None` otherwise (absent, truncated,
/// another size, not a permutation).
pub fn load(path: &Path, dim: usize) -> Option<(Vec<usize>, Ordering)> {
    let bytes = std::fs::read(path).ok()?;
    let header = MAGIC.len() + 1 + 8;
    if bytes.len() != header + 4 * dim || &bytes[..MAGIC.len()] != MAGIC {
        return None;
    }
    let ordering = match bytes[MAGIC.len()] {
        0 => Ordering::Metis,
        1 => Ordering::Amd,
        2 => Ordering::Natural,
        _ => return None,
    };
    let stored_dim = u64::from_le_bytes(bytes[MAGIC.len() + 1..header].try_into().ok()?);
    if stored_dim != dim as u64 {
        return None;
    }
    let forward: Vec<usize> = bytes[header..]
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as usize)
        .collect();
    let mut seen = vec![false; dim];
    for &j in &forward {
        if j >= dim || std::mem::replace(&mut seen[j], true) {
            return None;
        }
    }
    Some((forward, ordering))
}

/// Writes the ordering to `path` (temporary name, then rename: a reader never sees half a file).
pub fn store(path: &Path, forward: &[usize], ordering: Ordering) -> std::io::Result<()> {
    let too_large = || std::io::Error::other("ordering has more than 2^32 unknowns");
    let mut bytes = Vec::with_capacity(MAGIC.len() + 9 + 4 * forward.len());
    bytes.extend_from_slice(MAGIC);
    bytes.push(code(ordering));
    bytes.extend_from_slice(&(forward.len() as u64).to_le_bytes());
    for &j in forward {
        bytes.extend_from_slice(&u32::try_from(j).map_err(|_| too_large())?.to_le_bytes());
    }
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".tmp-{}", std::process::id()));
    let temporary = path.with_file_name(name);
    std::fs::write(&temporary, &bytes)?;
    std::fs::rename(&temporary, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&temporary);
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stored_ordering_loads_back_and_a_damaged_one_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = order_file(dir.path(), "/x/strip.msh", "slider", 0xabc);
        assert!(path.ends_with("strip.msh.slider.order-0000000000000abc"));
        let forward = vec![2, 0, 3, 1];
        store(&path, &forward, Ordering::Metis).unwrap();
        assert_eq!(
            load(&path, 4),
            Some((forward, Ordering::Metis)),
            "stored ordering"
        );
        assert_eq!(
            load(&path, 5),
            None,
            "an ordering of another size is refused"
        );
        // Not a permutation (entry 3 replaced by a repeated 2).
        let mut bytes = std::fs::read(&path).unwrap();
        let at = MAGIC.len() + 9 + 4 * 2;
        bytes[at..at + 4].copy_from_slice(&2u32.to_le_bytes());
        std::fs::write(&path, &bytes).unwrap();
        assert_eq!(load(&path, 4), None, "a repeated unknown is refused");
        std::fs::write(&path, &bytes[..bytes.len() - 1]).unwrap();
        assert_eq!(load(&path, 4), None, "a truncated ordering is refused");
    }
}
