//! Matrix-free or assembled: one product y = K x and the set-up each needs, one thread, on Tet10
//! cube meshes (straight-sided, isotropic). The numbers and the choice: this crate's README,
//! "Matrix-free or assembled".
//!
//! `cargo bench -p elastic-fem --bench operator -- --sample-size 10`
//! Sizes ≈ 55k and ≈ 350k unknowns. Products:
//! - `csr_f64`: the assembled full-row CSR in f64 (CG's own product);
//! - `csr_f32`: the same with the values rounded to f32 (the smoothers' products);
//! - `matrix_free_gradients` / `matrix_free_jacobians`: elastic-fem's `matrix_free` operator with
//!   the physical gradients stored per point / J⁻¹ per element.
//!
//! Set-up: `assembled` = pattern + assembly + full-row CSR + its f32 copy; `matrix_free_*` = the
//! operator's element data. Bytes held by each are printed once per size (stderr).

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use elastic_fem::matrix_free::{MatrixFreeGeometry, MatrixFreeStiffness};
use elastic_fem::mesh_gen::BoxMesh;
use elastic_fem::sparse::CsrMatrix;
use elastic_fem::{Material, Model, StiffnessPattern, assemble_stiffness};

const GEOMETRIES: [(&str, MatrixFreeGeometry); 2] = [
    ("matrix_free_gradients", MatrixFreeGeometry::Gradients),
    ("matrix_free_jacobians", MatrixFreeGeometry::Jacobians),
];

fn model(target_unknowns: usize) -> Model {
    let n = BoxMesh::tet10_divisions_for_unknowns(target_unknowns);
    let mesh = BoxMesh::tet10([1e-4; 3], [n; 3]);
    let material = Material::isotropic(203e9, 0.25).unwrap();
    Model::new(mesh.nodes, mesh.connectivity, material).unwrap()
}

fn assembled(model: &Model) -> CsrMatrix {
    let k = assemble_stiffness(model, &StiffnessPattern::build(model)).unwrap();
    CsrMatrix::from_symmetric(&k).unwrap()
}

fn operator(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for target in [55_000, 350_000] {
        let model = model(target);
        let csr = pool.install(|| assembled(&model));
        let single = csr.single_precision();
        let operators: Vec<_> = GEOMETRIES
            .iter()
            .map(|&(_, g)| MatrixFreeStiffness::new(&model, g).unwrap())
            .collect();
        let dim = model.dof_count();
        eprintln!(
            "{dim} unknowns, {} elements: CSR {:.1} MB (+ f32 values {:.1} MB), {} entries; \
             matrix-free gradients {:.1} MB, jacobians {:.1} MB",
            model.element_count(),
            csr.memory_bytes() as f64 / 1e6,
            csr.nnz() as f64 * 4.0 / 1e6,
            csr.nnz(),
            operators[0].memory_bytes() as f64 / 1e6,
            operators[1].memory_bytes() as f64 / 1e6,
        );
        let x: Vec<f64> = (0..dim)
            .map(|i| ((i * 7919) % 1000) as f64 * 1e-9)
            .collect();
        let mut y = vec![0.0; dim];

        let mut g = c.benchmark_group("operator_product");
        g.throughput(Throughput::Elements(dim as u64));
        g.bench_function(BenchmarkId::new("csr_f64", dim), |b| {
            b.iter(|| pool.install(|| csr.mul_vec(black_box(&x), &mut y)))
        });
        g.bench_function(BenchmarkId::new("csr_f32", dim), |b| {
            b.iter(|| pool.install(|| csr.mul_vec_single(&single, black_box(&x), &mut y)))
        });
        for ((name, _), op) in GEOMETRIES.iter().zip(&operators) {
            g.bench_function(BenchmarkId::new(*name, dim), |b| {
                b.iter(|| op.mul_vec(black_box(&x), &mut y))
            });
        }
        g.finish();

        let mut g = c.benchmark_group("operator_setup");
        g.throughput(Throughput::Elements(dim as u64));
        g.bench_with_input(BenchmarkId::new("assembled", dim), &model, |b, m| {
            b.iter(|| {
                pool.install(|| {
                    let csr = assembled(m);
                    black_box(csr.single_precision());
                    csr
                })
            })
        });
        for (name, geometry) in GEOMETRIES {
            g.bench_with_input(BenchmarkId::new(name, dim), &model, |b, m| {
                b.iter(|| MatrixFreeStiffness::new(m, geometry).unwrap())
            });
        }
        g.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(Duration::from_secs(5));
    targets = operator
}
criterion_main!(benches);
