//! Scene files: the embedded default, layering, units and refusals.

use std::io::Write;

use sawdrive::scene::{DEFAULT_SCENE_TOML, SceneError, load_scene};

fn scene_file(text: &str) -> tempfile::NamedTempFile {
    let mut file = tempfile::Builder::new().suffix(".toml").tempfile().unwrap();
    file.write_all(text.as_bytes()).unwrap();
    file
}

fn error_of(text: &str, overrides: &[&str]) -> String {
    let file = scene_file(text);
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    load_scene(Some(file.path()), &overrides)
        .expect_err("scene must be refused")
        .to_string()
}

#[test]
fn default_scene_is_the_papers_motor() {
    let scene = load_scene(None, &[]).unwrap();
    assert_eq!(scene.motor.wave.frequency_hz, 9.61e6, "frequency");
    assert_eq!(
        scene.motor.wave.normal_amplitude_m, 20e-9,
        "normal amplitude"
    );
    let omega = 2.0 * std::f64::consts::PI * 9.61e6;
    assert!(
        (scene.motor.wave.tangential_amplitude_m - 1.1 / omega).abs() < 1e-20,
        "A_t = V_t/ω ≈ 18.2 nm"
    );
    assert_eq!(
        (
            scene.motor.posts.count_x,
            scene.motor.posts.count_y,
            scene.motor.posts.count()
        ),
        (100, 100, 10_000),
        "post count"
    );
    assert!(
        (scene.motor.posts.pitch_x_m() - 40e-6).abs() < 1e-15,
        "pitch 40 µm"
    );
    assert_eq!(scene.motor.posts.diameter_m, 20e-6, "post diameter");
    assert_eq!(scene.motor.slider.material.name, "si");
    assert_eq!(scene.motor.stator.name, "linbo3");
    let expected_mass = 2329.0 * 5e-3 * 5e-3 * 0.5e-3;
    assert!(
        (scene.motor.slider.mass_kg - expected_mass).abs() < 1e-15,
        "mass from geometry"
    );
    assert_eq!(scene.contact.effective_ratio_source, "fem");
    // λ = c/f ≈ 414 µm
    assert!(
        (scene.motor.wave.wavelength_m() - 3979.0 / 9.61e6).abs() < 1e-15,
        "wavelength"
    );
}

#[test]
fn printed_default_scene_reads_back_as_a_scene_file() {
    let file = scene_file(DEFAULT_SCENE_TOML);
    assert_eq!(
        load_scene(Some(file.path()), &[]).unwrap(),
        load_scene(None, &[]).unwrap()
    );
}

#[test]
fn a_partial_scene_overrides_only_what_it_gives() {
    let file = scene_file(
        "name = \"light\"\n[slider]\nmass = \"5 mg\"\n[model]\ndynamics = \"transient\"\n",
    );
    let scene = load_scene(Some(file.path()), &[]).unwrap();
    assert_eq!(scene.name, "light");
    assert!(
        (scene.motor.slider.mass_kg - 5e-6).abs() < 1e-18,
        "given mass"
    );
    assert_eq!(
        scene.model.dynamics,
        sawdrive::scene::Dynamics::Lumped(stick_slip::ModelChoice::Transient)
    );
    assert_eq!(
        scene.motor.posts.count(),
        10_000,
        "untouched keys keep the default"
    );
}

#[test]
fn set_overrides_accept_short_names_and_human_units() {
    let overrides: Vec<String> = [
        "preload=20N",
        "posts.count=50x50",
        "posts.diameter=30 um",
        "friction=0.2",
        "effective_ratio=0.36",
    ]
    .map(String::from)
    .to_vec();
    let scene = load_scene(None, &overrides).unwrap();
    assert_eq!(scene.motor.load.preload_n, 20.0, "preload");
    assert_eq!(scene.motor.posts.count(), 2500, "post count");
    assert!(
        (scene.motor.posts.diameter_m - 30e-6).abs() < 1e-18,
        "diameter"
    );
    assert_eq!(
        (
            scene.motor.friction.mu_static,
            scene.motor.friction.mu_kinetic
        ),
        (0.2, 0.2),
        "friction"
    );
    assert_eq!(scene.contact.effective_ratio, Some(0.36), "η");
}

#[test]
fn tangential_amplitude_may_replace_the_velocity() {
    let file = scene_file("[wave]\ntangential_amplitude = \"10 nm\"\n");
    let scene = load_scene(Some(file.path()), &[]).unwrap();
    assert_eq!(scene.motor.wave.tangential_amplitude_m, 10e-9);
    let omega = 2.0 * std::f64::consts::PI * 9.61e6;
    assert!((scene.motor.wave.crest_speed_m_per_s() - 10e-9 * omega).abs() < 1e-12);
}

#[test]
fn every_refusal_names_the_field_at_fault() {
    let cases: [(&str, &[&str], &str); 12] = [
        ("[posts]\ndiametre = \"20 um\"\n", &[], "posts.diametre"),
        ("[posts]\ndiameter = 20\n", &[], "posts.diameter"),
        ("[posts]\ndiameter = \"20 kg\"\n", &[], "posts.diameter"),
        ("[posts]\ndiameter = \"-20 um\"\n", &[], "posts.diameter"),
        ("[posts]\ncount = \"100\"\n", &[], "posts.count"),
        ("[slider]\nthickness = \"0 mm\"\n", &[], "slider.thickness"),
        (
            "[slider]\nmaterial = { shear_modulus = \"1 GPa\", poisson_ratio = 0.5, density = \"1 g/cm3\" }\n",
            &[],
            "slider.material",
        ),
        ("[stator]\nmaterial = \"steel\"\n", &[], "stator.material"),
        ("[load]\npreload = \"0 N\"\n", &[], "load.preload"),
        ("", &["friction=-0.1"], "friction.static"),
        (
            "",
            &["model.lumped.vertical=sideways"],
            "model.lumped.vertical",
        ),
        (
            "[wave]\nfrequency = \"9.61 MHz\"\ncolour = \"red\"\n",
            &[],
            "wave.colour",
        ),
    ];
    for (text, overrides, field) in cases {
        let message = error_of(text, overrides);
        assert!(
            message.contains(field),
            "error for {field} must name it: {message}"
        );
        assert!(!message.contains('\n'), "one-line error: {message}");
    }
}

#[test]
fn syntax_errors_and_missing_files_name_the_file() {
    let file = scene_file("[wave\n");
    let message = load_scene(Some(file.path()), &[]).unwrap_err().to_string();
    assert!(
        message.contains(&file.path().display().to_string()) && message.contains("line 1"),
        "{message}"
    );
    let missing = std::path::Path::new("/nonexistent/scene.toml");
    assert!(matches!(
        load_scene(Some(missing), &[]),
        Err(SceneError::Io { .. })
    ));
}

#[test]
fn malformed_set_is_refused() {
    let message = load_scene(None, &["preload".to_string()])
        .unwrap_err()
        .to_string();
    assert!(message.starts_with("--set preload"), "{message}");
}

#[test]
fn overflowing_underflowing_and_non_decimal_values_are_refused_naming_the_key() {
    let cases: [(&str, &[&str], &str); 8] = [
        ("", &["wave.frequency=1e308 GHz"], "wave.frequency"),
        ("", &["wave.frequency=4.9e-324 MHz"], "wave.frequency"),
        ("", &["posts.diameter=1e-200 m"], "posts.diameter"),
        ("", &["posts.count=0x5"], "posts.count"),
        ("", &["posts.count=+5x5"], "posts.count"),
        (
            "",
            &["model.transient.periods=0x10"],
            "model.transient.periods",
        ),
        (
            "[model.transient]\nperiods = 0x10\n",
            &[],
            "model.transient.periods",
        ),
        ("[posts]\ncount = \"0x5x5\"\n", &[], "posts.count"),
    ];
    for (text, overrides, field) in cases {
        let message = error_of(text, overrides);
        assert!(
            message.contains(field),
            "error for {field} ({text}{overrides:?}) must name it: {message}"
        );
        assert!(!message.contains('\n'), "one-line error: {message}");
    }
}

#[test]
fn an_effective_ratio_the_fem_reports_above_one_reads_back_and_the_bound_is_shared() {
    let file = scene_file("name = \"sparse\"\n[contact]\neffective_ratio = 1.03\n");
    let scene = load_scene(Some(file.path()), &[]).expect("η = 1.03 (FEM, sparse array at 5 N)");
    assert_eq!(scene.contact.effective_ratio, Some(1.03), "η read back");
    let limit = contact_springs::effective_ratio::MAX_EFFECTIVE_RATIO;
    let message = error_of("", &[&format!("effective_ratio={}", limit * 1.01)]);
    assert!(
        message.contains("contact.effective_ratio") && message.contains("1.5"),
        "η above the shared bound refused naming the key and the bound: {message}"
    );
    let mut dynamic = stick_slip::DynamicScene::paper_default(1.8e6, 1.5e6);
    dynamic.slider.effective_ratio = 1.03;
    assert!(
        dynamic.validate().is_ok(),
        "stick-slip accepts the same η = 1.03"
    );
    dynamic.slider.effective_ratio = limit * 1.01;
    assert!(
        dynamic.validate().is_err(),
        "stick-slip refuses η above the same bound"
    );
}

/// The embedded default scene (human units, with comments) and the libraries' one copy of the
/// paper's numbers (`motor::Motor::paper`) describe the same motor, bit for bit.
#[test]
fn default_scene_resolves_into_motor_paper() {
    let scene = load_scene(None, &[]).expect("default scene");
    assert_eq!(
        scene.motor,
        motor::Motor::paper(),
        "default.toml vs Motor::paper()"
    );
}

#[test]
fn static_tolerance_auto_gives_each_static_model_its_own_and_a_given_value_is_used_by_both() {
    use sawdrive::scene::StaticModel;
    let auto = load_scene(None, &[]).unwrap().static_fem;
    assert_eq!(auto.tolerance, None, "the default static.tolerance is auto");
    assert_eq!(auto.tolerance_for(StaticModel::Strip), 1e-10, "strip");
    assert_eq!(
        auto.tolerance_for(StaticModel::Slider),
        slider_contact::DEFAULT_TOLERANCE,
        "whole slider"
    );
    let given = load_scene(None, &["static.tolerance=1e-10".to_string()])
        .unwrap()
        .static_fem;
    for model in [StaticModel::Strip, StaticModel::Slider] {
        assert_eq!(
            given.tolerance_for(model),
            1e-10,
            "a given tolerance for {model:?}"
        );
    }
    let e = load_scene(None, &["static.tolerance=-1".to_string()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("static.tolerance"), "{e}");
}

#[test]
fn static_fem_solver_defaults_to_auto_takes_the_three_names_and_refuses_others_in_one_line() {
    use static_contact::FemSolver;
    let solver = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        load_scene(None, &sets).map(|s| s.static_fem.fem_solver)
    };
    assert_eq!(
        solver(&[]).unwrap(),
        FemSolver::Auto,
        "default static.fem_solver"
    );
    for (name, value) in [
        ("direct", FemSolver::Direct),
        ("iterative", FemSolver::Iterative),
        ("auto", FemSolver::Auto),
    ] {
        let set = format!("static.fem_solver={name}");
        assert_eq!(solver(&[set.as_str()]).unwrap(), value, "{set}");
    }
    let e = solver(&["static.fem_solver=cholesky"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("static.fem_solver"), "names the key: {e}");
    assert!(e.contains("\"iterative\""), "lists the choices: {e}");
    assert_eq!(e.trim().lines().count(), 1, "one line: {e}");
}

#[test]
fn each_models_settings_are_set_in_its_own_sub_table() {
    let set = |o: &[&str]| {
        let o: Vec<String> = o.iter().map(|s| s.to_string()).collect();
        load_scene(None, &o).unwrap()
    };
    let coupled = set(&["model.coupled.steps_per_period=96"]);
    assert_eq!(coupled.model.steps_per_period, Some(96));
    let transient = set(&["model.dynamics=transient", "model.transient.periods=300"]);
    assert_eq!(transient.model.periods, Some(300));
    let lumped = set(&[
        "model.lumped.integrator=post-mass",
        "model.lumped.time_step=5ns",
    ]);
    assert_eq!(lumped.model.time_step_s, Some(5e-9));
    let text = "name = \"sub\"\n[model.coupled]\nsteps_per_period = 32\n";
    let file = scene_file(text);
    let from_file = load_scene(Some(file.path()), &[]).unwrap();
    assert_eq!(from_file.model.steps_per_period, Some(32));
}

#[test]
fn an_old_flat_model_key_is_refused_naming_its_new_spelling() {
    for (old, new) in [
        ("steps_per_period = 96", "model.coupled.steps_per_period"),
        ("periods = 300", "model.transient.periods"),
        ("integrator = \"post-mass\"", "model.lumped.integrator"),
        ("time_step = \"5 ns\"", "model.lumped.time_step"),
        ("vertical = \"dynamic\"", "model.lumped.vertical"),
    ] {
        let e = error_of(&format!("name = \"old\"\n[model]\n{old}\n"), &[]);
        assert!(e.contains(new), "{old}: {e}");
        let key = old.split(' ').next().unwrap();
        assert!(e.contains(&format!("model.{key}")), "{old}: {e}");
    }
    let e = error_of("name = \"old\"\n", &["model.steps_per_period=96"]);
    assert!(e.contains("model.coupled.steps_per_period"), "{e}");
}

#[test]
fn a_misplaced_or_unused_model_setting_is_refused_by_name() {
    for (text, overrides, key) in [
        (
            "[model.coupled]\nperiods = 10\n",
            &[][..],
            "model.coupled.periods",
        ),
        (
            "",
            &[
                "model.dynamics=periodic-average",
                "model.transient.periods=10",
            ][..],
            "model.transient.periods",
        ),
        (
            "",
            &[
                "model.dynamics=transient",
                "model.coupled.steps_per_period=64",
            ][..],
            "model.coupled.steps_per_period",
        ),
        (
            "",
            &["model.ball.steps_per_period=64"][..],
            "model.ball.steps_per_period",
        ),
    ] {
        let e = error_of(&format!("name = \"m\"\n{text}"), overrides);
        assert!(e.contains(key), "{text} {overrides:?}: {e}");
    }
}
