//! The default slider (100 × 100 posts, 4 phases, one preload of 40 N, rigid back): operator
//! build, one phase, the whole stage; and one phase against the lattice size (1 000 → 40 000
//! posts at the default pitch and per-post load).
//!
//! Free back (`pressure`, `point` at the centre): operator + plate build, one phase and the
//! 4 phases + η at 40 N.
//!
//! `cargo bench -p slider-contact --bench default_slider [-- free_back]`. CPU time, iteration
//! counts, the cost per extra phase and the growth exponent of every mechanism in one command:
//! `cargo run -p slider-contact --profile test --example speed`.

use criterion::{Criterion, criterion_group, criterion_main};
use slider_contact::{ComplianceOperator, Mechanism, Precision, SliderModel, SliderParams, run};

fn lattice(side_x: usize, side_y: usize) -> SliderParams {
    SliderParams {
        posts_x: side_x,
        posts_y: side_y,
        slider_length_m: side_x as f64 * 40e-6 + 1e-3,
        slider_width_m: side_y as f64 * 40e-6 + 1e-3,
        preload_n: 4e-3 * (side_x * side_y) as f64,
        ..SliderParams::default()
    }
}

fn default_slider(c: &mut Criterion) {
    let params = SliderParams::default();
    let mut group = c.benchmark_group("default_slider");
    group.sample_size(10);
    group.bench_function("operator_build", |b| {
        b.iter(|| SliderModel::build(&params).unwrap())
    });
    let model = SliderModel::build(&params).unwrap();
    group.bench_function("one_phase_40n", |b| {
        b.iter(|| model.solve_phase(40.0, Some(0.0)).unwrap())
    });
    group.bench_function("four_phases_and_eta_40n", |b| {
        b.iter(|| model.analyse(40.0).unwrap())
    });
    group.bench_function("whole_stage_40n", |b| b.iter(|| run(&params).unwrap()));
    group.finish();
}

/// One product C·f of the default slider's lattice operator (10 000 posts, the zero-padded FFT
/// convolution every CG iteration of the static and the coupled solves applies), in double and
/// in single precision (`Precision::Single`: f32 transforms, f64 input and output).
fn operator_product(c: &mut Criterion) {
    let model = SliderModel::build(&SliderParams::default()).unwrap();
    let n = model.operator.len();
    let force: Vec<f64> = (0..n).map(|i| 1.0 + (i % 7) as f64 * 0.1).collect();
    let mut out = vec![0.0; n];
    let mut group = c.benchmark_group("operator_product");
    group.bench_function("apply_10000_posts", |b| {
        b.iter(|| model.operator.apply(&force, &mut out))
    });
    group.bench_function("apply_10000_posts_single", |b| {
        b.iter(|| model.operator.apply_at(&force, &mut out, Precision::Single))
    });
    group.finish();
}

fn growth(c: &mut Criterion) {
    let mut group = c.benchmark_group("one_phase_vs_posts");
    group.sample_size(10);
    for (nx, ny) in [(32, 32), (71, 71), (100, 100), (141, 141), (200, 200)] {
        let params = lattice(nx, ny);
        let model = SliderModel::build(&params).unwrap();
        group.bench_function(format!("{}_posts", nx * ny), |b| {
            b.iter(|| model.solve_phase(params.preload_n, Some(0.0)).unwrap())
        });
    }
    group.finish();
}

fn free_back(c: &mut Criterion) {
    let mut group = c.benchmark_group("free_back");
    group.sample_size(10);
    for (name, mechanism) in [
        (
            "point",
            Mechanism::Point {
                x_m: 2.5e-3,
                y_m: 2.5e-3,
            },
        ),
        ("pressure", Mechanism::Pressure),
    ] {
        let params = SliderParams {
            mechanism,
            ..SliderParams::default()
        };
        group.bench_function(format!("{name}_build"), |b| {
            b.iter(|| SliderModel::build(&params).unwrap())
        });
        let model = SliderModel::build(&params).unwrap();
        group.bench_function(format!("{name}_one_phase_40n"), |b| {
            b.iter(|| model.solve_phase(40.0, Some(0.0)).unwrap())
        });
        group.bench_function(format!("{name}_four_phases_and_eta_40n"), |b| {
            b.iter(|| model.analyse(40.0).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, default_slider, operator_product, growth, free_back);
criterion_main!(benches);
