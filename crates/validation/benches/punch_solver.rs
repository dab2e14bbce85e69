//! Stages of the punch FEM on the springs-study meshes (quarter model, Tet10, k_sn, clamped
//! far field): numeric assembly, ordering + symbolic Cholesky, numeric Cholesky, solve, and the
//! iterative path (p-multigrid set-up, PCG solve at the default tolerance).
//! Throughput is in unknowns per second (criterion "elements").
//!
//! `cargo bench -p validation --bench punch_solver -- --sample-size 10`
//! Default: levels 0 and 1 of `MeshFamily::tet10()` (≈ 22k and 52k unknowns);
//! `VALIDATION_BENCH_LARGE=1` adds level 2 (≈ 150k). The ≥ 300k point (level 3) is measured once
//! by `cargo run --release -p validation --example punch_scaling -- --level 3` (a criterion run
//! would factor it 10+ times). Cube meshes are benchmarked in elastic-fem (fem_pipeline); these
//! are the graded punch meshes, whose fill differs. Meshes come from the cache (gmsh if missing).

use std::hint::black_box;

use contact_springs::Material;
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use elastic_fem::sparse::{FactorOptions, Ordering, SymbolicCholesky};
use elastic_fem::{
    DofMap, IterativeOptions, IterativeSolver, ReducedSystem, StiffnessPattern,
    assemble_stiffness_into,
};
use validation::{AssembledPunch, MeshCache, MeshFamily, MeshSymmetry, PunchMesh, Spring};

fn levels() -> Vec<usize> {
    if std::env::var_os("VALIDATION_BENCH_LARGE").is_some() {
        vec![0, 1, 2]
    } else {
        vec![0, 1]
    }
}

fn stages(c: &mut Criterion) {
    let material = Material::lithium_niobate();
    for level in levels() {
        let parameters = MeshFamily::tet10().parameters(level, 10e-6, MeshSymmetry::Quarter);
        let path = MeshCache::default()
            .punch_mesh(&parameters)
            .expect("punch mesh (gmsh)");
        let mesh = PunchMesh::read(&path).expect("punch mesh reads");
        let assembled = AssembledPunch::new(&mesh, &material).expect("model");
        let model = assembled.model();
        let pattern = StiffnessPattern::build(model);
        let mut stiffness = assembled.stiffness().clone();
        let constraints =
            assembled.clamped_constraints(Spring::FrictionlessNormal, 1e-3 * mesh.radius_m);
        let reduced = ReducedSystem::new(
            &stiffness,
            DofMap::new(mesh.node_count(), &constraints).unwrap(),
        )
        .unwrap();
        let k_red = reduced.reduce_matrix(&stiffness).unwrap();
        let load = reduced
            .reduce_load(&stiffness, &vec![0.0; 3 * mesh.node_count()])
            .unwrap();
        let symbolic = SymbolicCholesky::analyze(&k_red, Ordering::Metis).unwrap();
        let numeric = symbolic.factor(&k_red).unwrap();
        let unknowns = reduced.dim();
        let id = BenchmarkId::from_parameter(unknowns);
        let throughput = Throughput::Elements(unknowns as u64);
        eprintln!(
            "level {level}: {unknowns} unknowns, factor {} MB ({} nnz)",
            symbolic.factor_nnz() * 8 / 1_000_000,
            symbolic.factor_nnz()
        );

        let mut g = c.benchmark_group("punch_assembly");
        g.throughput(throughput.clone());
        g.bench_function(id.clone(), |b| {
            b.iter(|| assemble_stiffness_into(model, &pattern, black_box(&mut stiffness)).unwrap())
        });
        g.finish();

        let mut g = c.benchmark_group("punch_symbolic");
        g.throughput(throughput.clone());
        g.bench_function(id.clone(), |b| {
            b.iter(|| black_box(SymbolicCholesky::analyze(&k_red, Ordering::Metis).unwrap()))
        });
        g.finish();

        let mut g = c.benchmark_group("punch_numeric");
        g.throughput(throughput.clone());
        g.bench_function(id.clone(), |b| {
            b.iter(|| black_box(symbolic.factor(&k_red).unwrap()))
        });
        g.finish();

        let mut g = c.benchmark_group("punch_solve");
        g.throughput(throughput.clone());
        g.bench_function(id.clone(), |b| {
            b.iter(|| black_box(numeric.solve(&load).unwrap()))
        });
        g.finish();

        let setup = || {
            IterativeSolver::new(
                model,
                reduced.dof_map(),
                &k_red,
                &IterativeOptions::default(),
                FactorOptions::default(),
            )
            .unwrap()
        };
        let mut g = c.benchmark_group("punch_iterative_setup");
        g.throughput(throughput.clone());
        g.bench_function(id.clone(), |b| b.iter(|| black_box(setup())));
        g.finish();

        let solver = setup();
        let mut workspace = solver.workspace();
        let mut g = c.benchmark_group("punch_iterative_solve");
        g.throughput(throughput.clone());
        g.bench_function(id.clone(), |b| {
            b.iter(|| {
                let mut x = load.clone();
                black_box(solver.solve_in_place(&mut x, &mut workspace).unwrap())
            })
        });
        g.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = stages
}
criterion_main!(benches);
