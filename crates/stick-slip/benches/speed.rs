//! Speed targets: a 50-point speed–thrust curve with the period-average model in
//! ≤ 20 ms, and a transient run of the default slider (10000 posts, 100 × 100 at 40 µm pitch)
//! over 1000 wave periods in ≤ 2 s.
//!
//! `cargo bench -p stick-slip --bench speed -- --quick`

#[path = "../tests/support/johnson.rs"]
mod johnson;

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use stick_slip::{
    DynamicScene, Integrator, ModelChoice, PeriodicAverageModel, TransientModel, TransientStart,
};

fn paper_scene() -> DynamicScene {
    let (k_n, k_t) = johnson::springs(10e-6);
    DynamicScene::paper_default(k_n, k_t)
}

fn periodic_curve(c: &mut Criterion) {
    let scene = paper_scene();
    c.bench_function("periodic_average_curve_50_points", |b| {
        b.iter(|| {
            let model = PeriodicAverageModel::new(black_box(&scene)).unwrap();
            black_box(model.curve(50, &stick_slip::RunControl::none()).unwrap())
        })
    });
    c.bench_function("periodic_average_full_solve", |b| {
        b.iter(|| black_box(stick_slip::solve(black_box(&scene)).unwrap()))
    });
}

fn transient_run(c: &mut Criterion) {
    let mut scene = paper_scene();
    scene.model = ModelChoice::Transient;
    scene.options.transient.periods = 1000.0;
    scene.options.transient.average_periods = 100.0;
    let model = TransientModel::new(&scene).unwrap();
    let mut group = c.benchmark_group("transient");
    group.sample_size(10);
    group.bench_function("default_slider_1000_periods_return_mapping_T/256", |b| {
        b.iter(|| black_box(model.run(0.0, TransientStart::Estimate, false).unwrap()))
    });
    // Reference cost of the exact event-driven transient on the same slider (100 periods).
    let mut exact = scene.clone();
    exact.integrator = Integrator::EventDriven { max_step_s: None };
    exact.options.transient.periods = 100.0;
    exact.options.transient.average_periods = 20.0;
    let exact = TransientModel::new(&exact).unwrap();
    group.bench_function("default_slider_100_periods_event_driven", |b| {
        b.iter(|| black_box(exact.run(0.0, TransientStart::Estimate, false).unwrap()))
    });
    group.finish();
}

criterion_group!(benches, periodic_curve, transient_run);
criterion_main!(benches);
