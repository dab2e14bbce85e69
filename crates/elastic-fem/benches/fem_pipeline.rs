//! Assembly, symbolic and numeric Cholesky, and solve on Tet10 cube meshes of increasing size,
//! clamped at z = 0; throughput is reported in unknowns per second (criterion "elements").
//!
//! `cargo bench -p elastic-fem --bench fem_pipeline -- --sample-size 10`
//! Sizes: ≈10k, 50k, 150k unknowns; set `ELASTIC_FEM_BENCH_LARGE=1` to add ≈300k.
//! The METIS vs AMD comparison (numeric factorisation) runs at ≈10k and ≈50k (AMD at ≈150k
//! would take minutes per sample).

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use elastic_fem::mesh_gen::{BoxFace, BoxMesh};
use elastic_fem::sparse::{Ordering, SymbolicCholesky, SymmetricMatrix};
use elastic_fem::{
    Constraints, Dirichlet, DofMap, Material, Model, ReducedSystem, StiffnessPattern,
    assemble_stiffness,
};

struct Case {
    unknowns: usize,
    model: Model,
    pattern: StiffnessPattern,
    stiffness: SymmetricMatrix,
    reduced_matrix: SymmetricMatrix,
}

fn case(target_unknowns: usize) -> Case {
    let n = BoxMesh::tet10_divisions_for_unknowns(target_unknowns);
    let mesh = BoxMesh::tet10([1.0; 3], [n; 3]);
    let model = Model::new(
        mesh.nodes.clone(),
        mesh.connectivity.clone(),
        Material::isotropic(160e9, 0.22).unwrap(),
    )
    .unwrap();
    let pattern = StiffnessPattern::build(&model);
    let stiffness = assemble_stiffness(&model, &pattern).unwrap();
    let constraints = Constraints {
        dirichlet: vec![Dirichlet::clamped(mesh.face_nodes(BoxFace::ZMin))],
        ..Default::default()
    };
    let reduced = ReducedSystem::new(
        &stiffness,
        DofMap::new(model.node_count(), &constraints).unwrap(),
    )
    .unwrap();
    let reduced_matrix = reduced.reduce_matrix(&stiffness).unwrap();
    Case {
        unknowns: model.dof_count(),
        model,
        pattern,
        stiffness,
        reduced_matrix,
    }
}

fn sizes() -> Vec<usize> {
    let mut s = vec![10_000, 50_000, 150_000];
    if std::env::var_os("ELASTIC_FEM_BENCH_LARGE").is_some() {
        s.push(300_000);
    }
    s
}

fn pipeline(c: &mut Criterion) {
    for target in sizes() {
        let mut case = case(target);
        let id = BenchmarkId::from_parameter(case.unknowns);
        let throughput = Throughput::Elements(case.unknowns as u64);

        let mut g = c.benchmark_group("pattern_build");
        g.throughput(throughput.clone());
        g.bench_with_input(id.clone(), &case, |b, case| {
            b.iter(|| black_box(StiffnessPattern::build(&case.model)))
        });
        g.finish();

        let mut g = c.benchmark_group("assembly");
        g.throughput(throughput.clone());
        g.bench_function(id.clone(), |b| {
            b.iter(|| {
                elastic_fem::assemble_stiffness_into(
                    &case.model,
                    &case.pattern,
                    &mut case.stiffness,
                )
                .unwrap()
            })
        });
        g.finish();

        let mut g = c.benchmark_group("symbolic_cholesky_metis");
        g.throughput(throughput.clone());
        g.bench_with_input(id.clone(), &case, |b, case| {
            b.iter(|| {
                black_box(SymbolicCholesky::analyze(&case.reduced_matrix, Ordering::Metis).unwrap())
            })
        });
        g.finish();

        let symbolic = SymbolicCholesky::analyze(&case.reduced_matrix, Ordering::Metis).unwrap();
        let mut numeric = symbolic.factor(&case.reduced_matrix).unwrap();
        eprintln!(
            "size {}: reduced {} unknowns, K_red nnz(upper) {}, L nnz {} ({:.0} MB), supernodal {}, colours {}",
            case.unknowns,
            case.reduced_matrix.dim(),
            case.reduced_matrix.nnz_upper(),
            symbolic.factor_nnz(),
            numeric.memory_bytes() as f64 / 1e6,
            symbolic.is_supernodal(),
            case.pattern.color_count()
        );
        let mut g = c.benchmark_group("numeric_cholesky_metis");
        g.throughput(throughput.clone());
        g.bench_function(id.clone(), |b| {
            b.iter(|| numeric.refactor(&case.reduced_matrix).unwrap())
        });
        g.finish();

        let rhs: Vec<f64> = (0..case.reduced_matrix.dim())
            .map(|i| ((i % 17) as f64 - 8.0) * 1e3)
            .collect();
        let mut g = c.benchmark_group("solve_metis");
        g.throughput(throughput.clone());
        g.bench_function(id.clone(), |b| {
            b.iter(|| {
                let mut x = rhs.clone();
                numeric.solve_in_place(&mut x).unwrap();
                black_box(x)
            })
        });
        g.finish();
        drop(numeric);

        if target <= 50_000 {
            let amd = SymbolicCholesky::analyze(&case.reduced_matrix, Ordering::Amd).unwrap();
            eprintln!(
                "size {}: AMD L nnz {} vs METIS {}",
                case.unknowns,
                amd.factor_nnz(),
                symbolic.factor_nnz()
            );
            let mut numeric = amd.factor(&case.reduced_matrix).unwrap();
            let mut g = c.benchmark_group("numeric_cholesky_amd");
            g.throughput(throughput.clone());
            g.bench_function(id.clone(), |b| {
                b.iter(|| numeric.refactor(&case.reduced_matrix).unwrap())
            });
            g.finish();
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(5));
    targets = pipeline
}
criterion_main!(benches);
