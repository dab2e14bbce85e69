//! The transient model: agreement with the period average where both apply, phase grouping,
//! energy balance, and the scenes only the transient resolves (burst, step response, bounce).

#[path = "support/johnson.rs"]
mod johnson;

use stick_slip::{
    DynamicScene, Integrator, ModelChoice, PeriodicAverageModel, PostLayout, TransientModel,
    TransientStart, VerticalModel,
};

fn transient_scene() -> DynamicScene {
    let (k_n, k_t) = johnson::springs(10e-6);
    let mut scene = DynamicScene::paper_default(k_n, k_t);
    scene.model = ModelChoice::Transient;
    scene.options.transient.periods = 200.0;
    scene.options.transient.average_periods = 80.0;
    scene
}

#[test]
fn transient_agrees_with_period_average_to_one_percent_in_speed_and_thrust() {
    let scene = transient_scene();
    let periodic = PeriodicAverageModel::new(&scene).unwrap();
    let stall = periodic.stall_thrust_n().unwrap();
    let model = TransientModel::new(&scene).unwrap();
    for load in [0.0, 0.5 * stall, 0.85 * stall] {
        let run = model.run(load, TransientStart::Estimate, false).unwrap();
        let expected = periodic.at_load(load).unwrap().unwrap();
        let speed_error =
            (run.speed_m_per_s - expected.speed_m_per_s).abs() / expected.speed_m_per_s;
        assert!(run.steady, "transient at load {load:.3} N did not settle");
        assert!(
            speed_error < 0.01,
            "load {load:.3} N: transient speed {} vs period average {} m/s",
            run.speed_m_per_s,
            expected.speed_m_per_s
        );
        let thrust_at_speed = periodic.at_speed(run.speed_m_per_s).unwrap().thrust_n;
        assert!(
            (run.thrust_n - thrust_at_speed).abs() < 0.01 * stall,
            "load {load:.3} N: transient thrust {} vs period-average F(v) {} N",
            run.thrust_n,
            thrust_at_speed
        );
    }
}

#[test]
fn transient_stall_thrust_and_no_load_speed_match_the_period_average() {
    let mut scene = transient_scene();
    scene.options.transient.periods = 120.0;
    scene.options.transient.average_periods = 40.0;
    scene.options.transient.curve_loads = 3;
    let periodic = PeriodicAverageModel::new(&scene).unwrap();
    let result = TransientModel::new(&scene).unwrap().solve().unwrap();
    let stall = periodic.stall_thrust_n().unwrap();
    let v0 = periodic.no_load_speed_m_per_s().unwrap();
    assert!(
        (result.stall_thrust_n / stall - 1.0).abs() < 0.01,
        "stall thrust transient {} vs {stall} N",
        result.stall_thrust_n
    );
    assert!(
        (result.no_load_speed_m_per_s / v0 - 1.0).abs() < 0.01,
        "no-load speed transient {} vs {v0} m/s",
        result.no_load_speed_m_per_s
    );
    assert!(
        result
            .curve
            .windows(2)
            .all(|w| w[1].speed_m_per_s >= w[0].speed_m_per_s),
        "curve sorted by speed"
    );
}

#[test]
fn square_array_groups_posts_by_phase() {
    let mut scene = transient_scene();
    assert_eq!(
        TransientModel::new(&scene).unwrap().phase_groups(),
        100,
        "100 × 100 posts at 40 µm: 100 phases"
    );
    let lambda = scene.wave.wavelength_m();
    scene.slider.layout = PostLayout::SquareArray {
        posts_per_side: 8,
        pitch_m: lambda / 4.0,
    };
    assert_eq!(
        TransientModel::new(&scene).unwrap().phase_groups(),
        4,
        "8 columns a quarter wavelength apart: 4 phases"
    );
    scene.wave.decay_length_m = Some(0.05);
    assert_eq!(
        TransientModel::new(&scene).unwrap().phase_groups(),
        8,
        "with decay every column is its own group"
    );
}

#[test]
fn event_driven_transient_balances_energy_over_steady_periods() {
    let mut scene = transient_scene();
    scene.slider.layout = PostLayout::UniformPhase { post_count: 10000 };
    scene.options.transient.uniform_phase_groups = 12;
    scene.options.transient.periods = 40.0;
    scene.options.transient.average_periods = 10.0;
    scene.integrator = Integrator::EventDriven { max_step_s: None };
    let run = TransientModel::new(&scene)
        .unwrap()
        .run(3.0, TransientStart::Estimate, false)
        .unwrap();
    assert!(
        run.energy_balance_residual.abs() < 1e-6,
        "stator − output − friction − stored = {:e} of the power flow",
        run.energy_balance_residual
    );
    assert!(
        run.friction_dissipation_w > 0.0 && run.output_power_w > 0.0,
        "dissipation and output must be positive"
    );
}

#[test]
fn step_response_from_rest_rises_to_the_steady_speed() {
    let scene = transient_scene();
    let run = TransientModel::new(&scene)
        .unwrap()
        .run(0.0, TransientStart::Rest, false)
        .unwrap();
    let speeds = &run.period_speed_m_per_s;
    assert!(
        speeds[0] < 0.5 * run.speed_m_per_s,
        "first-period speed {} vs steady {}",
        speeds[0],
        run.speed_m_per_s
    );
    let settled = speeds
        .iter()
        .position(|&v| (v / run.speed_m_per_s - 1.0).abs() < 0.01)
        .unwrap();
    assert!(
        settled < 100,
        "speed within 1 % of steady after {settled} periods"
    );
}

#[test]
fn burst_moves_the_slider_a_finite_distance_then_it_stops() {
    let mut scene = transient_scene();
    scene.wave.burst_periods = Some(20.0);
    scene.slider.vertical = VerticalModel::Dynamic { damping_ratio: 0.2 };
    scene.options.transient.periods = 80.0;
    scene.options.transient.average_periods = 10.0;
    let run = TransientModel::new(&scene)
        .unwrap()
        .run(0.0, TransientStart::Rest, false)
        .unwrap();
    assert!(
        run.displacement_m > 0.0,
        "burst displacement along the drive direction {} m",
        run.displacement_m
    );
    // Bound: the crest speed for the burst duration plus the time the wave takes to cross the slider.
    let bound = scene.wave.crest_speed_m_per_s()
        * (20.0 * scene.wave.period_s() + 4e-3 / scene.wave.phase_velocity_m_per_s);
    assert!(
        run.displacement_m < bound,
        "burst displacement {} m above the crest-speed bound {bound} m",
        run.displacement_m
    );
    assert!(
        run.speed_m_per_s.abs() < 0.02 * run.peak_speed_m_per_s,
        "speed after the burst {} m/s should vanish (peak {} m/s)",
        run.speed_m_per_s,
        run.peak_speed_m_per_s
    );
}

#[test]
fn incommensurate_light_slider_ripples_and_bounces() {
    let mut scene = transient_scene();
    scene.slider.layout = PostLayout::SquareArray {
        posts_per_side: 33,
        pitch_m: 121e-6,
    };
    scene.slider.preload_n = 10.0;
    scene.slider.mass_kg *= 0.1;
    scene.slider.vertical = VerticalModel::Dynamic {
        damping_ratio: 0.05,
    };
    let run = TransientModel::new(&scene)
        .unwrap()
        .run(0.0, TransientStart::Estimate, false)
        .unwrap();
    assert!(
        run.vertical_bounce_m > 0.0,
        "vertical bounce {} m",
        run.vertical_bounce_m
    );
    let relative_ripple = run.speed_ripple_m_per_s / run.speed_m_per_s;
    assert!(
        relative_ripple > 1e-3,
        "speed ripple {relative_ripple} of the mean for an incommensurate light slider"
    );
    let periodic = PeriodicAverageModel::new(&DynamicScene {
        model: ModelChoice::PeriodicAverage,
        slider: stick_slip::Slider {
            vertical: VerticalModel::PeriodMean,
            ..scene.slider.clone()
        },
        ..scene.clone()
    })
    .unwrap();
    let v0 = periodic.no_load_speed_m_per_s().unwrap();
    assert!(
        (run.speed_m_per_s / v0 - 1.0).abs() < 0.2,
        "incommensurate no-load speed {} m/s vs period average {v0} m/s: same order",
        run.speed_m_per_s
    );
}

/// The effect estimates behind `auto` bound what the transient measures: on the incommensurate
/// 33 × 33 array the measured speed ripple and bounce stay below their estimates, and where
/// `auto` picks the period average (2.9 mg slider) its no-load speed matches the transient's
/// within the ripple limit; a ten times lighter slider is sent to the transient.
#[test]
fn auto_effect_estimates_bound_the_transient_ripple_and_bounce() {
    for (mass_factor, expected) in [
        (0.1, stick_slip::ModelKind::PeriodicAverage),
        (0.01, stick_slip::ModelKind::Transient),
    ] {
        let mut scene = transient_scene();
        scene.slider.layout = PostLayout::SquareArray {
            posts_per_side: 33,
            pitch_m: 121e-6,
        };
        scene.slider.preload_n = 10.0;
        scene.slider.mass_kg *= mass_factor;
        scene.slider.vertical = VerticalModel::Dynamic {
            damping_ratio: 0.05,
        };
        let auto = DynamicScene {
            model: ModelChoice::Auto,
            ..scene.clone()
        };
        let (kind, reason) = auto.resolve_model().unwrap();
        assert_eq!(
            kind, expected,
            "slider mass {:.2e} kg: {reason}",
            scene.slider.mass_kg
        );
        let run = TransientModel::new(&scene)
            .unwrap()
            .run(0.0, TransientStart::Estimate, false)
            .unwrap();
        let crest = scene.wave.crest_speed_m_per_s();
        let ripple_measured = 0.5 * run.speed_ripple_m_per_s / crest;
        let bounce_measured = 0.5 * run.vertical_bounce_m / scene.wave.normal_amplitude_m;
        assert!(
            ripple_measured <= auto.speed_ripple_estimate(),
            "speed ripple amplitude {ripple_measured:.2e} of A_t ω above its estimate {:.2e}",
            auto.speed_ripple_estimate()
        );
        let bounce_estimate = auto.bounce_estimate().unwrap();
        assert!(
            bounce_measured <= bounce_estimate,
            "bounce amplitude {bounce_measured:.2e} of A_n above its estimate {bounce_estimate:.2e}"
        );
        if kind == stick_slip::ModelKind::PeriodicAverage {
            let v0 = PeriodicAverageModel::new(&auto)
                .unwrap()
                .no_load_speed_m_per_s()
                .unwrap();
            assert!(
                (run.speed_m_per_s - v0).abs() <= stick_slip::SPEED_RIPPLE_LIMIT * crest,
                "no-load speed: transient {} vs period average {v0} m/s",
                run.speed_m_per_s
            );
        }
    }
}

#[test]
fn posts_held_off_by_a_gap_carry_no_load() {
    // 24 phases over one wavelength; in the gapped scene every phase has a second post lifted
    // 50 A_n above the wave (never touching). Same contact, same η: it must run like the scene
    // with only the touching posts.
    let base = transient_scene();
    let lambda = base.wave.wavelength_m();
    let phases: Vec<f64> = (0..24).map(|j| lambda * j as f64 / 24.0).collect();
    let touching: Vec<f64> = phases
        .iter()
        .flat_map(|&x| std::iter::repeat_n(x, 100))
        .collect();
    let mut plain = base.clone();
    plain.slider.layout = PostLayout::Positions {
        x_m: touching.clone(),
        gap_m: None,
    };
    let mut gapped = base.clone();
    let mut x_m = touching.clone();
    x_m.extend(&touching);
    let mut gap_m = vec![0.0; touching.len()];
    gap_m.extend(std::iter::repeat_n(
        50.0 * base.wave.normal_amplitude_m,
        touching.len(),
    ));
    gapped.slider.layout = PostLayout::Positions {
        x_m,
        gap_m: Some(gap_m),
    };
    // Same η: N_eff = η·N doubles with N, and the lifted half carries nothing.
    let plain_model = TransientModel::new(&plain).unwrap();
    let gapped_model = TransientModel::new(&gapped).unwrap();
    assert_eq!(
        gapped_model.phase_groups(),
        2 * plain_model.phase_groups(),
        "gaps split phase groups"
    );
    // Same start (rest): the runs must coincide to round-off, not merely settle alike.
    let a = plain_model.run(0.0, TransientStart::Rest, false).unwrap();
    let b = gapped_model.run(0.0, TransientStart::Rest, false).unwrap();
    assert!(
        (a.speed_m_per_s / b.speed_m_per_s - 1.0).abs() < 1e-6,
        "no-load speed with lifted posts {} vs without them {} m/s",
        b.speed_m_per_s,
        a.speed_m_per_s
    );
    assert!(
        (a.mean_tip_height_m - b.mean_tip_height_m).abs() < 1e-6 * base.wave.normal_amplitude_m,
        "same tip height"
    );
}

#[test]
fn every_integrator_runs_the_transient_near_the_period_average() {
    let mut scene = transient_scene();
    scene.slider.layout = PostLayout::UniformPhase { post_count: 10000 };
    scene.options.transient.uniform_phase_groups = 12;
    scene.options.transient.periods = 60.0;
    scene.options.transient.average_periods = 20.0;
    scene.contact.post_mass_kg = Some(johnson::post_mass(10e-6));
    scene.slider.vertical = VerticalModel::Dynamic { damping_ratio: 0.3 };
    let period = scene.wave.period_s();
    let v0 = PeriodicAverageModel::new(&DynamicScene {
        model: ModelChoice::PeriodicAverage,
        slider: stick_slip::Slider {
            vertical: VerticalModel::PeriodMean,
            ..scene.slider.clone()
        },
        ..scene.clone()
    })
    .unwrap()
    .no_load_speed_m_per_s()
    .unwrap();
    // Massless schemes within 0.5 %, schemes with post mass within their ≈ 2–5 % model floor.
    for (integrator, tolerance) in [
        (Integrator::EventDriven { max_step_s: None }, 5e-3),
        (
            Integrator::ReturnMapping {
                dt_s: period / 256.0,
            },
            5e-3,
        ),
        (
            Integrator::PostMass {
                dt_s: period / 256.0,
            },
            0.05,
        ),
        (
            Integrator::RegularizedExplicit {
                dt_s: period / 8192.0,
                regularization_speed_m_per_s: 0.1,
            },
            0.08,
        ),
    ] {
        scene.integrator = integrator;
        let run = TransientModel::new(&scene)
            .unwrap()
            .run(0.0, TransientStart::Estimate, false)
            .unwrap();
        let error = (run.speed_m_per_s / v0 - 1.0).abs();
        assert!(
            error < tolerance,
            "{}: no-load speed {} vs period average {v0} m/s",
            integrator.name(),
            run.speed_m_per_s
        );
        assert!(
            run.vertical_bounce_m < 0.05 * scene.wave.normal_amplitude_m,
            "{}: bounce {} m with uniform phases",
            integrator.name(),
            run.vertical_bounce_m
        );
    }
}

#[test]
fn locked_slider_does_not_advance_in_the_transient_either() {
    let mut scene = transient_scene();
    scene.slider.layout = PostLayout::SquareArray {
        posts_per_side: 33,
        pitch_m: 121e-6,
    };
    scene.slider.preload_n = 100.0;
    scene.options.transient.periods = 60.0;
    scene.options.transient.average_periods = 20.0;
    scene.options.transient.curve_loads = 2;
    let result = TransientModel::new(&scene).unwrap().solve().unwrap();
    assert!(
        result.no_load_speed_m_per_s.abs() < 1e-3,
        "locked slider's no-load speed {} m/s",
        result.no_load_speed_m_per_s
    );
    assert_eq!(result.stall_thrust_n, 0.0, "locked slider's stall thrust");
    assert!(
        result.warnings.iter().any(|w| w.message.contains("locked")),
        "warning, got {:?}",
        result.warnings
    );
}

/// Regression: an 80 × 80 array (pitch 50 µm) at 20 N with η = 0.876 reported an efficiency of
/// 1.115 at the curve point next to the no-load speed, where stator and output work are both
/// small and did not balance.
#[test]
fn efficiency_never_exceeds_one_along_the_curve() {
    let (k_n, k_t) = johnson::springs(10e-6);
    let mut scene = DynamicScene::paper_default(k_n, k_t);
    scene.slider.layout = PostLayout::SquareArray {
        posts_per_side: 80,
        pitch_m: 50e-6,
    };
    scene.slider.preload_n = 20.0;
    scene.slider.effective_ratio = 0.8761936079883987;
    let result = stick_slip::solve(&scene).unwrap();
    for point in &result.curve {
        assert!(
            point.efficiency <= 1.0,
            "efficiency {} at {} m/s",
            point.efficiency,
            point.speed_m_per_s
        );
    }
    assert!(
        result.efficiency > 0.0 && result.efficiency <= 1.0,
        "max efficiency {}",
        result.efficiency
    );
}
