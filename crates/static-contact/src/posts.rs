//! Finding the posts of a slider mesh: each connected patch of the post-tip surface group is one
//! post tip disk.

use gmsh_mesh::TetMesh;

use crate::body::Disk;
use crate::error::{ContactError, Result};

/// Relative tolerance (of the patch's x extent) for telling a half disk from a whole one by its
/// y extent, and for finding the nodes on a half disk's straight edge. Default 0.1.
pub const HALF_DISK_TOLERANCE: f64 = 0.1;

/// The tip disks of the surface group `group` (connected components of its triangles), sorted by
/// y row then x. Centre = middle of the patch's bounding box, radius = largest in-plane distance
/// of a patch node from it. A half disk (the strip's mirror cut, `slider-strip.geo` `half_y`)
/// gets the centre of its whole disk; see [`find_tip_disks_with_fraction`].
pub fn find_tip_disks(mesh: &TetMesh, group: &str) -> Result<Vec<Disk>> {
    find_tip_disks_with_fraction(mesh, group).map(|(disks, _)| disks)
}

/// Centre and radius of one patch from its nodes' bounding box, and its fraction of a whole
/// disk: 1, or ½ for a disk cut by a plane y = const through its centre (y extent ≈ half the x
/// extent; the centre lies on the straight edge, the side of the bounding box where more nodes
/// sit).
fn patch_disk(mesh: &TetMesh, nodes: &[usize]) -> (Disk, f64) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for &a in nodes {
        for c in 0..3 {
            lo[c] = lo[c].min(mesh.nodes[a][c]);
            hi[c] = hi[c].max(mesh.nodes[a][c]);
        }
    }
    let (ex, ey) = (hi[0] - lo[0], hi[1] - lo[1]);
    let half = (ey / ex - 0.5).abs() < HALF_DISK_TOLERANCE;
    let mut centre_m = [
        0.5 * (lo[0] + hi[0]),
        0.5 * (lo[1] + hi[1]),
        0.5 * (lo[2] + hi[2]),
    ];
    if half {
        let tol = HALF_DISK_TOLERANCE * ex;
        let near = |y: f64| {
            nodes
                .iter()
                .filter(|&&a| (mesh.nodes[a][1] - y).abs() <= tol)
                .count()
        };
        centre_m[1] = if near(lo[1]) >= near(hi[1]) {
            lo[1]
        } else {
            hi[1]
        };
    }
    let radius_m = nodes
        .iter()
        .map(|&a| {
            ((mesh.nodes[a][0] - centre_m[0]).powi(2) + (mesh.nodes[a][1] - centre_m[1]).powi(2))
                .sqrt()
        })
        .fold(0.0, f64::max);
    (Disk { centre_m, radius_m }, if half { 0.5 } else { 1.0 })
}

/// [`find_tip_disks`] and the fraction of a whole disk that each patch is: 1, or ½ when every
/// patch is a half disk (a mirror cut through the post axes). A mix of whole and half disks is
/// refused.
pub fn find_tip_disks_with_fraction(mesh: &TetMesh, group: &str) -> Result<(Vec<Disk>, f64)> {
    let faces = mesh
        .group_faces(group)
        .map_err(|source| ContactError::Mesh {
            file: mesh.source.clone(),
            source: Box::new(source),
        })?;
    let n = mesh.nodes.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    let mut used = vec![false; n];
    for i in 0..faces.len() {
        let nodes = faces.nodes(i);
        for &a in nodes {
            used[a] = true;
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, nodes[0]));
            if ra != rb {
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    let mut patches: std::collections::BTreeMap<usize, Vec<usize>> =
        std::collections::BTreeMap::new();
    for a in (0..n).filter(|&a| used[a]) {
        let r = find(&mut parent, a);
        patches.entry(r).or_default().push(a);
    }
    let measured: Vec<(Disk, f64)> = patches
        .values()
        .map(|nodes| patch_disk(mesh, nodes))
        .collect();
    let fraction = measured.first().map_or(1.0, |d| d.1);
    if let Some((d, f)) = measured.iter().find(|d| d.1 != fraction) {
        return Err(ContactError::MeshMismatch {
            file: mesh.source.clone(),
            detail: format!(
                "surface group `{group}` mixes whole and half tip disks (the patch at {:?} m is \
                 {f} of a disk, the first {fraction})",
                d.centre_m
            ),
        });
    }
    let mut disks: Vec<Disk> = measured.into_iter().map(|d| d.0).collect();
    if disks.is_empty() {
        return Err(ContactError::MeshMismatch {
            file: mesh.source.clone(),
            detail: format!("surface group `{group}` has no triangles"),
        });
    }
    let r = disks[0].radius_m;
    disks.sort_by(|a, b| {
        let row = |d: &Disk| (d.centre_m[1] / r).round() as i64;
        row(a)
            .cmp(&row(b))
            .then(a.centre_m[0].total_cmp(&b.centre_m[0]))
    });
    Ok((disks, fraction))
}
