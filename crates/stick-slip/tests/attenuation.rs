//! The energy-conserving wave in the lumped models (`stick_slip::attenuation`): the posts draw
//! no more power than the wave brings, the wave's books close at every curve point, a weak load
//! recovers the constant-amplitude results, and the transient and the period average agree with
//! it as they agree without it.

#[path = "support/johnson.rs"]
mod johnson;

use stick_slip::{
    AttenuatedPeriodicModel, AttenuationOptions, AttenuationSetting, DynamicScene, Integrator,
    ModelChoice, PeriodicAverageModel, TransientModel, TransientStart,
};

/// `sawdrive wave --json`'s `power_under_array_w` for the paper wave (128° Y-X LiNbO3, 20 nm,
/// 9.61 MHz, 2.4466 kW/m × the 4 mm array).
const POWER_UNDER_ARRAY_W: f64 = 9.78634644379686;

fn paper_scene(preload_n: f64) -> DynamicScene {
    let (k_n, k_t) = johnson::springs(10e-6);
    let mut scene = DynamicScene::paper_default(k_n, k_t);
    scene.slider.preload_n = preload_n;
    scene.options.curve_points = 11;
    scene
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

#[test]
fn the_balance_closes_at_every_curve_point_and_the_wave_is_never_overdrawn() {
    for preload in [40.0, 100.0] {
        let scene = paper_scene(preload);
        let options = AttenuationOptions::new(POWER_UNDER_ARRAY_W);
        let model = AttenuatedPeriodicModel::new(&scene, &options).unwrap();
        let result = model.solve().unwrap();
        assert_eq!(result.points.len(), result.result.curve.len());
        for p in &result.points {
            assert!(
                p.balance_residual <= 1e-6,
                "{preload} N, {} m/s: wave balance residual {:e}",
                p.sample.speed_m_per_s,
                p.balance_residual
            );
            assert!(
                p.wave_power_out_w >= 0.0,
                "{preload} N: wave power out {} W",
                p.wave_power_out_w
            );
            assert!(p.sample.stator_power_w <= POWER_UNDER_ARRAY_W * (1.0 + 1e-9));
            assert!(p.last_change < 1e-8, "amplitude change {}", p.last_change);
            assert_eq!(p.amplitude_scale.len(), 100, "one amplitude per column");
        }
        println!(
            "{preload} N: stall {:.4} N, v0 {:.4} m/s, max power {:.4} W, max iterations {}, post solves {}",
            result.result.stall_thrust_n,
            result.result.no_load_speed_m_per_s,
            result.result.max_output_power_w,
            result.max_iterations,
            result.post_solves
        );
    }
}

#[test]
fn at_100_n_the_stall_draw_stays_within_the_wave_power_and_the_thrust_falls() {
    let scene = paper_scene(100.0);
    let constant = PeriodicAverageModel::new(&scene)
        .unwrap()
        .at_speed(0.0)
        .unwrap();
    // The constant-amplitude posts draw more than the wave brings.
    assert!(constant.stator_power_w > POWER_UNDER_ARRAY_W);
    let model = AttenuatedPeriodicModel::new(&scene, &AttenuationOptions::new(POWER_UNDER_ARRAY_W))
        .unwrap();
    let stall = model.at_speed(0.0, None).unwrap();
    assert!(stall.sample.stator_power_w <= POWER_UNDER_ARRAY_W);
    assert!(stall.wave_power_out_w >= 0.0);
    assert!(stall.sample.thrust_n < constant.thrust_n, "stall thrust");
    // Where every bin draws, the amplitude falls along the wave.
    let a = &stall.amplitude_scale;
    assert!(a.windows(2).all(|w| w[1] <= w[0] + 1e-12), "profile {a:?}");
    assert!(
        a[99] < a[0],
        "trailing amplitude {} vs leading {}",
        a[99],
        a[0]
    );
    // The preload is still carried.
    assert!(relative(stall.sample.mean_normal_force_n, 100.0) < 1e-9);
}

#[test]
fn a_weak_load_recovers_the_constant_amplitude_results() {
    let scene = paper_scene(40.0);
    let constant_model = PeriodicAverageModel::new(&scene).unwrap();
    let constant = constant_model.solve().unwrap();
    let draw = constant_model.at_speed(0.0).unwrap().stator_power_w;
    // The posts draw 1e-8 of the wave's power.
    let model = AttenuatedPeriodicModel::new(&scene, &AttenuationOptions::new(1e8 * draw)).unwrap();
    let result = model.solve().unwrap();
    let r = &result.result;
    for (name, a, b) in [
        ("stall thrust", r.stall_thrust_n, constant.stall_thrust_n),
        (
            "no-load speed",
            r.no_load_speed_m_per_s,
            constant.no_load_speed_m_per_s,
        ),
        (
            "maximum output power",
            r.max_output_power_w,
            constant.max_output_power_w,
        ),
        ("efficiency", r.efficiency, constant.efficiency),
    ] {
        assert!(relative(a, b) <= 1e-6, "{name}: {a} vs constant {b}");
    }
    for (p, q) in result.points.iter().zip(&constant.curve) {
        assert!(relative(p.sample.thrust_n + 1.0, q.thrust_n + 1.0) <= 1e-6);
    }
}

#[test]
fn coarser_bins_keep_the_books_and_stay_close_to_every_column() {
    let scene = paper_scene(100.0);
    let fine = AttenuatedPeriodicModel::new(&scene, &AttenuationOptions::new(POWER_UNDER_ARRAY_W))
        .unwrap()
        .at_speed(0.0, None)
        .unwrap();
    let mut options = AttenuationOptions::new(POWER_UNDER_ARRAY_W);
    options.bins = Some(20);
    let coarse = AttenuatedPeriodicModel::new(&scene, &options)
        .unwrap()
        .at_speed(0.0, None)
        .unwrap();
    assert_eq!(coarse.amplitude_scale.len(), 20);
    assert!(coarse.balance_residual <= 1e-6);
    // Midpoint rule, second order in the bin width: 20 bins within 1 % of 100.
    let e = relative(coarse.sample.thrust_n, fine.sample.thrust_n);
    println!("20 vs 100 bins: stall thrust {e:.2e}");
    assert!(e < 1e-2, "stall thrust with 20 bins off by {e}");
}

#[test]
fn transient_and_period_average_agree_with_attenuation_as_without() {
    let mut scene = paper_scene(40.0);
    scene.model = ModelChoice::Transient;
    scene.options.transient.periods = 200.0;
    scene.options.transient.average_periods = 80.0;
    let mut options = AttenuationOptions::new(POWER_UNDER_ARRAY_W);
    // The transient's window means settle to ≈ 1e-7 of the draws (steady tolerance 1e-3 on the
    // speed drift); the profile is converged well inside the 1 % the models agree to.
    options.tolerance = 1e-6;
    let periodic = AttenuatedPeriodicModel::new(&scene, &options).unwrap();
    let transient = TransientModel::new(&scene).unwrap();
    let stall = periodic.at_speed(0.0, None).unwrap();
    for load in [0.0, 0.5 * stall.sample.thrust_n] {
        let mut at_load = scene.clone();
        at_load.slider.external_load_n = load;
        let pa = AttenuatedPeriodicModel::new(&at_load, &options)
            .unwrap()
            .solve()
            .unwrap()
            .operating
            .unwrap();
        let run = transient
            .run_attenuated(
                load,
                TransientStart::Estimate,
                &options,
                Some(&pa.amplitude_scale),
            )
            .unwrap();
        let speed_error = relative(run.run.speed_m_per_s, pa.sample.speed_m_per_s);
        println!(
            "load {load:.3} N: transient {} m/s ({} runs, change {:.1e}), period average {} m/s",
            run.run.speed_m_per_s, run.iterations, run.last_change, pa.sample.speed_m_per_s
        );
        assert!(
            run.run.steady,
            "attenuated transient at {load} N did not settle"
        );
        assert!(
            speed_error < 0.01,
            "load {load:.3} N: speed off by {speed_error}"
        );
        assert!(
            run.balance_residual <= 1e-6,
            "transient balance {}",
            run.balance_residual
        );
        assert!(run.wave_power_out_w >= 0.0);
        let profile_error = run
            .amplitude_scale
            .iter()
            .zip(&pa.amplitude_scale)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(profile_error < 0.01, "profiles differ by {profile_error}");
    }
}

#[test]
fn bad_attenuation_settings_and_scenes_are_named() {
    let scene = paper_scene(40.0);
    let e = AttenuatedPeriodicModel::new(&scene, &AttenuationOptions::new(-1.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("attenuation.power_in_w"), "{e}");
    let mut options = AttenuationOptions::new(1.0);
    options.relaxation = 0.0;
    let e = AttenuatedPeriodicModel::new(&scene, &options)
        .unwrap_err()
        .to_string();
    assert!(e.contains("attenuation.relaxation"), "{e}");
    let mut decaying = scene.clone();
    decaying.model = ModelChoice::Transient;
    decaying.wave.decay_length_m = Some(5e-3);
    let e = TransientModel::new(&decaying)
        .unwrap()
        .run_attenuated(
            0.0,
            TransientStart::Rest,
            &AttenuationOptions::new(1.0),
            None,
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("decay_length_m"), "{e}");
    let mut exact = scene.clone();
    exact.model = ModelChoice::Transient;
    exact.integrator = Integrator::EventDriven { max_step_s: None };
    exact.options.transient.periods = 2.0;
    exact.options.transient.average_periods = 1.0;
    let e = TransientModel::new(&exact)
        .unwrap()
        .run_attenuated(
            0.0,
            TransientStart::Rest,
            &AttenuationOptions::new(1.0),
            None,
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("event-driven"), "{e}");
}

#[test]
fn auto_attenuates_when_the_posts_draw_a_noticeable_share_of_the_wave() {
    let (on, reason) = AttenuationSetting::Auto.resolve(11.0, POWER_UNDER_ARRAY_W);
    assert!(on, "{reason}");
    let (on, reason) = AttenuationSetting::Auto.resolve(1e-7, POWER_UNDER_ARRAY_W);
    assert!(!on, "{reason}");
    assert!(AttenuationSetting::On.resolve(0.0, 1.0).0);
    assert!(!AttenuationSetting::Off.resolve(1e3, 1.0).0);
    // The threshold: 1 % of the wave's power at stall.
    assert!(!AttenuationSetting::Auto.resolve(0.009, 1.0).0);
    assert!(AttenuationSetting::Auto.resolve(0.011, 1.0).0);
}
