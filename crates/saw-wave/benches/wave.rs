//! Time to solve one cut's Rayleigh wave (free and metallized surface, modes and power flux).
//! The target is ≤ 10 ms per cut in a release build.

use criterion::{Criterion, criterion_group, criterion_main};
use saw_wave::Cut;
use std::hint::black_box;

fn solve_named_cuts(c: &mut Criterion) {
    for name in Cut::KNOWN_NAMES {
        let cut = Cut::from_name(name).expect("named cut");
        c.bench_function(&format!("solve {name}"), |b| {
            b.iter(|| black_box(&cut).solve().expect("surface wave"))
        });
    }
}

criterion_group!(benches, solve_named_cuts);
criterion_main!(benches);
