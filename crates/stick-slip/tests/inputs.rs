//! Bad input is refused with typed errors naming the parameter; borderline input is warned
//! about; scenes and results serialise.

#[path = "support/johnson.rs"]
mod johnson;

use stick_slip::{
    DynamicScene, Integrator, ModelChoice, ModelKind, PostLayout, StabilityPolicy, StickSlipError,
    VerticalModel, curve_csv, solve,
};

fn paper_scene() -> DynamicScene {
    let (k_n, k_t) = johnson::springs(10e-6);
    DynamicScene::paper_default(k_n, k_t)
}

fn invalid_parameter(result: Result<Vec<stick_slip::Warning>, StickSlipError>) -> &'static str {
    match result {
        Err(StickSlipError::InvalidParameter { parameter, .. }) => parameter,
        other => panic!("expected an invalid-parameter error, got {other:?}"),
    }
}

#[test]
fn negative_friction_is_refused_naming_the_coefficient() {
    let mut scene = paper_scene();
    scene.contact.mu_static = -0.1;
    assert_eq!(
        invalid_parameter(scene.validate()),
        "contact.mu_static",
        "negative μ_s"
    );
    let mut scene = paper_scene();
    scene.contact.mu_kinetic = 0.5;
    assert_eq!(
        invalid_parameter(scene.validate()),
        "contact.mu_kinetic",
        "μ_k above μ_s"
    );
}

#[test]
fn zero_or_negative_preload_and_mass_are_refused() {
    for preload in [0.0, -5.0, f64::NAN] {
        let mut scene = paper_scene();
        scene.slider.preload_n = preload;
        assert_eq!(
            invalid_parameter(scene.validate()),
            "slider.preload_n",
            "preload {preload} N"
        );
    }
    for mass in [0.0, -1e-5] {
        let mut scene = paper_scene();
        scene.slider.mass_kg = mass;
        assert_eq!(
            invalid_parameter(scene.validate()),
            "slider.mass_kg",
            "mass {mass} kg"
        );
    }
    let mut scene = paper_scene();
    scene.slider.effective_ratio = 0.0;
    assert_eq!(
        invalid_parameter(scene.validate()),
        "slider.effective_ratio",
        "η = 0"
    );
}

#[test]
fn wave_faster_than_the_fastest_bulk_wave_is_refused() {
    let mut scene = paper_scene();
    scene.wave.phase_velocity_m_per_s = 8000.0;
    match scene.validate() {
        Err(StickSlipError::UnphysicalWave {
            parameter, limit, ..
        }) => {
            assert_eq!(parameter, "wave.phase_velocity_m_per_s", "parameter named");
            assert!(
                limit > 7000.0 && limit < 8000.0,
                "bulk-wave bound {limit} m/s"
            );
        }
        other => panic!("expected an unphysical-wave error, got {other:?}"),
    }
    // Between the shear and the longitudinal bound: allowed with a warning.
    scene.wave.phase_velocity_m_per_s = 5500.0;
    let warnings = scene.validate().unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.parameter == "wave.phase_velocity_m_per_s"),
        "shear-speed warning, got {warnings:?}"
    );
}

#[test]
fn wave_strained_beyond_linear_elasticity_is_refused() {
    let mut scene = paper_scene();
    // A_t ω = 1.1 m/s → strain 3e-4; 100 m/s tangential velocity is strain ≈ 2.5e-2.
    scene.wave.tangential_amplitude_m = 100.0 / scene.wave.angular_frequency_rad_per_s();
    match scene.validate() {
        Err(StickSlipError::UnphysicalWave { value, limit, .. }) => {
            assert!(
                value > limit,
                "surface strain {value} should exceed the limit {limit}"
            );
        }
        other => panic!("expected an unphysical-wave error for strain, got {other:?}"),
    }
    scene.wave.tangential_amplitude_m = 12.0 / scene.wave.angular_frequency_rad_per_s();
    let warnings = scene.validate().unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.message.contains("surface strain")),
        "strain warning, got {warnings:?}"
    );
}

#[test]
fn step_beyond_the_stability_limit_is_refused_or_warned_with_the_limit() {
    let mut scene = paper_scene();
    scene.contact.post_mass_kg = Some(johnson::post_mass(10e-6));
    let period = scene.wave.period_s();
    scene.integrator = Integrator::PostMass {
        dt_s: period / 20.0,
    };
    match scene.validate() {
        Err(StickSlipError::StepAboveStabilityLimit {
            integrator,
            step_s,
            limit_s,
            criterion,
            ..
        }) => {
            assert_eq!(integrator, "post-mass", "integrator named");
            assert!(step_s > limit_s, "step {step_s} s vs limit {limit_s} s");
            // h·ω_p < 2 with ω_p ≈ 2π·163 MHz: limit ≈ 2 ns.
            assert!(
                (1.5e-9..2.5e-9).contains(&limit_s),
                "post-mass limit {limit_s} s"
            );
            assert!(
                criterion.contains("ω_p"),
                "criterion names the post resonance: {criterion}"
            );
        }
        other => panic!("expected a stability error, got {other:?}"),
    }
    scene.options.stability = StabilityPolicy::Warn;
    let warnings = scene.validate().unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.message.contains("stability limit")),
        "stability warning, got {warnings:?}"
    );
    // Regularised friction adds a far stiffer limit.
    scene.options.stability = StabilityPolicy::Refuse;
    scene.integrator = Integrator::RegularizedExplicit {
        dt_s: period / 1000.0,
        regularization_speed_m_per_s: 1e-3,
    };
    assert!(
        matches!(
            scene.validate(),
            Err(StickSlipError::StepAboveStabilityLimit { .. })
        ),
        "regularised step refused"
    );
}

#[test]
fn coarse_return_mapping_step_is_warned_about() {
    let mut scene = paper_scene();
    scene.integrator = Integrator::ReturnMapping {
        dt_s: scene.wave.period_s() / 10.0,
    };
    let warnings = scene.validate().unwrap();
    assert!(
        warnings.iter().any(|w| w.parameter == "integrator.dt_s"),
        "accuracy warning, got {warnings:?}"
    );
}

#[test]
fn mass_schemes_without_a_post_mass_are_refused() {
    let mut scene = paper_scene();
    scene.integrator = Integrator::PostMass { dt_s: 1e-10 };
    assert!(
        matches!(
            scene.validate(),
            Err(StickSlipError::MissingPostMass {
                integrator: "post-mass"
            })
        ),
        "post-mass integrator without post_mass_kg"
    );
}

#[test]
fn inconsistent_layouts_are_refused() {
    let mut scene = paper_scene();
    scene.slider.layout = PostLayout::Positions {
        x_m: vec![0.0, 1e-4],
        gap_m: Some(vec![0.0]),
    };
    assert!(
        matches!(scene.validate(), Err(StickSlipError::InvalidLayout { .. })),
        "gap list length mismatch"
    );
    scene.slider.layout = PostLayout::Positions {
        x_m: vec![],
        gap_m: None,
    };
    assert!(
        matches!(scene.validate(), Err(StickSlipError::InvalidLayout { .. })),
        "empty layout"
    );
    scene.slider.layout = PostLayout::SquareArray {
        posts_per_side: 0,
        pitch_m: 1e-5,
    };
    assert!(
        matches!(scene.validate(), Err(StickSlipError::InvalidLayout { .. })),
        "zero posts per side"
    );
}

#[test]
fn period_average_is_refused_for_scenes_it_cannot_represent() {
    let mut scene = paper_scene();
    scene.model = ModelChoice::PeriodicAverage;
    scene.wave.burst_periods = Some(20.0);
    match solve(&scene) {
        Err(StickSlipError::ModelNotApplicable { model, reason }) => {
            assert_eq!(model, "periodic-average", "model named");
            assert!(reason.contains("burst"), "reason names the burst: {reason}");
        }
        other => panic!("expected model-not-applicable, got {other:?}"),
    }
}

/// `auto` decides by the estimated effect of the post phases on the result (speed ripple and,
/// with a dynamic vertical model, bounce), not by the phase non-uniformity alone: the
/// incommensurate 33 × 33 array on the paper's 29 mg slider runs the period average (measured
/// exact to 2e-5, validation/stick-slip), while light sliders, bursts, decaying waves and a
/// bouncing slider that the wave's harmonics shake still get the transient.
#[test]
fn auto_choice_follows_what_the_scene_needs() {
    let scene = paper_scene();
    assert_eq!(
        scene.resolve_model().unwrap().0,
        ModelKind::PeriodicAverage,
        "paper scene → period average"
    );
    let mut incommensurate = paper_scene();
    incommensurate.slider.layout = PostLayout::SquareArray {
        posts_per_side: 33,
        pitch_m: 121e-6,
    };
    let (kind, reason) = incommensurate.resolve_model().unwrap();
    assert!(
        incommensurate.phase_nonuniformity() > 0.2,
        "33 × 33 at 121 µm is far from uniform over the phase (7th harmonic)"
    );
    assert_eq!(
        kind,
        ModelKind::PeriodicAverage,
        "33 × 33 at 121 µm on the 29 mg slider → period average ({reason})"
    );
    assert!(
        reason.contains("non-uniformity") && reason.contains("speed ripple"),
        "reason states the non-uniformity and its effect: {reason}"
    );
    let mut light_incommensurate = incommensurate.clone();
    light_incommensurate.slider.mass_kg *= 1e-2;
    let (kind, reason) = light_incommensurate.resolve_model().unwrap();
    assert_eq!(
        kind,
        ModelKind::Transient,
        "33 × 33 at 121 µm on a 0.29 mg slider → transient ({reason})"
    );
    assert!(
        reason.contains("speed ripple") && reason.contains("non-uniformity"),
        "reason names the ripple and the phase non-uniformity: {reason}"
    );
    let mut light = paper_scene();
    light.slider.mass_kg = 1e-9;
    assert_eq!(
        light.resolve_model().unwrap().0,
        ModelKind::Transient,
        "1 µg slider → transient"
    );
    let mut burst = paper_scene();
    burst.wave.burst_periods = Some(20.0);
    assert_eq!(
        burst.resolve_model().unwrap().0,
        ModelKind::Transient,
        "burst → transient"
    );
    let mut decay = paper_scene();
    decay.wave.decay_length_m = Some(0.05);
    assert_eq!(
        decay.resolve_model().unwrap().0,
        ModelKind::Transient,
        "decaying wave → transient"
    );
    let mut bouncing = light_incommensurate.clone();
    bouncing.slider.vertical = VerticalModel::Dynamic {
        damping_ratio: 0.05,
    };
    assert_eq!(
        bouncing.resolve_model().unwrap().0,
        ModelKind::Transient,
        "dynamic vertical on a light slider with incommensurate posts → transient"
    );
}

/// The bounce criterion acts on its own: posts all in phase (pitch = λ) on a slider heavy
/// enough for a speed ripple below the limit but shaken vertically by the wave's harmonics.
#[test]
fn auto_runs_the_transient_for_a_slider_the_wave_makes_bounce() {
    let mut scene = paper_scene();
    scene.slider.layout = PostLayout::SquareArray {
        posts_per_side: 10,
        pitch_m: scene.wave.wavelength_m(),
    };
    scene.slider.mass_kg = 1.2e-4;
    let ripple = scene.speed_ripple_estimate();
    assert!(
        ripple < stick_slip::SPEED_RIPPLE_LIMIT,
        "speed ripple estimate {ripple} below the limit"
    );
    assert_eq!(
        scene.resolve_model().unwrap().0,
        ModelKind::PeriodicAverage,
        "period-mean vertical, small ripple → period average"
    );
    scene.slider.vertical = VerticalModel::Dynamic {
        damping_ratio: 0.05,
    };
    let bounce = scene.bounce_estimate().unwrap();
    assert!(
        bounce > stick_slip::BOUNCE_LIMIT,
        "bounce estimate {bounce} of A_n above the limit"
    );
    let (kind, reason) = scene.resolve_model().unwrap();
    assert_eq!(kind, ModelKind::Transient, "bouncing slider → transient");
    assert!(
        reason.contains("bounce"),
        "reason names the bounce: {reason}"
    );
    scene.slider.mass_kg *= 10.0;
    assert_eq!(
        scene.resolve_model().unwrap().0,
        ModelKind::PeriodicAverage,
        "ten times heavier: bounce {:.1e} of A_n → period average",
        scene.bounce_estimate().unwrap()
    );
}

#[test]
fn scene_round_trips_through_json_and_toml() {
    let mut scene = paper_scene();
    scene.integrator = Integrator::ReturnMapping { dt_s: 1e-10 };
    scene.wave.burst_periods = Some(50.0);
    let json = serde_json::to_string(&scene).unwrap();
    let back: DynamicScene = serde_json::from_str(&json).unwrap();
    assert_eq!(back, scene, "JSON round trip");
    let toml_text = toml::to_string(&scene).unwrap();
    let back: DynamicScene = toml::from_str(&toml_text).unwrap();
    assert_eq!(back, scene, "TOML round trip");
    // Minimal scene: defaults fill model, integrator, options, η, vertical and load.
    let minimal = r#"
        [wave]
        frequency_hz = 9.61e6
        normal_amplitude_m = 20e-9
        tangential_amplitude_m = 18.2e-9
        phase_velocity_m_per_s = 3979.0
        [contact]
        k_n_n_per_m = 1.8e6
        k_t_n_per_m = 1.5e6
        mu_static = 0.3
        mu_kinetic = 0.3
        [slider]
        mass_kg = 2.9e-5
        preload_n = 40.0
        layout = { kind = "square-array", posts_per_side = 100, pitch_m = 40e-6 }
    "#;
    let parsed: DynamicScene = toml::from_str(minimal).unwrap();
    assert_eq!(parsed.integrator, Integrator::Auto, "default integrator");
    assert_eq!(parsed.slider.effective_ratio, 1.0, "default η");
    let typo = minimal.replace("preload_n", "preload");
    assert!(
        toml::from_str::<DynamicScene>(&typo).is_err(),
        "unknown field `preload` must be refused"
    );
}

#[test]
fn result_serialises_with_the_documented_keys_and_csv_header() {
    let result = solve(&paper_scene()).unwrap();
    let json: serde_json::Value = serde_json::to_value(&result).unwrap();
    for key in [
        "stall_thrust_n",
        "no_load_speed_m_per_s",
        "curve",
        "stick_fraction",
        "efficiency",
        "model",
        "wall_time_s",
    ] {
        assert!(json.get(key).is_some(), "result JSON lacks `{key}`");
    }
    assert_eq!(json["model"], "periodic-average", "model key value");
    let point = &json["curve"][0];
    assert!(
        point.get("speed_m_per_s").is_some() && point.get("thrust_n").is_some(),
        "curve point keys"
    );
    let csv = curve_csv(&result.curve);
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("speed_m_per_s,thrust_n,output_power_w,efficiency,stick_fraction"),
        "CSV header"
    );
    assert_eq!(
        lines.count(),
        result.curve.len(),
        "one CSV row per curve point"
    );
}

#[cfg(feature = "charts")]
#[test]
fn histories_for_the_charts_cover_the_requested_periods() {
    let scene = paper_scene();
    let (result, histories) =
        stick_slip::solve_with_histories(&scene, &stick_slip::RunControl::none()).unwrap();
    let post = &histories.post;
    let span = post.time_s.last().unwrap() - post.time_s[0];
    let expected = scene.options.history.periods * scene.wave.period_s();
    assert!(
        (span / expected - 1.0).abs() < 1e-3,
        "history span {span} s vs {expected} s (Doppler-shifted periods)"
    );
    assert!(
        !post.stick_intervals_s.is_empty(),
        "stick intervals of the post"
    );
    assert!(
        post.normal_force_n.iter().all(|&n| n >= 0.0),
        "normal force never tensile"
    );
    let bound_ok = post
        .tangential_force_n
        .iter()
        .zip(&post.friction_bound_n)
        .all(|(f, b)| f.abs() <= b * (1.0 + 1e-9) + 1e-15);
    assert!(bound_ok, "|F| ≤ μ_k N at every sample (μ_s = μ_k)");
    let dir = tempfile::tempdir().unwrap();
    let files = stick_slip::plots::write_post_history_chart("test", post, &dir.path().join("fig6"))
        .unwrap();
    assert!(files[0].exists(), "Fig. 6 chart written");
    let files =
        stick_slip::plots::write_speed_thrust_chart(&result, &dir.path().join("curve")).unwrap();
    assert!(files[0].exists(), "speed–thrust chart written");
    stick_slip::write_curve_csv(&result.curve, &dir.path().join("curve.csv")).unwrap();
    assert!(dir.path().join("curve.csv").exists(), "curve CSV written");
}

#[test]
fn four_billion_transient_periods_are_refused_with_the_memory_estimate_before_allocating() {
    let mut scene = paper_scene();
    scene.model = ModelChoice::Transient;
    scene.options.transient.periods = 4_294_967_295.0;
    match scene.validate() {
        Err(StickSlipError::MemoryLimit {
            parameter,
            estimate_bytes,
            limit_bytes,
        }) => {
            assert_eq!(parameter, "options.transient.periods", "the size at fault");
            assert!(
                estimate_bytes > 1e11 && limit_bytes == stick_slip::MAX_RUN_MEMORY_BYTES,
                "memory estimate {estimate_bytes} B against the limit {limit_bytes} B"
            );
        }
        other => panic!("expected a memory-limit error, got {other:?}"),
    }
    let mut scene = paper_scene();
    scene.options.curve_points = 4_000_000_000;
    assert!(
        matches!(
            scene.validate(),
            Err(StickSlipError::MemoryLimit {
                parameter: "options.curve_points",
                ..
            })
        ),
        "4·10⁹ curve points refused naming options.curve_points"
    );
}

#[test]
fn a_regularized_run_above_the_cost_limit_is_refused_with_its_estimate() {
    let mut scene = paper_scene();
    scene.model = ModelChoice::Transient;
    scene.contact.post_mass_kg = Some(1.46e-12);
    let period = scene.wave.period_s();
    scene.integrator = Integrator::RegularizedExplicit {
        dt_s: period / 7e5,
        regularization_speed_m_per_s: 1.1e-3,
    };
    scene.options.stability = StabilityPolicy::Warn;
    match scene.validate() {
        Err(StickSlipError::CostLimit {
            estimate_post_steps,
            limit_post_steps,
            ..
        }) => assert!(
            estimate_post_steps > limit_post_steps
                && limit_post_steps == stick_slip::MAX_POST_STEPS,
            "cost estimate {estimate_post_steps} post-steps above the limit {limit_post_steps}"
        ),
        other => panic!("expected a cost-limit error, got {other:?}"),
    }
    let work = scene.work_estimate(ModelKind::Transient, &scene.integrator);
    assert!(
        (work.steps_per_period / 7e5 - 1.0).abs() < 1e-6,
        "steps per period {} from T/dt",
        work.steps_per_period
    );
    scene.options.max_post_steps = 1.1 * work.post_steps();
    assert!(
        !matches!(scene.validate(), Err(StickSlipError::CostLimit { .. })),
        "a raised max_post_steps admits the same run"
    );
}
