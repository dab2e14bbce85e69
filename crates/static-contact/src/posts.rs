//! Finding the posts of a slider mesh: each connected patch of the post-tip surface group is one
//! post tip disk.

use gmsh_mesh::TetMesh;

use crate::body::Disk;
use crate::error::{ContactError, Result};

/// The tip disks of the surface group `group` (connected components of its triangles), sorted by
/// y row then x. Centre = middle of the patch's bounding box, radius = largest in-plane distance
/// of a patch node from it.
pub fn find_tip_disks(mesh: &TetMesh, group: &str) -> Result<Vec<Disk>> {
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
    let mut disks: Vec<Disk> = patches
        .values()
        .map(|nodes| {
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            for &a in nodes {
                for c in 0..3 {
                    lo[c] = lo[c].min(mesh.nodes[a][c]);
                    hi[c] = hi[c].max(mesh.nodes[a][c]);
                }
            }
            let centre_m = [
                0.5 * (lo[0] + hi[0]),
                0.5 * (lo[1] + hi[1]),
                0.5 * (lo[2] + hi[2]),
            ];
            let radius_m = nodes
                .iter()
                .map(|&a| {
                    ((mesh.nodes[a][0] - centre_m[0]).powi(2)
                        + (mesh.nodes[a][1] - centre_m[1]).powi(2))
                    .sqrt()
                })
                .fold(0.0, f64::max);
            Disk { centre_m, radius_m }
        })
        .collect();
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
    Ok(disks)
}
