//! Physics checks of the lumped stick/slip model (docs/physics.md §4–7).

#[path = "support/johnson.rs"]
mod johnson;

use stick_slip::{
    DynamicScene, ModelChoice, PeriodicAverageModel, PostContact, PostLayout, TransientModel,
    TransientStart,
};

/// The paper scene with 20 µm posts (Johnson springs).
fn paper_scene() -> DynamicScene {
    let (k_n, k_t) = johnson::springs(10e-6);
    DynamicScene::paper_default(k_n, k_t)
}

/// A scene with n × n posts of radius `a` at preload `p`, springs ∝ a.
fn scene_with(posts_per_side: usize, radius_m: f64, preload_n: f64) -> DynamicScene {
    let mut scene = paper_scene();
    let (k_n, k_t) = johnson::springs(radius_m);
    scene.contact = PostContact::new(k_n, k_t, 0.3);
    scene.slider.layout = PostLayout::SquareArray {
        posts_per_side,
        pitch_m: 4e-3 / posts_per_side as f64,
    };
    scene.slider.preload_n = preload_n;
    scene
}

#[test]
fn slider_moves_opposite_to_the_wave() {
    let mut scene = paper_scene();
    scene.model = ModelChoice::Transient;
    scene.options.transient.periods = 120.0;
    scene.options.transient.average_periods = 40.0;
    let run = TransientModel::new(&scene)
        .unwrap()
        .run(0.0, TransientStart::Rest, false)
        .unwrap();
    assert!(
        run.velocity_x_m_per_s < -0.1,
        "slider velocity along the wave direction should be clearly negative, got {} m/s",
        run.velocity_x_m_per_s
    );
    assert!(
        run.displacement_m > 0.0,
        "displacement along the drive direction {} m",
        run.displacement_m
    );
}

#[test]
fn stall_thrust_never_exceeds_the_friction_limit() {
    for (side, preload) in [
        (100, 1.0),
        (100, 40.0),
        (100, 100.0),
        (33, 10.0),
        (33, 100.0),
        (50, 60.0),
    ] {
        let scene = scene_with(side, 10e-6, preload);
        let model = PeriodicAverageModel::new(&scene).unwrap();
        let stall = model.stall_thrust_n().unwrap();
        let limit = scene.contact.mu_static * preload;
        assert!(
            stall <= limit * (1.0 + 1e-12),
            "stall thrust {stall} N above μP = {limit} N ({side}², P = {preload} N)"
        );
    }
}

#[test]
fn no_load_speed_is_bounded_by_the_crest_speed() {
    for (side, preload) in [(100, 0.5), (100, 40.0), (50, 60.0), (33, 20.0)] {
        let scene = scene_with(side, 10e-6, preload);
        let model = PeriodicAverageModel::new(&scene).unwrap();
        let v0 = model.no_load_speed_m_per_s().unwrap();
        let crest = scene.wave.crest_speed_m_per_s();
        assert!(
            v0 > 0.0 && v0 <= crest,
            "no-load speed {v0} m/s outside (0, A_t ω = {crest}] ({side}², P = {preload} N)"
        );
    }
}

#[test]
fn stall_thrust_tends_to_mu_p_at_low_preload() {
    let mut previous_gap = f64::INFINITY;
    for preload in [10.0, 1.0, 0.01] {
        let scene = scene_with(100, 10e-6, preload);
        let stall = PeriodicAverageModel::new(&scene)
            .unwrap()
            .stall_thrust_n()
            .unwrap();
        let gap = 1.0 - stall / (scene.contact.mu_kinetic * preload);
        assert!(
            gap >= -1e-12 && gap <= previous_gap + 1e-12,
            "stall/μP shortfall {gap} at P = {preload} N should shrink"
        );
        previous_gap = gap;
    }
    assert!(
        previous_gap < 1e-6,
        "stall thrust at P = 0.01 N within 1e-6 of μP, shortfall {previous_gap}"
    );
}

#[test]
fn steady_period_balances_stator_work_output_and_dissipation() {
    let mut cases = vec![(paper_scene(), "paper scene")];
    let mut deep = scene_with(33, 10e-6, 100.0);
    deep.contact.mu_static = 0.45;
    deep.contact.mu_kinetic = 0.15;
    cases.push((deep, "always in contact, μ_s > μ_k"));
    cases.push((scene_with(100, 10e-6, 0.01), "light preload"));
    for (scene, name) in cases {
        let model = PeriodicAverageModel::new(&scene).unwrap();
        let v0 = model.no_load_speed_m_per_s().unwrap();
        for fraction in [0.0, 0.3, 0.7, 1.0, 1.3] {
            let sample = model.at_speed(fraction * v0).unwrap();
            assert!(
                sample.energy_balance_residual.abs() < 1e-6,
                "{name}: energy balance residual {} at {fraction}·v0 (stator {} W, output {} W, friction {} W)",
                sample.energy_balance_residual,
                sample.stator_power_w,
                sample.output_power_w,
                sample.friction_dissipation_w
            );
            let normal = sample.mean_normal_force_n / scene.slider.preload_n - 1.0;
            assert!(
                normal.abs() < 1e-9,
                "{name}: mean normal force off the preload by {normal}"
            );
        }
    }
}

#[test]
fn more_posts_give_higher_speed_and_thrust_at_high_preload() {
    let preload = 100.0;
    let measure = |side| {
        let model = PeriodicAverageModel::new(&scene_with(side, 10e-6, preload)).unwrap();
        (
            model.no_load_speed_m_per_s().unwrap(),
            model.stall_thrust_n().unwrap(),
        )
    };
    let mut previous = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for side in [33, 50, 66, 80, 100] {
        let (speed, thrust) = measure(side);
        assert!(
            speed > previous.0 || (speed == 0.0 && previous.0 == 0.0),
            "no-load speed {speed} m/s with {side}² posts should beat {} m/s",
            previous.0
        );
        assert!(
            thrust > previous.1,
            "stall thrust F(0⁺) {thrust} N with {side}² posts should beat {} N",
            previous.1
        );
        previous = (speed, thrust);
    }
    assert!(
        previous.0 > 0.3,
        "the densest array must move at 100 N, no-load speed {} m/s",
        previous.0
    );
}

#[test]
fn twenty_micron_posts_beat_fifty_micron_posts_at_equal_contact_area() {
    for preload in [40.0, 70.0, 100.0] {
        let small = PeriodicAverageModel::new(&scene_with(100, 10e-6, preload)).unwrap();
        let large = PeriodicAverageModel::new(&scene_with(40, 25e-6, preload)).unwrap();
        let (v_small, v_large) = (
            small.no_load_speed_m_per_s().unwrap(),
            large.no_load_speed_m_per_s().unwrap(),
        );
        let (f_small, f_large) = (
            small.stall_thrust_n().unwrap(),
            large.stall_thrust_n().unwrap(),
        );
        assert!(
            v_small > v_large,
            "P = {preload} N: no-load speed 20 µm {v_small} vs 50 µm {v_large} m/s"
        );
        assert!(
            f_small > f_large,
            "P = {preload} N: stall thrust 20 µm {f_small} vs 50 µm {f_large} N"
        );
    }
}

#[test]
fn speed_thrust_curve_falls_monotonically_from_stall_to_no_load() {
    let scene = paper_scene();
    let result = PeriodicAverageModel::new(&scene)
        .unwrap()
        .solve(&stick_slip::RunControl::none())
        .unwrap();
    assert_eq!(
        result.curve.len(),
        scene.options.curve_points,
        "curve point count"
    );
    assert!(
        result
            .curve
            .windows(2)
            .all(|w| w[1].thrust_n <= w[0].thrust_n),
        "thrust must fall with speed"
    );
    let last = result.curve.last().unwrap();
    assert!(
        last.thrust_n.abs() < 1e-9 * result.stall_thrust_n,
        "thrust at the no-load end {} N",
        last.thrust_n
    );
    assert!(
        result.efficiency > 0.0 && result.efficiency < 1.0,
        "peak efficiency {} should be inside (0, 1)",
        result.efficiency
    );
    assert!(
        result
            .curve
            .iter()
            .all(|p| (0.0..=1.0).contains(&p.stick_fraction)),
        "stick fractions within [0, 1]"
    );
}

#[test]
fn static_friction_above_kinetic_raises_stall_thrust_of_separating_posts() {
    for preload in [40.0, 100.0] {
        let mut scene = scene_with(100, 10e-6, preload);
        let equal = PeriodicAverageModel::new(&scene)
            .unwrap()
            .stall_thrust_n()
            .unwrap();
        scene.contact.mu_static = 0.45;
        let higher = PeriodicAverageModel::new(&scene)
            .unwrap()
            .stall_thrust_n()
            .unwrap();
        assert!(
            higher > equal,
            "P = {preload} N: μ_s = 0.45 stall {higher} N not above μ_s = 0.3 stall {equal} N"
        );
        assert!(
            higher <= 0.45 * preload,
            "P = {preload} N: stall {higher} N above μ_s P"
        );
    }
}

#[test]
fn locked_slider_is_reported_with_zero_stall_thrust_and_a_warning() {
    // 33 × 33 posts at 100 N: posts never separate and stay stuck within the friction band.
    let scene = scene_with(33, 10e-6, 100.0);
    let model = PeriodicAverageModel::new(&scene).unwrap();
    let limit = model.stall_thrust_n().unwrap();
    assert!(
        limit < 0.0 && limit.abs() <= 0.3 * 100.0,
        "F(0⁺) of a locked slider {limit} N should be negative, within μP"
    );
    let result = model.solve(&stick_slip::RunControl::none()).unwrap();
    assert_eq!(
        result.stall_thrust_n, 0.0,
        "reported stall thrust of a locked slider"
    );
    assert_eq!(
        result.no_load_speed_m_per_s, 0.0,
        "reported no-load speed of a locked slider"
    );
    assert!(
        result.warnings.iter().any(|w| w.message.contains("locked")),
        "a 'locked' warning, got {:?}",
        result.warnings
    );
}
