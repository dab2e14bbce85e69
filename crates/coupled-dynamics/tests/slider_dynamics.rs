//! The whole slider's coupled model against the strip's, and its own books: a one-row slider is
//! the strip model on the same compliances; an ideal lattice periodic in y reproduces the strip
//! exactly (every row the same); the energy balance closes and the maps add up to the point's
//! totals under scatter; friction's two limits (locked posts, no friction).

mod common;

use std::sync::Arc;

use coupled_dynamics::{
    CoupledModel, CoupledScene, RigidBackContact, SliderDynamics, SliderScene, solve,
};
use nalgebra::DMatrix;
use slider_contact::{
    LatticeGeometry, LatticeKernel, NearField, OperatorSpec, SliderModel, SliderParams,
    TangentialKernel,
};
use stick_slip::Wave;

use common::{PITCH_M, PRELOAD_PER_POST_N, periodic, rel, spec, tight};

fn slider_scene(geometry: LatticeGeometry, offsets: Vec<f64>) -> SliderScene {
    let n = geometry.len();
    SliderScene {
        geometry,
        post_offset_m: offsets,
        wave: Wave::paper_default(),
        mu_static: 0.35,
        mu_kinetic: 0.3,
        preload_n: PRELOAD_PER_POST_N * n as f64,
        wave_direction: coupled_dynamics::WaveDirection::PlusX,
        steps_per_period: 64,
        start_phase_rad: 0.0,
        curve_points: 5,
        tolerance: 1e-12,
        amplitude_scale: Vec::new(),
    }
}

/// The rigid-back normal contact of `s`'s lattice on its dense normal operator, at the tight
/// CG tolerance and the paper wave's 20 nm length scale.
fn rigid_back(s: &OperatorSpec) -> RigidBackContact<DMatrix<f64>> {
    RigidBackContact {
        operator: LatticeKernel::new(s).unwrap().to_dense(),
        options: tight(),
        length_scale_m: 20e-9,
    }
}

/// A 1 × 16 slider (one row, rigid back, no scatter) through the whole slider's path (lattice
/// operators by FFT, slider-contact's CG per phase, the matrix-free box QP) against the strip
/// model on the dense matrices of the same kernels (static-contact's active set, the factored
/// box QP). Measured: stall thrust, no-load speed and every curve point within 2e-9.
#[test]
fn a_one_row_slider_is_the_strip_model_on_the_same_compliances() {
    let s = spec(16, 1);
    let params = SliderParams {
        posts_x: 16,
        posts_y: 1,
        post_pitch_m: PITCH_M,
        slider_length_m: 16.0 * PITCH_M,
        slider_width_m: PITCH_M,
        preload_n: 16.0 * PRELOAD_PER_POST_N,
        solver: tight(),
        ..SliderParams::default()
    };
    let static_model = SliderModel::build(&params).unwrap();
    let scene = slider_scene(s.geometry, static_model.post_offset_m.clone());
    let slider = SliderDynamics::for_slider(&scene, &static_model, NearField::Johnson).unwrap();
    let ours = slider.solve(None).unwrap();

    let mut strip = scene.coupled_settings();
    strip.normal_compliance_m_per_n = LatticeKernel::new(&s).unwrap().to_dense();
    strip.tangential_compliance_m_per_n = TangentialKernel::new(&s, NearField::Johnson)
        .unwrap()
        .to_dense();
    let reference = solve(&CoupledModel::new(&strip).unwrap(), None).unwrap();
    compare(&ours.coupled, &reference, 2e-9, "one-row slider vs strip");
    assert_eq!(ours.dundurs_beta.map(|b| b > 0.02 && b < 0.022), Some(true));
}

fn compare(
    a: &coupled_dynamics::CoupledResult,
    b: &coupled_dynamics::CoupledResult,
    tol: f64,
    what: &str,
) {
    let curve = a
        .curve
        .iter()
        .zip(&b.curve)
        .map(|(p, q)| (p.thrust_n - q.thrust_n).abs() / b.stall_thrust_n)
        .fold(0.0, f64::max);
    println!(
        "{what}: stall {:.12} vs {:.12} N ({:.1e}), no-load {:.12} vs {:.12} m/s ({:.1e}), curve {curve:.1e} of the stall thrust",
        a.stall_thrust_n,
        b.stall_thrust_n,
        rel(a.stall_thrust_n, b.stall_thrust_n),
        a.no_load_speed_m_per_s,
        b.no_load_speed_m_per_s,
        rel(a.no_load_speed_m_per_s, b.no_load_speed_m_per_s)
    );
    assert!(
        rel(a.stall_thrust_n, b.stall_thrust_n) < tol,
        "{what}: stall thrust {} vs {}",
        a.stall_thrust_n,
        b.stall_thrust_n
    );
    assert!(
        rel(a.no_load_speed_m_per_s, b.no_load_speed_m_per_s) < tol,
        "{what}: no-load speed {} vs {}",
        a.no_load_speed_m_per_s,
        b.no_load_speed_m_per_s
    );
    for (p, q) in a.curve.iter().zip(&b.curve) {
        assert!(
            (p.thrust_n - q.thrust_n).abs() < tol * b.stall_thrust_n,
            "{what}: thrust at {} m/s: {} vs {}",
            p.speed_m_per_s,
            p.thrust_n,
            q.thrust_n
        );
        assert!(
            (p.stator_power_w - q.stator_power_w).abs() < 1e-6 * q.stator_power_w.abs().max(1e-9),
            "{what}: stator power at {} m/s: {} vs {}",
            p.speed_m_per_s,
            p.stator_power_w,
            q.stator_power_w
        );
    }
}

/// An ideal 10 × 5 lattice periodic in y (both compliances circulant over the rows) gives every
/// row the strip's forces: the strip of one row with the row-summed compliances and a fifth of
/// the preload. The identity is exact in exact arithmetic (each instant's normal problem and each
/// step's box QP are strictly convex, so their unique solutions share the lattice's symmetry);
/// measured agreement ≤ 2e-9 (the iterative solves' tolerance).
#[test]
fn an_ideal_periodic_lattice_reproduces_the_strip_exactly() {
    let (nx, ny) = (10, 5);
    let s = spec(nx, 41);
    let normal_kernel = LatticeKernel::new(&s).unwrap();
    let tangential_kernel = TangentialKernel::new(&s, NearField::Johnson).unwrap();
    let cn = periodic(|a, b| normal_kernel.at_offset(a, b), nx, ny, 4);
    let ct = periodic(|a, b| tangential_kernel.at_offset(a, b), nx, ny, 4);
    assert!(
        cn.clone().cholesky().is_some() && ct.clone().cholesky().is_some(),
        "SPD"
    );
    let geometry = spec(nx, ny).geometry;
    let scene = slider_scene(geometry, vec![0.0; nx * ny]);
    let normal = RigidBackContact {
        operator: cn.clone(),
        options: tight(),
        length_scale_m: scene.wave.normal_amplitude_m,
    };
    let slider = SliderDynamics::new(&scene, &normal, Arc::new(ct.clone())).unwrap();
    let ours = slider.solve(None).unwrap();

    // The strip: row 0's posts, compliance to all rows loaded alike.
    let row_sum = |c: &DMatrix<f64>| {
        DMatrix::from_fn(nx, nx, |i, k| {
            (0..ny).map(|l| c[(i * ny, k * ny + l)]).sum()
        })
    };
    let x: Vec<f64> = (0..nx).map(|i| geometry.x_m(i)).collect();
    let mut strip = CoupledScene {
        post_x_m: x,
        normal_compliance_m_per_n: row_sum(&cn),
        tangential_compliance_m_per_n: row_sum(&ct),
        strip_share: 1.0 / ny as f64,
        ..scene.coupled_settings()
    };
    strip.amplitude_scale.clear();
    let reference = solve(&CoupledModel::new(&strip).unwrap(), None).unwrap();
    compare(&ours.coupled, &reference, 2e-9, "periodic lattice vs strip");
    // Every row carries the same mean force.
    let map = &ours.maps[1];
    for i in 0..nx {
        let row = &map.means.mean_normal_force_n[i * ny..(i + 1) * ny];
        let spread = row.iter().fold(0.0f64, |m, f| m.max((f - row[0]).abs()));
        assert!(
            spread <= 1e-9 * PRELOAD_PER_POST_N,
            "column {i}: mean normal forces of the rows differ by {spread:e} N"
        );
    }
}

/// Under post-height scatter (every post different) the stepped energy books close, the maps add
/// up to the point's totals and the preload is carried at every instant.
#[test]
fn the_energy_balance_closes_and_the_maps_add_up_under_scatter() {
    let params = SliderParams {
        posts_x: 12,
        posts_y: 6,
        post_pitch_m: PITCH_M,
        slider_length_m: 12.0 * PITCH_M,
        slider_width_m: 6.0 * PITCH_M,
        preload_n: 72.0 * PRELOAD_PER_POST_N,
        imperfections: motor::Imperfections {
            height_scatter_m: 3e-9,
            ..motor::Imperfections::default()
        },
        solver: tight(),
        ..SliderParams::default()
    };
    let static_model = SliderModel::build(&params).unwrap();
    assert!(
        static_model.post_offset_m.iter().any(|d| d.abs() > 1e-9),
        "the scatter reaches the posts"
    );
    let mut scene = SliderScene::for_static(&static_model, Wave::paper_default(), 0.35, 0.3);
    scene.steps_per_period = 64;
    scene.curve_points = 4;
    let slider = SliderDynamics::for_slider(&scene, &static_model, NearField::Johnson).unwrap();
    let result = slider.solve(None).unwrap();
    assert!(result.coupled.stall_thrust_n > 0.0, "the slider is driven");
    assert!(
        result.coupled.energy_balance_residual < 1e-9,
        "energy balance residual {}",
        result.coupled.energy_balance_residual
    );
    for map in &result.maps {
        let p = &map.point;
        assert!(
            (p.stator_power_w - p.output_power_w - p.friction_dissipation_w).abs()
                <= 1e-9 * p.stator_power_w.abs().max(p.friction_dissipation_w),
            "stator = output + friction at {} m/s",
            p.speed_m_per_s
        );
        assert!(
            rel(map.total_friction_power_w(), p.friction_dissipation_w) < 1e-6,
            "Σ post friction power {} vs friction dissipation {}",
            map.total_friction_power_w(),
            p.friction_dissipation_w
        );
        let stator: f64 = map.means.stator_power_w.iter().sum();
        assert!(
            rel(stator, p.stator_power_w) < 1e-6,
            "Σ post stator power {stator} vs {}",
            p.stator_power_w
        );
        let carried: f64 = map.means.mean_normal_force_n.iter().sum();
        assert!(
            rel(carried, scene.preload_n) < 1e-9,
            "time-mean normal forces carry {carried} N of {} N",
            scene.preload_n
        );
        assert!(
            map.means
                .friction_power_w
                .iter()
                .all(|w| *w >= -1e-12 * p.friction_dissipation_w),
            "friction power is dissipated at every post"
        );
    }
    for j in 0..scene.steps_per_period {
        let total = slider.model().strip_normal_force_n(j);
        assert!(
            rel(total, scene.preload_n) < 1e-9,
            "Σ N at grid phase {j}: {total}"
        );
    }
}

/// Friction's limits on the whole slider: with μ → 0 nothing is transmitted (thrust ≤ μP, every
/// post in contact slips); with a large μ the posts stick wherever they touch at stall.
#[test]
fn friction_limits_no_thrust_without_friction_and_sticking_posts_with_much() {
    let g = spec(8, 3).geometry;
    let kernel_n = LatticeKernel::new(&spec(8, 3)).unwrap();
    let normal = RigidBackContact {
        operator: kernel_n.to_dense(),
        options: tight(),
        length_scale_m: 20e-9,
    };
    let ct = TangentialKernel::new(&spec(8, 3), NearField::Johnson)
        .unwrap()
        .operator();
    let ct = Arc::new(ct);
    let mut scene = slider_scene(g, vec![0.0; g.len()]);
    scene.mu_static = 1e-6;
    scene.mu_kinetic = 1e-6;
    let slick = SliderDynamics::new(&scene, &normal, ct.clone()).unwrap();
    let stall = slick.maps_at(0.0).unwrap();
    assert!(
        stall.point.thrust_n.abs() <= 1e-6 * scene.preload_n * (1.0 + 1e-9),
        "thrust {} exceeds μP",
        stall.point.thrust_n
    );
    for (k, (s, c)) in stall
        .means
        .slip_fraction
        .iter()
        .zip(&stall.means.contact_fraction)
        .enumerate()
    {
        assert!(
            *c == 0.0 || *s > 0.9,
            "post {k} slips {s} of its contact time with μ → 0"
        );
    }
    scene.mu_static = 50.0;
    scene.mu_kinetic = 50.0;
    let locked = SliderDynamics::new(&scene, &normal, ct).unwrap();
    let stall = locked.maps_at(0.0).unwrap();
    assert!(
        stall.point.stick_fraction > 0.95,
        "stick fraction {} with μ = 50",
        stall.point.stick_fraction
    );
}

/// An ideal square slider (rigid back, no offsets) against the strip of its middle row on the
/// same compliances (`middle_row_strip`): they differ only by the edge effect, the rows near the
/// y edges carrying differently. Measured on 16 × 16 posts (64 steps, 4 curve points): stall
/// thrust +0.49 %, no-load speed +0.74 %; the default 100 × 100 slider (example `whole_slider`,
/// 0.5 mm margins): −0.32 %, −0.36 %.
fn ideal_slider_against_its_middle_row(side: usize, points: usize) -> (f64, f64) {
    let params = SliderParams {
        posts_x: side,
        posts_y: side,
        post_pitch_m: PITCH_M,
        slider_length_m: side as f64 * PITCH_M + 1e-3,
        slider_width_m: side as f64 * PITCH_M + 1e-3,
        preload_n: (side * side) as f64 * PRELOAD_PER_POST_N,
        ..SliderParams::default()
    };
    let static_model = SliderModel::build(&params).unwrap();
    let mut scene = SliderScene::for_static(&static_model, Wave::paper_default(), 0.3, 0.3);
    scene.steps_per_period = 64;
    scene.curve_points = points;
    let slider = SliderDynamics::for_slider(&scene, &static_model, NearField::Johnson).unwrap();
    let whole = slider.solve(None).unwrap().coupled;
    let tangential = slider_contact::LatticeOperator::tangential(
        &static_model.params.operator_spec(),
        NearField::Johnson,
    )
    .unwrap();
    let strip =
        coupled_dynamics::slider::middle_row_strip(&scene, &static_model.operator, &tangential)
            .unwrap();
    let row = solve(&CoupledModel::new(&strip).unwrap(), None).unwrap();
    let (ds, dv) = (
        whole.stall_thrust_n / row.stall_thrust_n - 1.0,
        whole.no_load_speed_m_per_s / row.no_load_speed_m_per_s - 1.0,
    );
    println!(
        "{side} × {side}: whole slider {:.5} N, {:.5} m/s; middle-row strip {:.5} N, {:.5} m/s ({:+.2} %, {:+.2} %)",
        whole.stall_thrust_n,
        whole.no_load_speed_m_per_s,
        row.stall_thrust_n,
        row.no_load_speed_m_per_s,
        100.0 * ds,
        100.0 * dv
    );
    (ds, dv)
}

#[test]
fn an_ideal_slider_agrees_with_its_middle_row_strip_within_the_edge_effect() {
    let (ds, dv) = ideal_slider_against_its_middle_row(16, 4);
    assert!(
        ds.abs() < 0.02,
        "stall thrust: whole slider vs middle row {ds:+.4}"
    );
    assert!(
        dv.abs() < 0.02,
        "no-load speed: whole slider vs middle row {dv:+.4}"
    );
}

/// The default 100 × 100 slider against its middle row (≈ 10 min in the test profile on 2
/// cores): `cargo test -p coupled-dynamics --test slider_dynamics -- --ignored --nocapture`.
#[test]
#[ignore]
fn the_default_slider_agrees_with_its_middle_row_strip_within_the_edge_effect() {
    let (ds, dv) = ideal_slider_against_its_middle_row(100, 4);
    assert!(
        ds.abs() < 0.02,
        "stall thrust: whole slider vs middle row {ds:+.4}"
    );
    assert!(
        dv.abs() < 0.02,
        "no-load speed: whole slider vs middle row {dv:+.4}"
    );
}

/// The per-post amplitude factor (the energy-conserving wave's α_i, `amplitude_scale`): α = 1 at
/// every post is the constant wave bit for bit; a weaker wave under half of the posts lowers the
/// stall thrust and the power they draw, and the posts under it draw less each.
#[test]
fn the_per_post_amplitude_scales_the_local_wave() {
    let s = spec(8, 3);
    let normal = rigid_back(&s);
    let ct = Arc::new(
        TangentialKernel::new(&s, NearField::Johnson)
            .unwrap()
            .operator(),
    );
    let mut scene = slider_scene(s.geometry, vec![0.0; 24]);
    let constant = SliderDynamics::new(&scene, &normal, ct.clone())
        .unwrap()
        .maps_at(0.0)
        .unwrap();
    scene.amplitude_scale = vec![1.0; 24];
    let unit = SliderDynamics::new(&scene, &normal, ct.clone())
        .unwrap()
        .maps_at(0.0)
        .unwrap();
    assert_eq!(
        unit.point.thrust_n.to_bits(),
        constant.point.thrust_n.to_bits(),
        "α = 1 is the constant wave"
    );
    // The second half along x (columns 4…7) under a wave of 0.6 A₀.
    scene.amplitude_scale = (0..24)
        .map(|k| if k / 3 >= 4 { 0.6 } else { 1.0 })
        .collect();
    let weak = SliderDynamics::new(&scene, &normal, ct)
        .unwrap()
        .maps_at(0.0)
        .unwrap();
    assert!(
        weak.point.thrust_n < constant.point.thrust_n,
        "stall thrust {} under the weaker wave vs {}",
        weak.point.thrust_n,
        constant.point.thrust_n
    );
    let drawn = |m: &coupled_dynamics::SliderMaps, cols: std::ops::Range<usize>| -> f64 {
        cols.flat_map(|i| (0..3).map(move |j| i * 3 + j))
            .map(|k| m.means.stator_power_w[k])
            .sum()
    };
    assert!(
        drawn(&weak, 4..8) < drawn(&constant, 4..8),
        "posts under the weaker wave draw {} W vs {} W",
        drawn(&weak, 4..8),
        drawn(&constant, 4..8)
    );
}

/// The y-mirror of an ideal slider: detected (and not under scatter), and the folded model on
/// half the posts gives the model on every post — stall thrust, no-load speed, every curve
/// point, the maps of every post and the middle row's histories — to 1e-10.
#[test]
fn the_mirror_folded_slider_is_the_slider_on_every_post() {
    let side = (10, 8);
    let params = SliderParams {
        posts_x: side.0,
        posts_y: side.1,
        post_pitch_m: PITCH_M,
        slider_length_m: side.0 as f64 * PITCH_M + 1e-3,
        slider_width_m: side.1 as f64 * PITCH_M + 1e-3,
        preload_n: (side.0 * side.1) as f64 * PRELOAD_PER_POST_N,
        solver: tight(),
        ..SliderParams::default()
    };
    let static_model = SliderModel::build(&params).unwrap();
    let mut scene = SliderScene::for_static(&static_model, Wave::paper_default(), 0.35, 0.3);
    scene.curve_points = 4;
    scene.tolerance = 1e-13;
    let folded =
        SliderDynamics::for_slider_with(&scene, &static_model, NearField::Johnson, true).unwrap();
    let full =
        SliderDynamics::for_slider_with(&scene, &static_model, NearField::Johnson, false).unwrap();
    assert_eq!(
        folded.mirror().map(|m| m.len()),
        Some(40),
        "the ideal slider's mirror is detected and halves the posts"
    );
    assert!(full.mirror().is_none(), "the mirror can be switched off");
    let (a, b) = (folded.solve(None).unwrap(), full.solve(None).unwrap());
    compare(&a.coupled, &b.coupled, 1e-10, "mirror-folded vs every post");
    assert_eq!(a.coupled.posts, 80, "every post is counted");
    for (ma, mb) in a.maps.iter().zip(&b.maps) {
        for (field, x, y) in [
            (
                "friction power",
                &ma.means.friction_power_w,
                &mb.means.friction_power_w,
            ),
            (
                "stator power",
                &ma.means.stator_power_w,
                &mb.means.stator_power_w,
            ),
            (
                "mean normal force",
                &ma.means.mean_normal_force_n,
                &mb.means.mean_normal_force_n,
            ),
            (
                "slip fraction",
                &ma.means.slip_fraction,
                &mb.means.slip_fraction,
            ),
        ] {
            let scale = y.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
            let worst = x
                .iter()
                .zip(y)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            assert!(
                worst <= 1e-10 * scale,
                "{field} at {} m/s: folded vs full differ by {worst:e} of {scale:e}",
                ma.means.speed_m_per_s
            );
        }
    }
    assert_eq!(a.history_posts, b.history_posts, "the middle row's posts");
    let scale = b
        .histories
        .tangential_force_n
        .iter()
        .flatten()
        .fold(0.0, |m: f64, v| m.max(v.abs()));
    for (x, y) in a
        .histories
        .tangential_force_n
        .iter()
        .zip(&b.histories.tangential_force_n)
    {
        for (p, q) in x.iter().zip(y) {
            assert!(
                (p - q).abs() <= 1e-10 * scale,
                "history tangential force {p} vs {q}"
            );
        }
    }

    let mut scattered = params.clone();
    scattered.imperfections.height_scatter_m = 2e-9;
    let static_model = SliderModel::build(&scattered).unwrap();
    let mut scene = SliderScene::for_static(&static_model, Wave::paper_default(), 0.35, 0.3);
    scene.curve_points = 3;
    let slider = SliderDynamics::for_slider(&scene, &static_model, NearField::Johnson).unwrap();
    assert!(
        slider.mirror().is_none(),
        "height scatter breaks the mirror"
    );
}

/// A lattice whose coupled model would not fit in memory is refused before anything is
/// allocated (its post offsets are not even read), naming its size and the limit.
#[test]
fn a_lattice_too_large_for_memory_is_refused_by_its_size_and_the_limit() {
    let g = spec(3000, 3000).geometry;
    let scene = slider_scene(g, Vec::new());
    let normal = RigidBackContact {
        operator: DMatrix::<f64>::identity(1, 1),
        options: tight(),
        length_scale_m: 20e-9,
    };
    let err = SliderDynamics::new(&scene, &normal, Arc::new(DMatrix::<f64>::identity(1, 1)))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("3000 × 3000 posts") && err.contains("GB") && err.contains("limit of 4.0 GB"),
        "{err}"
    );
    assert!(scene.model_bytes() > coupled_dynamics::slider::MAX_SLIDER_MODEL_BYTES);
    let paper = slider_scene(spec(100, 100).geometry, Vec::new());
    assert!(
        paper.model_bytes() < 1e8,
        "the paper's slider needs {} bytes",
        paper.model_bytes()
    );
}

/// A step whose box QP cannot be solved (here a tangential compliance that is not positive
/// definite) is reported with its speed, its grid step and the lattice post that did not
/// settle.
#[test]
fn a_step_that_does_not_converge_names_its_step_and_its_post() {
    let s = spec(4, 3);
    let normal = rigid_back(&s);
    let not_spd = DMatrix::<f64>::identity(12, 12) * -1e-9;
    let scene = slider_scene(s.geometry, vec![0.0; 12]);
    let slider = SliderDynamics::new(&scene, &normal, Arc::new(not_spd)).unwrap();
    let err = slider.model().at_speed(0.0).unwrap_err().to_string();
    assert!(
        err.contains("frictional contact step")
            && err.contains("grid step 0")
            && err.contains("post (")
            && err.contains("of the lattice"),
        "{err}"
    );
}
