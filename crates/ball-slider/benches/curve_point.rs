//! Speed target: one curve point of the default ball (2 mm steel, 20 mN, 20 nm wave: the
//! imposed-speed periodic state plus its 100-period free-ball confirmation) well under a
//! second in release.
//!
//! `cargo bench -p ball-slider --bench curve_point -- --quick`

use std::hint::black_box;

use ball_slider::{BallModel, BallScene, solve};
use criterion::{Criterion, criterion_group, criterion_main};

fn curve_point(c: &mut Criterion) {
    let scene = BallScene::default_ball();
    let model = BallModel::new(&scene).unwrap();
    c.bench_function("ball_imposed_speed_period", |b| {
        b.iter(|| black_box(model.at_speed(black_box(0.2)).unwrap()))
    });
    c.bench_function("ball_curve_point_with_free_check", |b| {
        b.iter(|| black_box(model.curve_point(black_box(0.2)).unwrap()))
    });
    let mut group = c.benchmark_group("ball_solve");
    group.sample_size(10);
    group.bench_function("default_21_points", |b| {
        b.iter(|| black_box(solve(black_box(&scene)).unwrap()))
    });
    group.finish();
}

criterion_group!(benches, curve_point);
criterion_main!(benches);
