//! Cost of the coupled model (target: the default slider's row, 100 posts, 50-point
//! curve ≤ 10 s). The compliance is the row's analytic part — Johnson post springs on the
//! diagonal plus the half-space normal and tangential terms of all 100 rows — so the bench
//! needs no meshing; the FEM strip gives the same matrix sizes and solver work (see the
//! `default_row` ignored test for the FEM compliance: 4.1 s per curve in the test profile).
//!
//! `cargo bench -p coupled-dynamics --bench curve`

use contact_springs::{Material, post_springs};
use coupled_dynamics::{CoupledModel, CoupledScene, PreloadBalance, solve};
use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::DMatrix;
use static_contact::halfspace::{
    RowLayout, StripPost, strip_compliance, strip_tangential_compliance,
};
use stick_slip::Wave;

const PITCH_M: f64 = 40e-6;
const RADIUS_M: f64 = 10e-6;
const ROWS: usize = 100;

fn row_scene(n: usize) -> CoupledScene {
    let si = Material::silicon();
    let ln = Material::lithium_niobate();
    let springs = post_springs(&si, &ln, RADIUS_M).unwrap();
    let posts: Vec<StripPost> = (0..n)
        .map(|i| StripPost {
            x_m: (i as f64 - 0.5 * (n - 1) as f64) * PITCH_M,
            row: 0,
        })
        .collect();
    let layout = RowLayout {
        pitch_m: PITCH_M,
        strip_rows: 1,
        slider_rows: ROWS,
    };
    let g = ln.shear_modulus_pa;
    let nu = ln.poisson_ratio;
    let cn = strip_compliance(g, nu, RADIUS_M, &posts, &layout)
        + DMatrix::identity(n, n) / springs.k_pn_n_per_m;
    let ct = strip_tangential_compliance(g, nu, RADIUS_M, &posts, &layout)
        + DMatrix::identity(n, n) / springs.k_pt_n_per_m;
    let x = posts.iter().map(|p| p.x_m).collect();
    let mut scene =
        CoupledScene::independent_posts(Wave::paper_default(), x, 1.0, 1.0, 0.3, 0.3, 40.0);
    scene.normal_compliance_m_per_n = cn;
    scene.tangential_compliance_m_per_n = ct;
    scene.strip_share = n as f64 / (ROWS * 100) as f64;
    scene.preload_balance = PreloadBalance::Instant;
    scene.steps_per_period = 128;
    scene
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("coupled");
    group.sample_size(10);
    for n in [25, 50, 100] {
        let model = CoupledModel::new(&row_scene(n)).unwrap();
        let v = 0.5 * model.crest_speed_m_per_s();
        group.bench_function(format!("curve point, {n} posts"), |b| {
            b.iter(|| model.at_speed(v).unwrap())
        });
    }
    let scene = row_scene(100);
    group.bench_function("50-point curve, 100 posts (normal grid included)", |b| {
        b.iter(|| solve(&CoupledModel::new(&scene).unwrap(), None).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
