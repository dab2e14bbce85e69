//! An explicit mesh must fit the scene's post height, as it must fit the radius: a scene with
//! 1 nm or 1 m posts on the committed 2 µm-post mesh is refused with both values named.

mod common;

use common::run;
use static_contact::params::StaticParams;
use static_contact::scene::{GEOMETRY_MATCH_TOLERANCE, measured_post_height};
use static_contact::{ContactError, MeshChoice};

fn committed_mesh() -> std::path::PathBuf {
    static_contact::mesh_source::workspace_root()
        .join("meshes/slider-strip_p40um_d20um_n10_tet4_10k.msh")
}

fn on_committed_mesh(post_height_m: f64) -> StaticParams {
    StaticParams {
        mesh: MeshChoice::File(committed_mesh()),
        post_height_m,
        ..common::ten_post_tet4()
    }
}

#[test]
fn the_committed_strip_mesh_has_two_micrometre_posts() {
    let mesh = gmsh_mesh::read_msh(committed_mesh()).expect("committed mesh");
    let disks = static_contact::posts::find_tip_disks(&mesh, "post_tips").expect("tip disks");
    let h = measured_post_height(&mesh, &disks).expect("post height");
    assert!(
        (h / 2e-6 - 1.0).abs() < 1e-6,
        "measured post height {h} m, the mesh was made with h = 2 µm"
    );
}

#[test]
fn a_post_height_the_mesh_does_not_have_is_refused_with_both_values() {
    for wrong in [1e-9, 1.0] {
        match run(&on_committed_mesh(wrong)) {
            Err(ContactError::MeshMismatch { detail, .. }) => {
                assert!(
                    detail.contains("post_height_m")
                        && detail.contains(&format!("{wrong:.4e}"))
                        && detail.contains("2.0000e-6")
                        && detail.contains(&format!("{} %", GEOMETRY_MATCH_TOLERANCE * 100.0)),
                    "the error names the post height, both values and the tolerance: {detail}"
                );
            }
            other => panic!("post height {wrong} m on a 2 µm-post mesh must be refused: {other:?}"),
        }
    }
    run(&on_committed_mesh(2e-6)).expect("the mesh's own post height is accepted");
}
