//! Cost of the coupled model (target: the default slider's row, 100 posts, 50-point
//! curve ≤ 10 s). The compliance is the row's analytic part — Johnson post springs on the
//! diagonal plus the half-space normal and tangential terms of all 100 rows — so the bench
//! needs no meshing; the FEM strip gives the same matrix sizes and solver work (see the
//! `default_row` ignored test for the FEM compliance: 4.1 s per curve in the test profile).
//!
//! `cargo bench -p coupled-dynamics --bench curve`

use coupled_dynamics::{CoupledModel, solve};
use criterion::{Criterion, criterion_group, criterion_main};

#[path = "../examples/common/mod.rs"]
mod common;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("coupled");
    group.sample_size(10);
    for n in [25, 50, 100] {
        let model = CoupledModel::new(&common::analytic_row(n, 40.0)).unwrap();
        let v = 0.5 * model.crest_speed_m_per_s();
        group.bench_function(format!("curve point, {n} posts"), |b| {
            b.iter(|| model.at_speed(v).unwrap())
        });
    }
    let scene = common::analytic_row(100, 40.0);
    group.bench_function("50-point curve, 100 posts (normal grid included)", |b| {
        b.iter(|| solve(&CoupledModel::new(&scene).unwrap(), None).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
