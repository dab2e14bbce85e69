//! The ball on the wave: energy books, steady states, signs and bounds, regimes, and the
//! convergence of the step and of the spring bed.

use ball_slider::{BallModel, BallScene, solve};

/// The default scene (2 mm steel ball, 20 mN, the paper's 20 nm wave) with lighter numerics.
fn scene() -> BallScene {
    let mut s = BallScene::default_ball();
    s.numerics.curve_points = 6;
    s.numerics.free_periods = 40;
    s
}

#[test]
fn imposed_speed_energy_books_close_per_period() {
    for preload in [0.005, 0.02, 0.2] {
        let model = BallModel::new(&BallScene::paper_wave(2e-3, preload)).unwrap();
        for v in [1e-6, 0.2, 0.5, 1.0] {
            let p = model.at_speed(v).unwrap();
            assert!(
                p.energy_residual.abs() < 1e-9,
                "P = {preload} N, V = {v} m/s: stator {} − friction {} − mechanical {} − stored {} leaves {:e}",
                p.stator_power_w,
                p.friction_power_w,
                p.mechanical_power_w,
                p.stored_power_w,
                p.energy_residual
            );
            assert!(
                p.friction_power_w >= 0.0,
                "friction power {} W must not be negative",
                p.friction_power_w
            );
            assert!(
                (p.mean_normal_force_n / preload - 1.0).abs() < 1e-9,
                "period-mean normal force {} N vs preload {preload} N",
                p.mean_normal_force_n
            );
        }
    }
}

#[test]
fn free_ball_energy_books_close_and_confirm_the_imposed_speed() {
    let model = BallModel::new(&scene()).unwrap();
    for v in [0.1, 0.3] {
        let load = model.thrust_n(v).unwrap();
        let f = model.free_check(v, load, 60).unwrap();
        assert!(
            f.energy_residual.abs() < 1e-7,
            "free ball at {v} m/s: energy residual {:e}",
            f.energy_residual
        );
        assert!(
            f.steady,
            "free ball at {v} m/s not steady: drift {:e}",
            f.drift
        );
        assert!(
            (f.speed_m_per_s / v - 1.0).abs() < 1e-4,
            "free ball under the imposed thrust {load} N runs at {} m/s, imposed {v} m/s",
            f.speed_m_per_s
        );
    }
}

#[test]
fn ball_moves_against_the_wave_below_crest_speed_and_friction_limit() {
    let r = solve(&scene()).unwrap();
    assert!(r.drives, "the 20 nm wave must drive a 2 mm ball at 20 mN");
    assert!(
        r.no_load_speed_m_per_s > 0.0 && r.no_load_speed_m_per_s < r.crest_speed_m_per_s,
        "no-load speed {} m/s along the drive (−x) must lie in (0, A_tω = {})",
        r.no_load_speed_m_per_s,
        r.crest_speed_m_per_s
    );
    assert!(
        r.stall_thrust_n > 0.0 && r.stall_thrust_n < r.friction_limit_n,
        "stall thrust {} N must lie in (0, μP = {})",
        r.stall_thrust_n,
        r.friction_limit_n
    );
    assert!(r.all_steady, "every curve point's free run must be steady");
    assert!(
        r.max_energy_residual < 1e-7,
        "energy books over the curve: {:e}",
        r.max_energy_residual
    );
    for p in &r.curve {
        assert!(
            p.mechanical_power_w <= p.stator_power_w + 1e-15,
            "at {} m/s the ball delivers {} W but draws {} W from the wave",
            p.speed_m_per_s,
            p.mechanical_power_w,
            p.stator_power_w
        );
    }
    let thrusts: Vec<f64> = r.curve.iter().map(|p| p.thrust_n).collect();
    assert!(
        thrusts.windows(2).all(|w| w[1] < w[0]),
        "thrust must fall with speed: {thrusts:?}"
    );
    assert!(r.max_efficiency > 0.0 && r.max_efficiency < 1.0);
}

#[test]
fn heavy_preload_holds_the_ball_in_partial_slip() {
    let r = solve(&BallScene::paper_wave(2e-3, 1.0)).unwrap();
    assert!(
        !r.drives,
        "a 2 mm ball at 1 N (static approach 19 A_n) must not be driven"
    );
    assert_eq!(r.no_load_speed_m_per_s, 0.0);
    assert!(r.curve.is_empty() && r.operating_point.is_none());
    assert!(
        r.zero_speed_thrust_n < -0.5 * r.friction_limit_n,
        "creeping forward needs a push near μP: thrust at 0⁺ {} N",
        r.zero_speed_thrust_n
    );
    assert!(r.static_contact.full_slip_over_tangential_amplitude > 5.0);
}

#[test]
fn light_preload_lets_the_ball_fly_over_the_troughs() {
    let model = BallModel::new(&BallScene::paper_wave(2e-3, 0.005)).unwrap();
    let p = model.at_speed(0.2).unwrap();
    assert!(
        p.contact_fraction < 0.9 && p.contact_fraction > 0.1,
        "static approach 0.56 A_n: contact over {} of the period",
        p.contact_fraction
    );
    let s = model.static_summary().unwrap();
    assert!(s.approach_over_amplitude < 1.0);
}

#[test]
fn operating_point_carries_the_external_load() {
    let mut s = scene();
    let stall = BallModel::new(&s).unwrap().thrust_n(1e-6).unwrap();
    s.external_load_n = 0.5 * stall;
    let r = solve(&s).unwrap();
    let op = r
        .operating_point
        .expect("half the stall thrust must be carried");
    assert!(
        (op.thrust_n / s.external_load_n - 1.0).abs() < 1e-6,
        "thrust {} vs load {}",
        op.thrust_n,
        s.external_load_n
    );
    assert!(op.speed_m_per_s > 0.0 && op.speed_m_per_s < r.no_load_speed_m_per_s);
    s.external_load_n = 1.1 * stall;
    assert!(
        solve(&s).unwrap().operating_point.is_none(),
        "a load above stall holds the ball"
    );
}

#[test]
fn light_ball_from_rest_reaches_the_imposed_steady_speed() {
    // 0.1 mg: speed time constant m/|dT/dV| ≈ 150 periods, contact resonance 0.05 ω.
    let mut s = scene();
    s.ball.moving_mass_kg = Some(1e-7);
    let model = BallModel::new(&s).unwrap();
    let v0 = model.no_load_speed_m_per_s().unwrap().unwrap();
    let speeds = model.from_rest(0.0, 1200).unwrap();
    let tail = &speeds[1000..];
    let mean = tail.iter().sum::<f64>() / tail.len() as f64;
    let first = &speeds[1000..1100];
    let second = &speeds[1100..];
    let drift = (second.iter().sum::<f64>() - first.iter().sum::<f64>()).abs() / 100.0 / mean;
    assert!(
        drift < 1e-3,
        "from rest: speed still drifting ({drift:e}) after 1000 periods"
    );
    assert!(
        (mean / v0 - 1.0).abs() < 5e-3,
        "from rest the light ball settles at {mean} m/s; the imposed-speed no-load speed is {v0} m/s"
    );
}

fn no_load_and_stall(steps: usize, springs: usize) -> (f64, f64) {
    let mut s = scene();
    s.numerics.steps_per_period = steps;
    s.numerics.springs = springs;
    let m = BallModel::new(&s).unwrap();
    (
        m.no_load_speed_m_per_s().unwrap().unwrap(),
        m.thrust_n(1e-6).unwrap(),
    )
}

#[test]
fn step_refinement_converges_the_stall_thrust_and_no_load_speed() {
    let (v_ref, t_ref) = no_load_and_stall(2048, 200);
    let errs: Vec<(f64, f64)> = [32, 64, 128, 256]
        .iter()
        .map(|&n| {
            let (v, t) = no_load_and_stall(n, 200);
            ((v / v_ref - 1.0).abs(), (t / t_ref - 1.0).abs())
        })
        .collect();
    assert!(
        errs[2].0 < 1e-3 && errs[2].1 < 1e-3,
        "128 steps per period: errors (no-load, stall) {:?}",
        errs[2]
    );
    let rate = |a: f64, b: f64| (a / b).log2();
    let (p_v, p_t) = (
        rate(errs[0].0, errs[3].0) / 3.0,
        rate(errs[0].1, errs[3].1) / 3.0,
    );
    assert!(
        p_v > 0.9 && p_t > 0.9,
        "observed orders (no-load {p_v}, stall {p_t}) from 32 to 256 steps: {errs:?}"
    );
}

#[test]
fn spring_refinement_converges_the_curve() {
    let (v_ref, t_ref) = no_load_and_stall(128, 1600);
    let errs: Vec<(f64, f64)> = [50, 100, 200, 400]
        .iter()
        .map(|&n| {
            let (v, t) = no_load_and_stall(128, n);
            ((v / v_ref - 1.0).abs(), (t / t_ref - 1.0).abs())
        })
        .collect();
    assert!(
        errs[2].0 < 1e-4 && errs[2].1 < 1e-4,
        "200 springs: errors (no-load, stall) {:?}",
        errs[2]
    );
    assert!(
        errs[3].0 < errs[0].0 && errs[3].1 < errs[0].1,
        "errors must fall with springs: {errs:?}"
    );
}

#[test]
fn validation_study_runs_at_smoke_size() {
    let study = ball_slider::study::run(ball_slider::study::StudySize::Smoke).unwrap();
    assert_eq!(study.amplitude_sweep.len(), 2);
    let (small, large) = (
        &study.amplitude_sweep[0].result,
        &study.amplitude_sweep[1].result,
    );
    assert!(
        large.no_load_speed_m_per_s > small.no_load_speed_m_per_s,
        "a larger wave drives faster"
    );
    assert!(
        study.preload_sweep[0].result.drives && !study.preload_sweep[1].result.drives,
        "20 mN drives, 1 N holds"
    );
}

/// The energy-conserving wave's weak-draw limit: a wave share far above the ball's draw gives
/// the constant-amplitude result to 1e-6.
#[test]
fn a_wave_share_far_above_the_draw_recovers_the_constant_wave_to_1e_6() {
    let constant = solve(&scene()).unwrap();
    let mut wide = scene();
    wide.wave_share = Some(ball_slider::WaveShare::new(1e6).unwrap());
    let attenuated = solve(&wide).unwrap();
    let rel = |a: f64, b: f64| (a / b - 1.0).abs();
    assert!(rel(attenuated.stall_thrust_n, constant.stall_thrust_n) < 1e-6);
    assert!(
        rel(
            attenuated.no_load_speed_m_per_s,
            constant.no_load_speed_m_per_s
        ) < 1e-6
    );
    assert!(
        attenuated
            .curve
            .iter()
            .all(|p| p.amplitude_scale < 1.0 && p.amplitude_scale > 1.0 - 1e-6)
    );
}
