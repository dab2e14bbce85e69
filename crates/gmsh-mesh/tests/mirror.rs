//! `gmsh_mesh::mirror` on the strip geometry: the half strip `slider-strip.geo` meshes with
//! `mirror_x = 1`, reflected in its plane x = L/2, is a whole strip mesh of the same body as the
//! one gmsh meshes whole: same volume, same area of every named face group, outward faces, and an
//! exactly symmetric node set. Needs gmsh (CI installs it); without it the test prints a note
//! and returns.

mod common;

use std::path::Path;

use gmsh_mesh::gmsh::{GmshOptions, run_geo};
use gmsh_mesh::mirror::{MirrorPlane, MirrorRename, mirror_in_x};
use gmsh_mesh::{TetMesh, read_msh};

/// The 4-post strip (half width, with a stator block) meshed with `mirror_x`.
fn strip(dir: &Path, mirror_x: f64) -> TetMesh {
    let geo = common::geometry("slider-strip");
    let out = dir.join(format!("strip-mirror{mirror_x}.msh"));
    let numbers = [
        ("n_posts", 4.0),
        ("margin", 30e-6),
        ("stator_depth", 100e-6),
        ("h_post", 4e-6),
        ("half_y", 1.0),
        ("mirror_x", mirror_x),
    ];
    run_geo(&geo, &out, &numbers, &GmshOptions::default()).expect("gmsh strip");
    read_msh(&out).expect("strip mesh")
}

fn strip_plane() -> MirrorPlane {
    let rename = |from: &str, to: &str, tag| MirrorRename {
        from: from.into(),
        to: to.into(),
        tag,
    };
    MirrorPlane {
        groups: vec!["slider_mirror_x".into(), "stator_mirror_x".into()],
        renames: vec![
            rename("slider_x0", "slider_x1", 16),
            rename("stator_x0", "stator_x1", 26),
        ],
    }
}

#[test]
fn the_reflected_half_strip_is_the_whole_strip_body_with_outward_faces() {
    if !common::gmsh_available() {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let half = strip(dir.path(), 1.0);
    let whole = strip(dir.path(), 0.0);
    let mirrored = mirror_in_x(&half, &strip_plane()).expect("mirror");
    let relative = common::relative_error;
    assert!(relative(mirrored.volume(), whole.volume()) < 1e-12);
    let names = |m: &TetMesh| m.surface_groups.keys().cloned().collect::<Vec<_>>();
    assert_eq!(names(&mirrored), names(&whole));
    for name in names(&whole) {
        let (a, b) = (
            mirrored.face_area(&name).unwrap(),
            whole.face_area(&name).unwrap(),
        );
        assert!(relative(a, b) < 1e-9, "{name}: area {a:e} against {b:e}");
        assert_eq!(
            common::inward_face_count(&mirrored, &name),
            0,
            "{name} faces inward"
        );
    }
    let groups = |m: &TetMesh| {
        m.groups
            .iter()
            .map(|g| (g.dim, g.tag, g.name.clone()))
            .collect::<Vec<_>>()
    };
    assert_eq!(groups(&mirrored), groups(&whole));
    assert_eq!(
        mirrored.group_tets("slider").unwrap().len(),
        2 * half.group_tets("slider").unwrap().len()
    );
    // Every node has its mirror image among the nodes (y and z to the bit, x to round-off).
    let [lo, hi] = mirrored.bounding_box().unwrap();
    let mut by_yz: std::collections::HashMap<[u64; 2], Vec<f64>> = Default::default();
    for p in &mirrored.nodes {
        by_yz
            .entry([p[1].to_bits(), p[2].to_bits()])
            .or_default()
            .push(p[0]);
    }
    let tolerance = 1e-12 * (hi[0] - lo[0]);
    let missing = mirrored
        .nodes
        .iter()
        .filter(|p| {
            let image = (lo[0] + hi[0]) - p[0];
            !by_yz[&[p[1].to_bits(), p[2].to_bits()]]
                .iter()
                .any(|x| (x - image).abs() <= tolerance)
        })
        .count();
    assert_eq!(missing, 0, "nodes without a mirror image");
    assert_eq!(mirrored.quality().inverted_count, 0);
}
