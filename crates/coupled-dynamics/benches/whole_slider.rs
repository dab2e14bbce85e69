//! Cost of the whole slider's coupled model (target: the default slider's coupled curve ≤ 60 s
//! on 2 cores). Pieces, each on the paper's 100 × 100-post slider unless named: one product
//! with the tangential lattice operator (the unit of the step solves) and with its y-mirror-folded
//! form (the ideal slider's), the normal grid (64 phases
//! of the static contact solve), a curve point of a 30 × 30 slider, and the default slider's
//! stall point (≈ 20 s per sample: run it alone with a filter).
//!
//! `cargo bench -p coupled-dynamics --bench whole_slider` (all; ≈ 5 min)
//! `cargo bench -p coupled-dynamics --bench whole_slider -- "tangential product"`

use std::sync::Arc;

use coupled_dynamics::{SliderDynamics, SliderScene};
use criterion::{Criterion, criterion_group, criterion_main};
use motor::Motor;
use slider_contact::{ComplianceOperator, LatticeOperator, NearField, SliderModel, SliderParams};

/// The paper's slider cut to `side` × `side` posts (same pitch and margins, preload per post).
fn params(side: usize) -> SliderParams {
    let mut p = SliderParams::for_motor(&Motor::paper());
    let share = (side * side) as f64 / (p.posts_x * p.posts_y) as f64;
    let margin_x = p.slider_length_m - p.posts_x as f64 * p.post_pitch_m;
    let margin_y = p.slider_width_m - p.posts_y as f64 * p.post_pitch_m;
    p.posts_x = side;
    p.posts_y = side;
    p.slider_length_m = side as f64 * p.post_pitch_m + margin_x;
    p.slider_width_m = side as f64 * p.post_pitch_m + margin_y;
    p.preload_n *= share;
    p
}

fn scene(model: &SliderModel) -> SliderScene {
    let motor = Motor::paper();
    let mut s = SliderScene::for_static(
        model,
        motor.wave.clone(),
        motor.friction.mu_static,
        motor.friction.mu_kinetic,
    );
    s.steps_per_period = 64;
    s
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("whole slider");
    group.sample_size(10);
    let default = SliderModel::build(&params(100)).unwrap();
    let spec = default.params.operator_spec();
    let ct = LatticeOperator::tangential(&spec, NearField::Johnson).unwrap();
    let f: Vec<f64> = (0..ct.len())
        .map(|i| ((i * 37 % 11) as f64) * 1e-4)
        .collect();
    let mut u = vec![0.0; ct.len()];
    group.bench_function("tangential product, 100 × 100 posts", |b| {
        b.iter(|| ct.apply(&f, &mut u))
    });
    let folded = slider_contact::TangentialKernel::new(&spec, NearField::Johnson)
        .unwrap()
        .mirror_operator(&spec.geometry)
        .unwrap();
    let (f_half, mut u_half) = (f[..folded.len()].to_vec(), vec![0.0; folded.len()]);
    group.bench_function("mirror-folded tangential product, 100 × 50 posts", |b| {
        b.iter(|| folded.apply(&f_half, &mut u_half))
    });
    let default_scene = scene(&default);
    group.bench_function("normal grid, 64 phases, 100 × 100 posts", |b| {
        b.iter(|| SliderDynamics::new(&default_scene, &default, Arc::new(ct.clone())).unwrap())
    });
    let small = SliderModel::build(&params(30)).unwrap();
    let small_dynamics =
        SliderDynamics::for_slider(&scene(&small), &small, NearField::Johnson).unwrap();
    let v = 0.5 * small_dynamics.model().crest_speed_m_per_s();
    group.bench_function("curve point at half the crest speed, 30 × 30 posts", |b| {
        b.iter(|| small_dynamics.model().at_speed(v).unwrap())
    });
    let dynamics =
        SliderDynamics::for_slider(&default_scene, &default, NearField::Johnson).unwrap();
    group.bench_function("stall point, 100 × 100 posts", |b| {
        b.iter(|| dynamics.model().at_speed(0.0).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
