//! The whole slider on the energy-conserving wave: an ideal lattice periodic in y reproduces
//! the strip's attenuated curve (every row one lane carrying P_in/n_y); the y-mirror fold gives
//! the model on every post (a folded row carries a row and its image); under scatter the books
//! close at every point and every post's amplitude is the one its lane leaves it.

mod common;

use std::sync::Arc;

use coupled_dynamics::{
    AttenuationOptions, CoupledScene, RigidBackContact, SliderDynamics, SliderScene,
    solve_attenuated,
};
use nalgebra::DMatrix;
use slider_contact::{LatticeKernel, NearField, SliderModel, SliderParams, TangentialKernel};
use stick_slip::Wave;

use common::{PITCH_M, PRELOAD_PER_POST_N, geometry, periodic, rel, spec, tight};

/// Options whose P_in is `fraction` of the constant wave's stall draw `stall_draw_w`: the wave
/// runs low under the slider.
fn options(stall_draw_w: f64, fraction: f64) -> AttenuationOptions {
    AttenuationOptions::new(fraction * stall_draw_w)
}

/// An ideal 10 × 5 lattice periodic in y on the energy-conserving wave: every row is one lane
/// with P_in/5 and the same posts, so the slider is the strip of one row (row-summed
/// compliances, a fifth of the preload, one lane with P_in) on the same wave. The fixed point
/// to 1e-8 (the default 1e-6 lets the slider's trial profiles, whose normal grids are solved to
/// their own accuracy, end ≈ 6e-7 from the strip's in no-load speed). Measured: stall,
/// no-load speed and the curve within 1e-7, every post's amplitude within 1e-7.
#[test]
fn an_ideal_periodic_lattice_on_the_energy_conserving_wave_reproduces_the_strip() {
    let (nx, ny) = (10, 5);
    let s = spec(nx, 41);
    let normal_kernel = LatticeKernel::new(&s).unwrap();
    let tangential_kernel = TangentialKernel::new(&s, NearField::Johnson).unwrap();
    let cn = periodic(|a, b| normal_kernel.at_offset(a, b), nx, ny, 4);
    let ct = periodic(|a, b| tangential_kernel.at_offset(a, b), nx, ny, 4);
    let n = nx * ny;
    let scene = SliderScene {
        geometry: geometry(nx, ny),
        post_offset_m: vec![0.0; n],
        wave: Wave::paper_default(),
        mu_static: 0.35,
        mu_kinetic: 0.3,
        preload_n: PRELOAD_PER_POST_N * n as f64,
        wave_direction: coupled_dynamics::WaveDirection::PlusX,
        steps_per_period: 64,
        start_phase_rad: 0.0,
        curve_points: 4,
        tolerance: 1e-12,
        amplitude_scale: Vec::new(),
    };
    let normal = RigidBackContact {
        operator: cn.clone(),
        options: tight(),
        length_scale_m: scene.wave.normal_amplitude_m,
    };
    let slider = SliderDynamics::new(&scene, &normal, Arc::new(ct.clone())).unwrap();
    let draw = slider.model().at_speed(0.0).unwrap().stator_power_w;
    let mut o = options(draw, 1.2);
    o.tolerance = 1e-8;
    let ours = slider.solve_attenuated(&normal, &o).unwrap();

    let row_sum = |c: &DMatrix<f64>| {
        DMatrix::from_fn(nx, nx, |i, k| {
            (0..ny).map(|l| c[(i * ny, k * ny + l)]).sum()
        })
    };
    let strip = CoupledScene {
        post_x_m: (0..nx).map(|i| scene.geometry.x_m(i)).collect(),
        normal_compliance_m_per_n: row_sum(&cn),
        tangential_compliance_m_per_n: row_sum(&ct),
        strip_share: 1.0 / ny as f64,
        ..scene.coupled_settings()
    };
    let reference = solve_attenuated(&strip, &o).unwrap();
    let (a, b) = (&ours.curve, &reference);
    println!(
        "stall {} vs {} N, no-load {} vs {} m/s, trailing amplitude at stall {}",
        a.stall_thrust_n,
        b.stall_thrust_n,
        a.no_load_speed_m_per_s,
        b.no_load_speed_m_per_s,
        b.curve[0].amplitude_scale[nx - 1]
    );
    assert!(
        b.curve[0].amplitude_scale[nx - 1] < 0.9,
        "the wave runs low under the slider"
    );
    assert!(
        rel(a.stall_thrust_n, b.stall_thrust_n) < 1e-7,
        "stall thrust"
    );
    assert!(
        rel(a.no_load_speed_m_per_s, b.no_load_speed_m_per_s) < 1e-7,
        "no-load speed"
    );
    for (p, q) in a.curve.iter().zip(&b.curve) {
        assert!(
            (p.point.thrust_n - q.point.thrust_n).abs() < 1e-7 * b.stall_thrust_n,
            "thrust at {} m/s: {} vs {}",
            q.point.speed_m_per_s,
            p.point.thrust_n,
            q.point.thrust_n
        );
        for i in 0..nx {
            for j in 0..ny {
                let (x, y) = (p.amplitude_scale[i * ny + j], q.amplitude_scale[i]);
                assert!(
                    (x - y).abs() < 1e-7,
                    "amplitude of post ({i}, {j}) at {} m/s: {x} vs the strip's {y}",
                    q.point.speed_m_per_s
                );
            }
        }
    }
}

/// A slider with the y-mirror symmetry on the energy-conserving wave: the folded model (each
/// folded row one lane of 2 P_in/n_y, its draws a post's and its image's) gives the model on
/// every post, curve, amplitudes and maps, to the fixed point's tolerance.
#[test]
fn the_mirror_folded_slider_on_the_energy_conserving_wave_is_the_slider_on_every_post() {
    let (nx, ny) = (10, 8);
    let params = SliderParams {
        posts_x: nx,
        posts_y: ny,
        post_pitch_m: PITCH_M,
        slider_length_m: nx as f64 * PITCH_M + 1e-3,
        slider_width_m: ny as f64 * PITCH_M + 1e-3,
        preload_n: (nx * ny) as f64 * PRELOAD_PER_POST_N,
        solver: tight(),
        ..SliderParams::default()
    };
    let static_model = SliderModel::build(&params).unwrap();
    let mut scene = SliderScene::for_static(&static_model, Wave::paper_default(), 0.35, 0.3);
    scene.curve_points = 3;
    scene.tolerance = 1e-13;
    let folded =
        SliderDynamics::for_slider_with(&scene, &static_model, NearField::Johnson, true).unwrap();
    let full =
        SliderDynamics::for_slider_with(&scene, &static_model, NearField::Johnson, false).unwrap();
    assert!(folded.mirror().is_some() && full.mirror().is_none());
    let draw = full.model().at_speed(0.0).unwrap().stator_power_w;
    let o = options(draw, 1.1);
    let a = folded.solve_attenuated(&static_model, &o).unwrap();
    let b = full.solve_attenuated(&static_model, &o).unwrap();
    // The fixed point is settled to 1e-6 in α: both paths stop within that of the same profile.
    let tol = 1e-6;
    assert!(rel(a.curve.stall_thrust_n, b.curve.stall_thrust_n) < tol);
    assert!(rel(a.curve.no_load_speed_m_per_s, b.curve.no_load_speed_m_per_s) < tol);
    for (p, q) in a.curve.curve.iter().zip(&b.curve.curve) {
        assert_eq!(p.amplitude_scale.len(), nx * ny, "every post's amplitude");
        let worst = p
            .amplitude_scale
            .iter()
            .zip(&q.amplitude_scale)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(worst < 2.0 * tol, "amplitudes differ by {worst:e}");
        let power: f64 = p.post_power_w.iter().sum();
        assert!(
            rel(power, q.point.stator_power_w) < 1e-5,
            "Σ post draws {power} vs stator power {}",
            q.point.stator_power_w
        );
    }
    for (ma, mb) in a.maps.iter().zip(&b.maps) {
        let worst = ma
            .amplitude_scale
            .iter()
            .zip(&mb.amplitude_scale)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(worst < 2.0 * tol, "map amplitudes differ by {worst:e}");
    }
}

/// Under post-height scatter (every post and row different) on a wave that carries 0.8 of the
/// constant wave's stall draw: at every point the wave's books close (P_in − P_out = stator
/// power), the stator power stays below P_in, every post's amplitude is the one its row's lane
/// leaves it (midpoint rule on the posts' own draws, to the fixed point's tolerance), the
/// trailing posts see less wave than the leading ones, and the stall thrust falls below the
/// constant wave's.
#[test]
fn under_scatter_the_books_close_and_every_post_sees_what_its_row_leaves_it() {
    let (nx, ny) = (12, 5);
    let params = SliderParams {
        posts_x: nx,
        posts_y: ny,
        post_pitch_m: PITCH_M,
        slider_length_m: nx as f64 * PITCH_M,
        slider_width_m: ny as f64 * PITCH_M,
        preload_n: (nx * ny) as f64 * PRELOAD_PER_POST_N,
        imperfections: motor::Imperfections {
            height_scatter_m: 3e-9,
            ..motor::Imperfections::default()
        },
        solver: tight(),
        ..SliderParams::default()
    };
    let static_model = SliderModel::build(&params).unwrap();
    let mut scene = SliderScene::for_static(&static_model, Wave::paper_default(), 0.35, 0.3);
    scene.curve_points = 3;
    let slider = SliderDynamics::for_slider(&scene, &static_model, NearField::Johnson).unwrap();
    assert!(slider.mirror().is_none(), "scatter breaks the mirror");
    let constant = slider.model().at_speed(0.0).unwrap();
    let o = options(constant.stator_power_w, 0.8);
    let run = slider.solve_attenuated(&static_model, &o).unwrap();
    assert!(
        run.curve.stall_thrust_n < constant.thrust_n,
        "less wave, less thrust"
    );
    assert!(
        run.normal_grids > 0,
        "every profile re-solves the normal grid"
    );
    for p in &run.curve.curve {
        assert!(p.balance_residual < 1e-9, "books: {}", p.balance_residual);
        assert!(p.point.stator_power_w < o.power_in_w, "draw below P_in");
        let lane_in = o.power_in_w / ny as f64;
        for j in 0..ny {
            let mut remaining = lane_in;
            for i in 0..nx {
                let k = i * ny + j;
                let expected = ((remaining - 0.5 * p.post_power_w[k]).max(0.0) / lane_in).sqrt();
                assert!(
                    (p.amplitude_scale[k] - expected).abs() < 1e-5,
                    "post ({i}, {j}) at {} m/s: amplitude {} vs {expected}",
                    p.point.speed_m_per_s,
                    p.amplitude_scale[k]
                );
                remaining -= p.post_power_w[k];
            }
            let (first, last) = (p.amplitude_scale[j], p.amplitude_scale[(nx - 1) * ny + j]);
            let row_draw: f64 = (0..nx).map(|i| p.post_power_w[i * ny + j]).sum();
            assert!(
                row_draw <= 0.0 || last < first,
                "row {j} draws {row_draw} W: the trailing post sees less wave ({last} vs {first})"
            );
        }
    }
    let stall_map = &run.maps[0];
    assert_eq!(
        stall_map.amplitude_scale,
        run.curve.curve[0].amplitude_scale
    );
    let drawn: f64 = stall_map.means.stator_power_w.iter().sum();
    assert!(rel(drawn, run.curve.curve[0].point.stator_power_w) < 1e-6);
}
