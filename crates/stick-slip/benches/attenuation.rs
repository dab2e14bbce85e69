//! Cost of the energy-conserving wave: the attenuated speed–thrust curve (period average, every
//! column its own bin, and 20 bins) against the constant-amplitude curve of the default motor
//! (`Motor::paper()` springs, 50 points) at 40 and 100 N, in one run.
//!
//! `cargo bench -p stick-slip --bench attenuation -- --quick`

#[path = "../tests/support/johnson.rs"]
mod johnson;

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use stick_slip::{AttenuatedPeriodicModel, AttenuationOptions, DynamicScene, PeriodicAverageModel};

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
                        .solve()
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

criterion_group!(benches, curves);
criterion_main!(benches);
