//! Cost of the energy-conserving wave: the attenuated speed–thrust curve (period average, every
//! column its own bin, and 20 bins) against the constant-amplitude curve of the default motor
//! (`Motor::paper()` springs, 50 points) at 40 and 100 N; the transient at 40 N: one run at no
//! load and at 5 N (200 periods, the last 80 averaged: the study's) constant, with the profile
//! adjusted inside the run, and one run per fixed-point evaluation; and the whole transient
//! curve (120 periods, 40 averaged, 3 curve loads) the same three ways. One run.
//!
//! `cargo bench -p stick-slip --bench attenuation -- --quick`

#[path = "../tests/support/johnson.rs"]
mod johnson;

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use stick_slip::{
    AttenuatedPeriodicModel, AttenuationOptions, DynamicScene, ModelChoice, PeriodicAverageModel,
    ProfileIteration, TransientModel, TransientStart,
};

/// `sawdrive wave --json`'s `power_under_array_w` for the paper wave (W).
const POWER_UNDER_ARRAY_W: f64 = 9.78634644379686;

fn curves(c: &mut Criterion) {
    let (k_n, k_t) = johnson::springs(10e-6);
    let mut group = c.benchmark_group("attenuation");
    group.sample_size(10);
    for preload in [40.0, 100.0] {
        let mut scene = DynamicScene::paper_default(k_n, k_t);
        scene.slider.preload_n = preload;
        group.bench_function(format!("constant_curve_{preload}N"), |b| {
            b.iter(|| {
                black_box(
                    PeriodicAverageModel::new(black_box(&scene))
                        .unwrap()
                        .solve(&stick_slip::RunControl::none())
                        .unwrap(),
                )
            })
        });
        for bins in [None, Some(20)] {
            let mut options = AttenuationOptions::new(POWER_UNDER_ARRAY_W);
            options.bins = bins;
            let name = match bins {
                None => format!("attenuated_curve_{preload}N_every_column"),
                Some(n) => format!("attenuated_curve_{preload}N_{n}_bins"),
            };
            group.bench_function(name, |b| {
                b.iter(|| {
                    black_box(
                        AttenuatedPeriodicModel::new(black_box(&scene), &options)
                            .unwrap()
                            .solve()
                            .unwrap(),
                    )
                })
            });
        }
    }
    group.finish();
}

fn transient_scene(periods: f64, average_periods: f64) -> DynamicScene {
    let (k_n, k_t) = johnson::springs(10e-6);
    let mut scene = DynamicScene::paper_default(k_n, k_t);
    scene.slider.preload_n = 40.0;
    scene.model = ModelChoice::Transient;
    scene.options.transient.periods = periods;
    scene.options.transient.average_periods = average_periods;
    scene
}

fn schemes() -> [(&'static str, AttenuationOptions); 2] {
    let mut in_run = AttenuationOptions::new(POWER_UNDER_ARRAY_W);
    in_run.tolerance = 1e-6;
    let mut per_run = in_run;
    per_run.transient_iteration = ProfileIteration::PerRun;
    [("in_run", in_run), ("per_run", per_run)]
}

fn transient(c: &mut Criterion) {
    let mut group = c.benchmark_group("attenuation_transient");
    group.sample_size(10);
    let model = TransientModel::new(&transient_scene(200.0, 80.0)).unwrap();
    for load in [0.0, 5.0] {
        group.bench_function(format!("constant_run_40N_load_{load}N"), |b| {
            b.iter(|| black_box(model.run(load, TransientStart::Estimate, false).unwrap()))
        });
        for (name, options) in schemes() {
            group.bench_function(format!("attenuated_run_40N_load_{load}N_{name}"), |b| {
                b.iter(|| {
                    black_box(
                        model
                            .run_attenuated(load, TransientStart::Estimate, &options, None)
                            .unwrap(),
                    )
                })
            });
        }
    }
    let mut scene = transient_scene(120.0, 40.0);
    scene.options.transient.curve_loads = 3;
    scene.options.transient.stall_tolerance = 5e-3;
    let model = TransientModel::new(&scene).unwrap();
    group.bench_function("constant_curve_40N", |b| {
        b.iter(|| black_box(model.solve().unwrap()))
    });
    for (name, options) in schemes() {
        group.bench_function(format!("attenuated_curve_40N_{name}"), |b| {
            b.iter(|| black_box(model.solve_attenuated(&options).unwrap()))
        });
    }
    group.finish();
}

criterion_group!(benches, curves, transient);
criterion_main!(benches);
