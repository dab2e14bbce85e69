//! The condensed strip on the committed 10-post `slider-strip` mesh (Tet4, tips at a/4, 10 k
//! nodes; one wavelength long): contact conditions, symmetry, η against preload, outputs, errors.

mod common;

use common::run;
use nalgebra::DVector;
use static_contact::StaticAnalysis;
use static_contact::output::{write_force_chart, write_snapshot_vtu};
use static_contact::params::{MeshSizes, StaticParams};
use static_contact::scene::StripModel;
use static_contact::{ContactError, MeshChoice};

fn committed(file: &str) -> std::path::PathBuf {
    static_contact::mesh_source::workspace_root()
        .join("meshes")
        .join(file)
}

/// The default 100 × 100 slider, seen through a 10-post strip (its share of the preload).
fn ten_post_params(preload_sweep_n: Vec<f64>) -> StaticParams {
    StaticParams {
        mesh: MeshChoice::Auto,
        preload_sweep_n,
        ..common::ten_post_tet4()
    }
}

fn ten_post_run(preload_sweep_n: Vec<f64>) -> StaticAnalysis {
    run(&ten_post_params(preload_sweep_n)).expect("10-post strip on the committed mesh")
}

#[test]
fn the_automatic_mesh_choice_uses_the_committed_ten_post_strip() {
    let analysis = ten_post_run(Vec::new());
    assert!(
        analysis
            .report
            .mesh_file
            .ends_with("slider-strip_p40um_d20um_n10_tet4_10k.msh"),
        "mesh used: {}",
        analysis.report.mesh_file
    );
    assert_eq!(
        analysis.report.posts_in_strip, 10,
        "posts found in the strip"
    );
}

#[test]
fn on_a_flat_stator_mirror_posts_carry_equal_forces_that_sum_to_the_preload() {
    let analysis = ten_post_run(Vec::new());
    let flat = &analysis.report.preloads[0].flat_stator;
    let f: Vec<f64> = flat.posts.iter().map(|p| p.force_n).collect();
    let share = analysis.report.preloads[0].preload_strip_n;
    assert!(
        (f.iter().sum::<f64>() / share - 1.0).abs() < 1e-12,
        "post forces sum to the strip's preload share"
    );
    for i in 0..5 {
        // The strip is mirror-symmetric about its middle; the unstructured mesh is not exactly.
        assert!(
            (f[i] / f[9 - i] - 1.0).abs() < 0.01,
            "force on post {i} ({:.5e} N) vs its mirror post {} ({:.5e} N)",
            f[i],
            9 - i,
            f[9 - i]
        );
        assert!(f[i] > 0.0, "every post touches a flat stator: post {i}");
    }
    // A rigid-backed finite strip loads its end posts most (the rigid-punch edge effect).
    assert!(
        f[0] > f[4],
        "end post force {:.4e} N must exceed the middle post's {:.4e} N",
        f[0],
        f[4]
    );
    assert!(
        flat.load_sharing < 1.0 && flat.load_sharing > 0.9,
        "load sharing on a flat stator: {}",
        flat.load_sharing
    );
}

#[test]
fn wave_snapshot_forces_are_non_negative_and_act_only_on_the_active_set() {
    let analysis = ten_post_run(Vec::new());
    let c = &analysis.model.compliance_m_per_n;
    let amplitude = analysis.params.wave_amplitude_m;
    for snapshot in &analysis.report.preloads[0].snapshots {
        let f = DVector::from_iterator(10, snapshot.posts.iter().map(|p| p.force_n));
        let cf = c * &f;
        for (i, post) in snapshot.posts.iter().enumerate() {
            let gap = snapshot.reference_height_m - post.surface_height_m + cf[i];
            assert!(
                gap > -1e-9 * amplitude,
                "gap of post {i} at θ₀ = {:?}: {gap:.3e} m < 0 (penetration)",
                snapshot.phase_rad
            );
            assert!(
                post.force_n >= 0.0,
                "force of post {i} is tensile: {} N",
                post.force_n
            );
            if post.in_contact {
                assert!(
                    gap.abs() < 1e-9 * amplitude,
                    "active post {i} has a gap of {gap:.3e} m"
                );
            } else {
                assert_eq!(post.force_n, 0.0, "inactive post {i} carries a force");
            }
        }
        assert!(
            snapshot.complementarity_residual < 1e-9,
            "complementarity residual {}",
            snapshot.complementarity_residual
        );
        assert!(
            snapshot.contact_fraction > 0.0 && snapshot.contact_fraction < 1.0,
            "a 20 nm wave under 40 N lifts some posts off: contact fraction {}",
            snapshot.contact_fraction
        );
    }
}

#[test]
fn eta_is_at_most_one_and_falls_as_the_preload_grows() {
    let analysis = ten_post_run(vec![10.0, 100.0]);
    let mut by_preload: Vec<(f64, f64)> = analysis
        .report
        .preloads
        .iter()
        .map(|p| {
            (
                p.preload_n,
                p.effective_contact_ratio
                    .expect("η identifiable on a wave snapshot"),
            )
        })
        .collect();
    by_preload.sort_by(|a, b| a.0.total_cmp(&b.0));
    for w in by_preload.windows(2) {
        assert!(
            w[1].1 < w[0].1,
            "η must fall with preload: η({} N) = {:.4}, η({} N) = {:.4}",
            w[0].0,
            w[0].1,
            w[1].0,
            w[1].1
        );
    }
    for (p, eta) in &by_preload {
        assert!(
            *eta <= 1.0 && *eta > 0.0,
            "η({p} N) = {eta} must lie in (0, 1]"
        );
    }
}

#[test]
fn at_full_contact_the_fitted_eta_reaches_the_load_neutral_wave_response() {
    // 2000 N on the 100 × 100 slider puts every post of the strip in contact at every phase.
    let analysis = ten_post_run(vec![2000.0]);
    let full = analysis
        .report
        .preloads
        .iter()
        .find(|p| p.preload_n == 2000.0)
        .expect("the 2000 N preload");
    assert_eq!(full.contact_fraction, 1.0, "every post touches at 2000 N");
    let fitted = full
        .effective_contact_ratio
        .expect("η on the wave snapshot");
    let asymptote = analysis
        .report
        .eta_full_contact
        .expect("η at full contact of a regular compliance");
    // They differ only by the fit's sensitivity to the end posts' extra (mean-load) share.
    assert!(
        (fitted / asymptote - 1.0).abs() < 0.03,
        "fitted η at full contact {fitted:.4} against the load-neutral response {asymptote:.4}"
    );
    let at_40_n = analysis.report.effective_contact_ratio.expect("η at 40 N");
    assert!(
        at_40_n > asymptote,
        "η at 40 N ({at_40_n:.4}) lies above the full-contact asymptote ({asymptote:.4})"
    );
}

#[test]
fn snapshot_fields_and_the_force_chart_are_written() {
    let analysis = ten_post_run(Vec::new());
    let dir = tempfile::tempdir().unwrap();
    let vtu = dir.path().join("snapshot.vtu");
    let snapshot = &analysis.report.preloads[0].snapshots[0];
    write_snapshot_vtu(&analysis, snapshot, &vtu).unwrap();
    let text = std::fs::read_to_string(&vtu).unwrap();
    for field in [
        "displacement_m",
        "stress_zz_pa",
        "von_mises_pa",
        "contact_pressure_pa",
    ] {
        assert!(text.contains(field), "VTU has the point field {field}");
    }
    let files = write_force_chart(&analysis, 0, 0, &dir.path().join("forces")).unwrap();
    assert!(
        files
            .iter()
            .any(|f| f.extension().is_some_and(|e| e == "svg")),
        "chart SVG written: {files:?}"
    );
    let json = serde_json::to_value(&analysis.report).unwrap();
    for key in [
        "effective_contact_ratio",
        "load_sharing",
        "contact_fraction",
        "complementarity_residual",
        "post_forces_n",
    ] {
        assert!(json.get(key).is_some(), "report JSON has the key {key}");
    }
}

#[test]
fn a_mesh_without_post_tips_is_refused_naming_the_group() {
    let mesh = gmsh_mesh::read_msh(committed("punch_a10um_R20a_tet4_5k.msh")).unwrap();
    let err = StripModel::build(mesh, ten_post_params(Vec::new()).strip_config()).unwrap_err();
    assert!(
        matches!(err, ContactError::Mesh { .. }),
        "missing group must be a mesh error: {err}"
    );
    assert!(
        err.to_string().contains("post_tips"),
        "error names the missing group: {err}"
    );
}

#[test]
fn a_mesh_with_another_post_count_is_refused() {
    let params = StaticParams {
        strip_posts: Some(12),
        ..ten_post_params(Vec::new())
    };
    let params = StaticParams {
        mesh: MeshChoice::File(committed("slider-strip_p40um_d20um_n10_tet4_10k.msh")),
        ..params
    };
    let err = run(&params).unwrap_err();
    assert!(
        err.to_string().contains("10 tip disks") && err.to_string().contains("12 posts"),
        "error names both post counts: {err}"
    );
}

/// Needs gmsh and ≈ 1 min: `cargo test -p static-contact --release -- --ignored`.
#[test]
#[ignore]
fn eta_converges_under_mesh_refinement() {
    let etas: Vec<f64> = [1.0, 0.5, 0.25]
        .iter()
        .map(|&h| {
            let params = StaticParams {
                element_order: 2,
                mesh_sizes: MeshSizes {
                    h_post_over_radius: h,
                    ..MeshSizes::default()
                },
                ..ten_post_params(Vec::new())
            };
            run(&params)
                .expect("refined 10-post strip")
                .report
                .effective_contact_ratio
                .expect("η on the wave")
        })
        .collect();
    let (d1, d2) = (etas[0] - etas[1], etas[1] - etas[2]);
    assert!(
        d1 * d2 > 0.0 && d2.abs() < d1.abs(),
        "η must converge monotonically under refinement: {etas:?}"
    );
    let order = (d1 / d2).abs().log2();
    assert!(
        order > 0.5,
        "observed order of convergence of η: {order:.2} (η = {etas:?})"
    );
    println!("η at tip size a, a/2, a/4: {etas:?}, observed order {order:.2}");
}

#[test]
fn an_inverted_element_is_refused_naming_its_gmsh_tag() {
    let mut mesh =
        gmsh_mesh::read_msh(committed("slider-strip_p40um_d20um_n10_tet4_10k.msh")).unwrap();
    let first_slider_tet = mesh.group_tets("slider").unwrap()[0];
    let tag = mesh.tet_tags[first_slider_tet];
    match &mut mesh.tets {
        gmsh_mesh::Tets::Linear(tets) => tets[first_slider_tet].swap(0, 1),
        gmsh_mesh::Tets::Quadratic(_) => unreachable!("the committed strip is Tet4"),
    }
    let err = StripModel::build(mesh, ten_post_params(Vec::new()).strip_config()).unwrap_err();
    assert!(
        err.to_string().contains(&format!("gmsh tag {tag}")),
        "error names the inverted element's gmsh tag {tag}: {err}"
    );
}
