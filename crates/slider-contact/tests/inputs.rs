//! Inputs of a real slider through the whole stage: a measured height map read from CSV, and
//! the refusals of bad input (each naming its field).

use std::io::Write;

use slider_contact::{
    HeightMap, HeightMapCsv, Imperfections, ImperfectionsExt, Mechanism, MechanismExt, SliderModel,
    SliderParams,
};

fn small(imperfections: Imperfections) -> SliderParams {
    SliderParams {
        posts_x: 12,
        posts_y: 8,
        slider_length_m: 12.0 * 40e-6 + 0.2e-3,
        slider_width_m: 8.0 * 40e-6 + 0.2e-3,
        preload_n: 4e-3 * 96.0,
        phases: 2,
        imperfections,
        ..SliderParams::default()
    }
}

#[test]
fn a_height_map_written_from_the_scatter_gives_the_same_post_forces() {
    let scattered = small(Imperfections {
        height_scatter_m: 5e-9,
        scatter_seed: 11,
        ..Imperfections::default()
    });
    let g = scattered.geometry();
    let offsets = scattered.imperfections.post_offsets_m(&g).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("heights.csv");
    let mut f = std::fs::File::create(&path).unwrap();
    writeln!(f, "row,column,height_m").unwrap();
    for i in 0..g.posts_x {
        for j in 0..g.posts_y {
            writeln!(f, "{j},{i},{:e}", offsets[g.index(i, j)]).unwrap();
        }
    }
    drop(f);
    let map = HeightMap::read_csv(&path, g.posts_x, g.posts_y).unwrap();
    let mapped = small(Imperfections {
        height_map: Some(map),
        ..Imperfections::default()
    });
    let a = SliderModel::build(&scattered)
        .unwrap()
        .analyse(0.384)
        .unwrap();
    let b = SliderModel::build(&mapped).unwrap().analyse(0.384).unwrap();
    for (k, (fa, fb)) in a.post_forces_n.iter().zip(&b.post_forces_n).enumerate() {
        assert!(
            (fa - fb).abs() < 1e-9 * 4e-3,
            "post {k}: force with the scatter {fa} vs with its height map {fb}"
        );
    }
    let ideal = SliderModel::build(&small(Imperfections::default()))
        .unwrap()
        .analyse(0.384)
        .unwrap();
    assert!(
        ideal.contact_fraction != a.contact_fraction || ideal.post_forces_n != a.post_forces_n,
        "5 nm of scatter must change the post forces"
    );
}

#[test]
fn bad_inputs_are_refused_naming_the_field() {
    let cases: Vec<(SliderParams, &str)> = vec![
        (
            small(Imperfections {
                height_scatter_m: -1e-9,
                ..Imperfections::default()
            }),
            "height_scatter_m",
        ),
        (
            small(Imperfections {
                tilt_y_m: 1e-3,
                ..Imperfections::default()
            }),
            "tilt_y_m",
        ),
        (
            SliderParams {
                preload_n: 0.0,
                ..small(Imperfections::default())
            },
            "preload_n",
        ),
        (
            SliderParams {
                slider_length_m: 1e-4,
                ..small(Imperfections::default())
            },
            "slider_length_m",
        ),
    ];
    for (params, field) in cases {
        let e = SliderModel::build(&params).unwrap_err().to_string();
        assert!(e.contains(field), "error must name `{field}`: {e}");
    }
    let e = Mechanism::parse("glue", None).unwrap_err().to_string();
    assert!(
        e.contains("load.mechanism"),
        "error must name load.mechanism: {e}"
    );
    assert_eq!(
        Mechanism::parse("rigid", None).unwrap(),
        Mechanism::Rigid,
        "rigid back"
    );
}

/// At the library level: each refusal is one line naming the scene key.
#[test]
fn bad_scene_inputs_are_one_line_errors_naming_the_scene_key() {
    let free = |mechanism: Mechanism, imperfections: Imperfections| SliderParams {
        mechanism,
        ..small(imperfections)
    };
    let g = small(Imperfections::default()).geometry();
    let centre = (0.5 * g.slider_length_m, 0.5 * g.slider_width_m);
    let cases: Vec<(SliderParams, &str)> = vec![
        (
            small(Imperfections {
                height_scatter_m: -1e-9,
                ..Imperfections::default()
            }),
            "posts.height_scatter",
        ),
        (
            // 20 µm across 0.68 mm lands the body corner (2 µm above the tips) first.
            small(Imperfections {
                tilt_x_m: 20e-6,
                ..Imperfections::default()
            }),
            "slider.tilt_x",
        ),
        (
            small(Imperfections {
                bow_m: -5e-6,
                ..Imperfections::default()
            }),
            "slider.bow",
        ),
        (
            free(
                Mechanism::Point {
                    x_m: g.slider_length_m + 1e-4,
                    y_m: centre.1,
                },
                Imperfections::default(),
            ),
            "load.point",
        ),
        (
            // In the margin: inside the slider, outside the post array.
            free(
                Mechanism::Point {
                    x_m: 0.05e-3,
                    y_m: centre.1,
                },
                Imperfections::default(),
            ),
            "load.point",
        ),
        (
            free(
                Mechanism::Pressure,
                Imperfections {
                    tilt_y_m: 1e-8,
                    ..Imperfections::default()
                },
            ),
            "slider.tilt_y",
        ),
        (
            small(Imperfections {
                height_map: Some(slider_contact::HeightMap {
                    file: "h.csv".into(),
                    height_m: vec![0.0; 5],
                }),
                ..Imperfections::default()
            }),
            "posts.height_map",
        ),
    ];
    for (params, key) in cases {
        let e = SliderModel::build(&params).unwrap_err().to_string();
        assert!(e.contains(key), "error must name `{key}`: {e}");
        assert!(!e.contains('\n'), "error must be one line: {e}");
    }
    let nan_map = "row,column,height_m\n0,0,NaN\n";
    let e = HeightMap::parse(nan_map, "h.csv", 1, 1)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("posts.height_map") && e.contains("line 2"),
        "a NaN height names the key and the line: {e}"
    );
    for (name, point, key) in [
        ("point", None, "load.point"),
        ("pressure", Some((1e-3, 1e-3)), "load.point"),
        ("glue", None, "load.mechanism"),
    ] {
        let e = Mechanism::parse(name, point).unwrap_err().to_string();
        assert!(e.contains(key), "`{name}`: error must name {key}: {e}");
    }
    assert_eq!(
        Mechanism::parse("point", Some((1e-3, 2e-3))).unwrap(),
        Mechanism::Point {
            x_m: 1e-3,
            y_m: 2e-3
        },
        "point mechanism with its load point"
    );
}

#[test]
fn a_local_amplitude_profile_scales_each_columns_wave_and_moves_eta() {
    let uniform = small(Imperfections::default());
    let ones = SliderParams {
        amplitude_scale_x: vec![1.0; uniform.posts_x],
        ..uniform.clone()
    };
    let falling = SliderParams {
        amplitude_scale_x: (0..uniform.posts_x)
            .map(|i| 1.0 - 0.05 * i as f64)
            .collect(),
        ..uniform.clone()
    };
    let (u, o, h) = (
        SliderModel::build(&uniform).unwrap(),
        SliderModel::build(&ones).unwrap(),
        SliderModel::build(&falling).unwrap(),
    );
    let phase = Some(0.7);
    assert_eq!(
        u.obstacle_heights(phase),
        o.obstacle_heights(phase),
        "unit profile = constant wave"
    );
    let (hu, hh) = (u.obstacle_heights(phase), h.obstacle_heights(phase));
    let g = uniform.geometry();
    for i in 0..g.posts_x {
        let idx = g.index(i, 3);
        let expected = (1.0 - 0.05 * i as f64) * hu[idx];
        assert!(
            (hh[idx] - expected).abs() <= 1e-15 * hu[idx].abs().max(1e-9),
            "column {i}"
        );
    }
    let (eu, eh) = (
        u.analyse(uniform.preload_n)
            .unwrap()
            .effective_contact_ratio,
        h.analyse(uniform.preload_n)
            .unwrap()
            .effective_contact_ratio,
    );
    assert!(
        eu.is_some() && eh.is_some() && eu != eh,
        "η fitted at the local amplitudes differs"
    );
    let wrong = SliderParams {
        amplitude_scale_x: vec![1.0; 3],
        ..uniform.clone()
    };
    let e = SliderModel::build(&wrong).unwrap_err().to_string();
    assert!(e.contains("amplitude_scale_x"), "{e}");
}
