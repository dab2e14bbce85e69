//! The automatic strip mesh of an even number of posts is gmsh's half x ≤ L/2 reflected in Rust
//! (`slider-strip.geo` `mirror_x`, `gmsh_mesh::mirror`): its model is exactly symmetric about the
//! strip's middle (post i and post n − 1 − i have the same compliances to round-off), and it has
//! the compliances of the strip gmsh meshes whole, up to the two meshes' difference. An odd
//! number of posts is meshed whole, and a half strip given as a file is refused with what it is.
//! Needs gmsh (two 10-post Tet4 strips, a few seconds).

use nalgebra::DMatrix;
use static_contact::mesh_source::{generate_mesh, resolve_mesh_verified, strip_mesh_parameters};
use static_contact::params::{MeshChoice, MeshSizes, StaticParams};
use static_contact::prepare_strip;

/// A 10-post Tet4 strip (tip edges a/2: coarse and quick) meshed into `cache`; no committed
/// mesh has these sizes.
fn strip(cache: &std::path::Path, posts: usize) -> StaticParams {
    StaticParams {
        strip_posts: Some(posts),
        element_order: 1,
        mesh_sizes: MeshSizes {
            h_post_over_radius: 0.5,
            ..MeshSizes::default()
        },
        mesh_cache_dir: Some(cache.to_path_buf()),
        ..StaticParams::default()
    }
}

fn relative_difference(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).amax() / b.amax()
}

#[test]
fn an_even_strip_is_reflected_from_its_half_and_an_odd_one_meshed_whole() {
    let dir = tempfile::tempdir().expect("scratch folder");
    let even = resolve_mesh_verified(&strip(dir.path(), 10)).expect("gmsh meshes the strip");
    assert!(even.mirror.is_some(), "10 posts: the half is meshed");
    let half = gmsh_mesh::read_msh(&even.path).expect("half strip file");
    assert!(half.group("slider_mirror_x").is_some() && half.group("slider_x1").is_none());
    let whole = even.read().expect("reflected strip");
    assert!(whole.group("slider_x1").is_some() && whole.group("slider_mirror_x").is_none());
    assert_eq!(whole.tets.len(), 2 * half.tets.len());
    let odd = resolve_mesh_verified(&strip(dir.path(), 9)).expect("gmsh meshes the strip");
    assert!(odd.mirror.is_none(), "9 posts: meshed whole");
    // The half file given to a run is used as it is, and refused with what it is.
    let error = prepare_strip(&StaticParams {
        mesh: MeshChoice::File(even.path.clone()),
        ..strip(dir.path(), 10)
    })
    .expect_err("a half strip for a 10-post run")
    .to_string();
    assert!(
        error.contains("5 tip disks") && error.contains("mirror_x = 1"),
        "{error}"
    );
}

#[test]
fn the_reflected_strip_is_symmetric_and_has_the_whole_strips_tip_compliances() {
    let dir = tempfile::tempdir().expect("scratch folder");
    let mirrored = prepare_strip(&strip(dir.path(), 10)).expect("reflected strip model");
    // The same strip meshed whole by gmsh, given as a file (used as it is).
    let mut setnumbers = strip_mesh_parameters(&strip(dir.path(), 10));
    for (name, value) in &mut setnumbers {
        if *name == "mirror_x" {
            *value = 0.0;
        }
    }
    let file = dir.path().join("whole.msh");
    generate_mesh("slider-strip", &file, &setnumbers).expect("gmsh meshes the whole strip");
    let whole = prepare_strip(&StaticParams {
        mesh: MeshChoice::File(file),
        ..strip(dir.path(), 10)
    })
    .expect("whole strip model");

    let c = &mirrored.model.slider.compliance_m_per_n;
    let n = c.nrows();
    assert_eq!(n, 10);
    let reversed = DMatrix::from_fn(n, n, |i, j| c[(n - 1 - i, n - 1 - j)]);
    let asymmetry = relative_difference(&reversed, c);
    let mesh_difference = relative_difference(c, &whole.model.slider.compliance_m_per_n);
    eprintln!(
        "reflected strip: asymmetry {asymmetry:.2e}, against the whole mesh {mesh_difference:.2e}"
    );
    assert!(
        asymmetry < 1e-9,
        "post i and post n-1-i of the reflected strip differ by {asymmetry:.3e} relative"
    );
    // Two meshes of one strip at the same sizes differ by the discretisation error (≈ 1 %); a
    // wrongly joined half (a cut left open, a face turned inward) would change it by far more.
    assert!(
        mesh_difference < 0.03,
        "reflected against whole strip: {mesh_difference:.3e} relative"
    );
}
