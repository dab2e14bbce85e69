//! Bad input is refused with a typed error naming the field; the wave is stick-slip's.

use ball_slider::{BallError, BallModel, BallScene, BallSlider, solve};

/// A field name and how to spoil it.
type Spoil = (&'static str, Box<dyn Fn(&mut BallScene)>);

fn field_of(scene: &BallScene) -> &'static str {
    match scene.validate() {
        Err(BallError::InvalidParameter { field, .. }) => field,
        Err(BallError::Material { field, .. }) => field,
        Err(BallError::UnsupportedWave { field, .. }) => field,
        other => panic!("expected a refusal naming a field, got {other:?}"),
    }
}

#[test]
fn bad_input_is_refused_naming_the_field() {
    let cases: Vec<Spoil> = vec![
        ("ball.diameter_m", Box::new(|s| s.ball.diameter_m = -2e-3)),
        (
            "ball.diameter_m",
            Box::new(|s| s.ball.diameter_m = f64::NAN),
        ),
        (
            "ball.moving_mass_kg",
            Box::new(|s| s.ball.moving_mass_kg = Some(0.0)),
        ),
        (
            "friction_coefficient",
            Box::new(|s| s.friction_coefficient = 0.0),
        ),
        (
            "friction_coefficient",
            Box::new(|s| s.friction_coefficient = -0.3),
        ),
        ("preload_n", Box::new(|s| s.preload_n = f64::INFINITY)),
        ("preload_n", Box::new(|s| s.preload_n = 0.0)),
        ("external_load_n", Box::new(|s| s.external_load_n = -1.0)),
        (
            "wave.normal_amplitude_m",
            Box::new(|s| s.wave.normal_amplitude_m = f64::NAN),
        ),
        ("wave.frequency_hz", Box::new(|s| s.wave.frequency_hz = 0.0)),
        (
            "wave.decay_length_m",
            Box::new(|s| s.wave.decay_length_m = Some(1e-3)),
        ),
        (
            "wave.burst_periods",
            Box::new(|s| s.wave.burst_periods = Some(10.0)),
        ),
        (
            "ball.material",
            Box::new(|s| s.ball.material.poisson_ratio = 0.6),
        ),
        ("stator", Box::new(|s| s.stator.shear_modulus_pa = -1.0)),
        (
            "numerics.steps_per_period",
            Box::new(|s| s.numerics.steps_per_period = 2),
        ),
        ("numerics.springs", Box::new(|s| s.numerics.springs = 0)),
    ];
    for (field, spoil) in cases {
        let mut scene = BallScene::default_ball();
        spoil(&mut scene);
        assert_eq!(field_of(&scene), field, "the refusal must name {field}");
        let message = solve(&scene).unwrap_err().to_string();
        assert!(
            message.contains(field),
            "message must name {field}: {message}"
        );
        assert!(
            BallModel::new(&scene).is_err(),
            "the model must refuse {field} too"
        );
    }
}

#[test]
fn scene_reads_from_json_refusing_unknown_fields() {
    let scene = BallScene::default_ball();
    let text = serde_json::to_string(&scene).unwrap();
    assert!(text.contains("\"diameter_m\":0.002"));
    let mut value: serde_json::Value = serde_json::from_str(&text).unwrap();
    value["ball"]["diameter_mm"] = serde_json::json!(2.0);
    let err = serde_json::from_value::<BallScene>(value)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("diameter_mm"),
        "unknown key must be named: {err}"
    );
    let ball: BallSlider = serde_json::from_str(
        r#"{"diameter_m": 1e-3, "material": {"name": "steel", "shear_modulus_pa": 8.08e10, "poisson_ratio": 0.3, "density_kg_per_m3": 7810}}"#,
    )
    .unwrap();
    assert!(
        (ball.mass_kg() - 7810.0 * std::f64::consts::PI * 1e-9 / 6.0).abs() < 1e-15,
        "ρπd³/6"
    );
}

#[test]
fn wave_is_stick_slips_and_both_models_drive_against_the_wave() {
    // The same type: stick-slip's wave goes into the ball scene unchanged.
    let wave: stick_slip::Wave = stick_slip::Wave::paper_default();
    let mut scene = BallScene::default_ball();
    scene.wave = wave.clone();
    scene.numerics.free_periods = 0;
    let ball = solve(&scene).unwrap();
    let posts =
        stick_slip::solve(&stick_slip::DynamicScene::paper_default(1.786e6, 1.528e6)).unwrap();
    assert_eq!(
        ball.crest_speed_m_per_s, posts.crest_speed_m_per_s,
        "crest speed A_tω of the one wave"
    );
    for (name, v0, crest) in [
        ("ball", ball.no_load_speed_m_per_s, ball.crest_speed_m_per_s),
        (
            "posts",
            posts.no_load_speed_m_per_s,
            posts.crest_speed_m_per_s,
        ),
    ] {
        assert!(
            v0 > 0.0 && v0 < crest,
            "{name}: no-load speed {v0} m/s along the drive direction (−x), below {crest}"
        );
    }
}
