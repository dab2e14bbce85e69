//! The one-row strip meshed as its half y ≤ W/2 (`slider-strip.geo` `half_y = 1`, mirror plane
//! through the post axes) has the whole strip's solution: the same normal and tangential tip
//! compliances up to the two meshes' difference, with half disks found and their force halved.
//! Needs gmsh (two 10-post Tet4 strips, a few seconds).

mod common;

use nalgebra::DMatrix;
use static_contact::mesh_source::{generate_mesh, strip_mesh_parameters};
use static_contact::params::{MeshChoice, StaticParams};
use static_contact::prepare_strip;

/// Meshes the 10-post strip whole (`half_y` 0) or half (1) into `dir`, whole along x (a given
/// mesh file is used as it is, never reflected).
fn mesh(dir: &std::path::Path, half_y: f64) -> std::path::PathBuf {
    let mut setnumbers = strip_mesh_parameters(&common::ten_post_tet4());
    for (name, value) in &mut setnumbers {
        match *name {
            "half_y" => *value = half_y,
            "mirror_x" => *value = 0.0,
            _ => {}
        }
    }
    let out = dir.join(format!("strip-half{half_y}.msh"));
    generate_mesh("slider-strip", &out, &setnumbers).expect("gmsh meshes the 10-post strip");
    out
}

fn relative_difference(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).amax() / b.amax()
}

#[test]
fn the_half_strip_has_the_whole_strips_tip_compliances() {
    let dir = tempfile::tempdir().expect("scratch folder");
    let run = |half_y: f64| {
        let params = StaticParams {
            mesh: MeshChoice::File(mesh(dir.path(), half_y)),
            ..common::ten_post_tet4()
        };
        prepare_strip(&params).expect("strip model")
    };
    let (whole, half) = (run(0.0), run(1.0));
    assert!(
        half.model.slider.stats.reduced_unknowns < whole.model.slider.stats.reduced_unknowns,
        "the half strip has fewer unknowns ({} vs {})",
        half.model.slider.stats.reduced_unknowns,
        whole.model.slider.stats.reduced_unknowns
    );
    for (h, w) in half.model.posts.iter().zip(&whole.model.posts) {
        assert!(
            (h.x_m - w.x_m).abs() < 1e-9 && (h.y_m - w.y_m).abs() < 1e-9 && h.row == w.row,
            "post centre of the half disk {h:?} equals the whole disk's {w:?}"
        );
    }
    let normal = relative_difference(
        &half.model.slider.compliance_m_per_n,
        &whole.model.slider.compliance_m_per_n,
    );
    let (th, tw) = (
        half.model.tip_compliance().expect("half strip tangential"),
        whole
            .model
            .tip_compliance()
            .expect("whole strip tangential"),
    );
    let tangential = relative_difference(&th.tangential_m_per_n, &tw.tangential_m_per_n);
    eprintln!(
        "half vs whole strip: slider normal compliance {normal:.2e}, tangential {tangential:.2e}"
    );
    // Two different meshes of the same strip at the same sizes: they differ by the
    // discretisation error, ≈ 1 % here; a wrong force share would be 100 %.
    assert!(
        normal < 0.03,
        "slider normal tip compliance, half vs whole strip: {normal:.3e} relative"
    );
    assert!(
        tangential < 0.03,
        "tangential tip compliance, half vs whole strip: {tangential:.3e} relative"
    );
}
