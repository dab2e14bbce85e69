//! The energy-conserving wave under the slider (`coupled_dynamics::attenuation`): the posts
//! draw no more power than the wave brings, the wave's power balance closes, and a weak load
//! recovers the constant-amplitude results.

use coupled_dynamics::{
    AttenuationOptions, CoupledModel, CoupledScene, attenuated_at_speed, solve_attenuated,
    solve_attenuated_with_histories,
};
use stick_slip::Wave;

const K_N: f64 = 1.8e6;
const K_T: f64 = 1.5e6;
const POSTS: usize = 12;

/// A row of independent posts 0.37 λ apart (spread over the phase), one row: strip share 1.
fn row(preload_n: f64) -> CoupledScene {
    let wave = Wave::paper_default();
    let x = (0..POSTS)
        .map(|i| 0.37 * wave.wavelength_m() * i as f64)
        .collect();
    let mut scene = CoupledScene::independent_posts(wave, x, K_N, K_T, 0.3, 0.3, preload_n);
    scene.steps_per_period = 64;
    scene
}

/// The default slider's row (100 posts at 40 µm of a 100 × 100 array, analytic compliance:
/// Johnson post springs plus the half-space terms of all 100 rows, as the `curve` bench).
fn default_row(preload_n: f64) -> CoupledScene {
    use contact_springs::{Material, post_springs};
    use nalgebra::DMatrix;
    use static_contact::halfspace::{
        RowLayout, StripPost, strip_compliance, strip_tangential_compliance,
    };
    let (pitch, radius, n) = (40e-6, 10e-6, 100);
    let (si, ln) = (Material::silicon(), Material::lithium_niobate());
    let springs = post_springs(&si, &ln, radius).unwrap();
    let posts: Vec<StripPost> = (0..n)
        .map(|i| StripPost {
            x_m: (i as f64 - 0.5 * (n - 1) as f64) * pitch,
            row: 0,
        })
        .collect();
    let layout = RowLayout {
        pitch_m: pitch,
        strip_rows: 1,
        slider_rows: 100,
    };
    let (g, nu) = (ln.shear_modulus_pa, ln.poisson_ratio);
    let mut scene = CoupledScene::independent_posts(
        Wave::paper_default(),
        posts.iter().map(|p| p.x_m).collect(),
        1.0,
        1.0,
        0.3,
        0.3,
        preload_n,
    );
    scene.normal_compliance_m_per_n = strip_compliance(g, nu, radius, &posts, &layout)
        + DMatrix::identity(n, n) / springs.k_pn_n_per_m;
    scene.tangential_compliance_m_per_n =
        strip_tangential_compliance(g, nu, radius, &posts, &layout)
            + DMatrix::identity(n, n) / springs.k_pt_n_per_m;
    scene.strip_share = 0.01;
    scene.steps_per_period = 128;
    scene
}

/// `sawdrive wave --json`'s `power_under_array_w` for the paper wave (128° Y-X LiNbO3, 20 nm,
/// 9.61 MHz, 2.4466 kW/m × the 4 mm array).
const POWER_UNDER_ARRAY_W: f64 = 9.78634644379686;

#[test]
fn at_100_n_the_drawn_power_no_longer_exceeds_the_power_under_the_slider() {
    let scene = default_row(100.0);
    let constant = CoupledModel::new(&scene).unwrap().at_speed(0.0).unwrap();
    // Constant amplitude: ≈ 22.7 W drawn from a wave that brings 9.8 W.
    assert!(constant.stator_power_w > 2.0 * POWER_UNDER_ARRAY_W);
    let p =
        attenuated_at_speed(&scene, 0.0, &AttenuationOptions::new(POWER_UNDER_ARRAY_W)).unwrap();
    assert!(p.point.stator_power_w < POWER_UNDER_ARRAY_W);
    assert!(p.wave_power_out_w >= 0.0);
    assert!(p.balance_residual <= 1e-6, "balance {}", p.balance_residual);
    // The trailing posts see a weaker wave, so the stall thrust falls.
    assert!(p.amplitude_scale[99] < 0.5 * p.amplitude_scale[0]);
    assert!(p.point.thrust_n < 0.8 * constant.thrust_n);
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

#[test]
fn unit_amplitude_profile_is_bit_identical_to_the_constant_wave() {
    let scene = row(0.5);
    let mut ones = scene.clone();
    ones.amplitude_scale = vec![1.0; POSTS];
    let a = CoupledModel::new(&scene).unwrap().at_speed(0.3).unwrap();
    let b = CoupledModel::new(&ones).unwrap().at_speed(0.3).unwrap();
    assert_eq!(a.thrust_n.to_bits(), b.thrust_n.to_bits());
    assert_eq!(a.stator_power_w.to_bits(), b.stator_power_w.to_bits());
}

#[test]
fn drawn_power_never_exceeds_the_wave_power_and_the_balance_closes() {
    let scene = row(0.5);
    let model = CoupledModel::new(&scene).unwrap();
    let stall = model.at_speed(0.0).unwrap();
    // A wave carrying 60 % of what the constant-amplitude posts would draw at stall: the
    // unattenuated model violates energy conservation there.
    let power_in = 0.6 * stall.stator_power_w;
    assert!(stall.stator_power_w > power_in);
    let options = AttenuationOptions::new(power_in);
    for speed in [0.0, 0.05, 0.5] {
        let p = attenuated_at_speed(&scene, speed, &options).unwrap();
        let drawn = p.wave_power_in_w - p.wave_power_out_w;
        println!(
            "v = {speed}: thrust {:.6} N, stator {:.6e} W, in {:.6e} W, out {:.6e} W, \
             iterations {}, balance {:.2e}, α {:?}",
            p.point.thrust_n,
            p.point.stator_power_w,
            p.wave_power_in_w,
            p.wave_power_out_w,
            p.iterations,
            p.balance_residual,
            p.amplitude_scale
        );
        assert!(p.wave_power_out_w >= 0.0, "out {}", p.wave_power_out_w);
        assert!(p.point.stator_power_w <= power_in * (1.0 + 1e-9));
        assert!(p.balance_residual <= 1e-6, "balance {}", p.balance_residual);
        assert!(relative(drawn, p.point.stator_power_w) <= 1e-6);
        // Where every post draws power the amplitude falls along the wave; beyond the no-load
        // speed the pushed slider feeds the wave and it grows (energy is still conserved).
        // (The reported profile is the last iterate, within the tolerance of the exactly
        // monotone target profile.)
        if p.post_power_w.iter().all(|&w| w >= 0.0) {
            let slack = 2.0 * options.tolerance;
            assert!(p.amplitude_scale.windows(2).all(|w| w[1] <= w[0] + slack));
        }
        assert!(p.last_change < options.tolerance);
    }
    // The attenuated stall thrust is below the constant-amplitude one.
    let attenuated = attenuated_at_speed(&scene, 0.0, &options).unwrap();
    assert!(attenuated.point.thrust_n < stall.thrust_n);
}

#[test]
fn a_weak_load_recovers_the_constant_amplitude_results() {
    let scene = row(0.5);
    let model = CoupledModel::new(&scene).unwrap();
    for speed in [0.0, 0.3] {
        let constant = model.at_speed(speed).unwrap();
        // The posts draw 1e-8 of the wave's power.
        let options = AttenuationOptions::new(1e8 * constant.stator_power_w.abs().max(1e-12));
        let p = attenuated_at_speed(&scene, speed, &options).unwrap();
        assert!(relative(p.point.thrust_n, constant.thrust_n) <= 1e-6);
        assert!(relative(p.point.stator_power_w, constant.stator_power_w) <= 1e-6);
        assert!(p.balance_residual <= 1e-6);
    }
}

#[test]
fn bad_attenuation_options_are_named() {
    let scene = row(0.5);
    let mut options = AttenuationOptions::new(-1.0);
    let e = attenuated_at_speed(&scene, 0.0, &options)
        .unwrap_err()
        .to_string();
    assert!(e.contains("power_in_w"), "{e}");
    options.power_in_w = 1.0;
    options.relaxation = 0.0;
    let e = attenuated_at_speed(&scene, 0.0, &options)
        .unwrap_err()
        .to_string();
    assert!(e.contains("relaxation"), "{e}");
    let mut bad = scene.clone();
    bad.amplitude_scale = vec![1.0; 3];
    let e = CoupledModel::new(&bad).unwrap_err().to_string();
    assert!(e.contains("amplitude_scale"), "{e}");
}

/// The target profile g(α) of the posts' draws `power_w` (midpoint rule, posts in the order the
/// wave reaches them: x ascending for the +x wave), as the module docs define it.
fn target_profile(power_w: &[f64], power_in_w: f64) -> Vec<f64> {
    let mut remaining = power_in_w;
    power_w
        .iter()
        .map(|p| {
            let at_post = remaining - 0.5 * p;
            remaining -= p;
            (at_post.max(0.0) / power_in_w).sqrt()
        })
        .collect()
}

#[test]
fn the_joint_steppings_profile_is_the_fixed_point_of_an_independent_steady_solve() {
    // The tips and the profile stepped together must land on the profile whose own periodic
    // state (a constant-profile steady solve from rest) draws the powers that reproduce it.
    let scene = row(0.5);
    let stall = CoupledModel::new(&scene).unwrap().at_speed(0.0).unwrap();
    let options = AttenuationOptions::new(0.6 * stall.stator_power_w);
    for speed in [0.0, 0.05, 0.5] {
        let p = attenuated_at_speed(&scene, speed, &options).unwrap();
        let mut fixed = scene.clone();
        fixed.amplitude_scale = p.amplitude_scale.clone();
        let (point, power_w, _) = CoupledModel::new(&fixed)
            .unwrap()
            .post_stator_power_from(speed, None)
            .unwrap();
        let target = target_profile(&power_w, options.power_in_w);
        let residual = target
            .iter()
            .zip(&p.amplitude_scale)
            .fold(0.0, |m: f64, (t, a)| m.max((t - a).abs()));
        assert!(
            residual < 2.0 * options.tolerance,
            "v = {speed}: max|g(α) − α| = {residual:e} at the joint stepping's profile"
        );
        assert!(
            relative(point.thrust_n, p.point.thrust_n) <= 1e-9,
            "v = {speed}: thrust {} from rest against {} jointly",
            point.thrust_n,
            p.point.thrust_n
        );
    }
}

#[test]
fn the_history_point_from_a_curve_neighbour_has_the_histories_of_a_start_from_rest() {
    let scene = {
        let mut s = row(0.5);
        s.curve_points = 9;
        s
    };
    let stall = CoupledModel::new(&scene).unwrap().at_speed(0.0).unwrap();
    let options = AttenuationOptions::new(0.6 * stall.stator_power_w);
    let (curve, at_half, histories) =
        solve_attenuated_with_histories(&scene, &options, 0.5).unwrap();
    let speed = 0.5 * curve.no_load_speed_m_per_s;
    assert_eq!(at_half.point.speed_m_per_s, speed);
    let mut fixed = scene.clone();
    fixed.amplitude_scale = at_half.amplitude_scale.clone();
    let (_, from_rest) = CoupledModel::new(&fixed)
        .unwrap()
        .post_histories(speed)
        .unwrap();
    assert_eq!(histories.time_s, from_rest.time_s);
    assert_eq!(histories.mode, from_rest.mode);
    let scale = stall.thrust_n;
    for (a, b) in histories
        .tangential_force_n
        .iter()
        .flatten()
        .zip(from_rest.tangential_force_n.iter().flatten())
    {
        assert!(
            (a - b).abs() <= 1e-9 * scale,
            "tangential force {a} against {b}"
        );
    }
}

#[test]
fn the_no_load_search_from_a_guess_finds_the_regula_falsis_speed() {
    let mut scene = row(0.5);
    scene.curve_points = 3;
    let stall = CoupledModel::new(&scene).unwrap().at_speed(0.0).unwrap();
    let mut options = AttenuationOptions::new(0.6 * stall.stator_power_w);
    // A tight profile tolerance: the no-load speed is then set by the searches alone (at 1e-6
    // each point's thrust, and with it the root, moves by the tolerance's share).
    options.tolerance = 1e-10;
    let falsi = solve_attenuated(&scene, &options).unwrap();
    options.no_load_guess_m_per_s = Some(1.03 * falsi.no_load_speed_m_per_s);
    let secant = solve_attenuated(&scene, &options).unwrap();
    assert!(
        relative(secant.no_load_speed_m_per_s, falsi.no_load_speed_m_per_s) <= 1e-8,
        "{} against {}",
        secant.no_load_speed_m_per_s,
        falsi.no_load_speed_m_per_s
    );
    assert!(relative(secant.stall_thrust_n, falsi.stall_thrust_n) <= 1e-12);
}
