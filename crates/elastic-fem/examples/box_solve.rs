//! Full static solve of a clamped Tet10 cube under gravity, with a timing breakdown; used to
//! measure peak memory (`/usr/bin/time -v`) and the scaling of the solvers.
//!
//! `cargo run --release -p elastic-fem --example box_solve -- [unknowns=50000] [SOLVER]`
//! with SOLVER one of `metis | amd | natural` (direct Cholesky with that ordering) or
//! `iterative | iterative-direct | iterative-amg` (p-multigrid PCG with the automatic, the
//! factorised or the SA-AMG coarse solve). `--tet4` meshes the cube with Tet4 (iterative: SA-AMG
//! alone).

use std::time::Instant;

use elastic_fem::iterative::{CoarseSolver, IterativeOptions, IterativeSolver};
use elastic_fem::mesh_gen::{BoxFace, BoxMesh};
use elastic_fem::sparse::{FactorOptions, Ordering, SymbolicCholesky};
use elastic_fem::{
    Constraints, Dirichlet, DofMap, FemResult, Material, Model, ReducedSystem, StiffnessPattern,
    assemble_stiffness, loads,
};

fn main() -> FemResult<()> {
    let args: Vec<String> = std::env::args().collect();
    let target: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(50_000);
    let solver = args.get(2).map_or("metis", String::as_str);
    let coarse = match solver {
        "iterative" => Some(CoarseSolver::Auto),
        "iterative-direct" => Some(CoarseSolver::Direct),
        "iterative-amg" => Some(CoarseSolver::Amg),
        _ => None,
    };
    let ordering = match solver {
        "amd" => Ordering::Amd,
        "natural" => Ordering::Natural,
        _ => Ordering::Metis,
    };
    let tet4 = args.iter().any(|a| a == "--tet4");
    let n = BoxMesh::tet10_divisions_for_unknowns(target);
    let t = Instant::now();
    let mesh = if tet4 {
        BoxMesh::tet4([1e-3; 3], [2 * n; 3])
    } else {
        BoxMesh::tet10([1e-3; 3], [n; 3])
    };
    let model = Model::new(
        mesh.nodes.clone(),
        mesh.connectivity.clone(),
        Material::isotropic(160e9, 0.22)?,
    )?;
    let t_mesh = t.elapsed();
    let t = Instant::now();
    let pattern = StiffnessPattern::build(&model);
    let t_pattern = t.elapsed();
    let t = Instant::now();
    let k = assemble_stiffness(&model, &pattern)?;
    let t_assembly = t.elapsed();
    let constraints = Constraints {
        dirichlet: vec![Dirichlet::clamped(mesh.face_nodes(BoxFace::ZMin))],
        ..Default::default()
    };
    let t = Instant::now();
    let reduced = ReducedSystem::new(&k, DofMap::new(model.node_count(), &constraints)?)?;
    let k_red = reduced.reduce_matrix(&k)?;
    let t_reduce = t.elapsed();
    let mut f = vec![0.0; model.dof_count()];
    loads::add_body_force(&model, |_| [0.0, 0.0, -2329.0 * 9.81], &mut f)?;
    let mut q = reduced.reduce_load(&k, &f)?;
    if let Some(coarse_solver) = coarse {
        let options = IterativeOptions {
            coarse_solver,
            ..IterativeOptions::default()
        };
        let t = Instant::now();
        let solver = IterativeSolver::new(
            &model,
            reduced.dof_map(),
            &k_red,
            &options,
            FactorOptions::default(),
        )?;
        let t_setup = t.elapsed();
        let t = Instant::now();
        let pcg = solver.solve_in_place(&mut q, &mut solver.workspace())?;
        let t_solve = t.elapsed();
        let r = solver.report();
        println!(
            "unknowns {} (reduced {}), elements {}, fine nnz {}, coarse {} ({}), AMG levels {} complexity {:.2}, solver MB {:.0}, PCG iterations {}",
            model.dof_count(),
            reduced.dim(),
            model.element_count(),
            r.fine_nnz,
            r.coarse_unknowns,
            r.coarse_solver,
            r.amg_levels,
            r.amg_operator_complexity,
            r.memory_bytes as f64 / 1e6,
            pcg.iterations
        );
        println!(
            "times [s]: mesh+checks {:.3}, pattern {:.3}, assembly {:.3}, reduction {:.3}, set-up {:.3}, PCG {:.3}, assembly+set-up+PCG {:.3}",
            t_mesh.as_secs_f64(),
            t_pattern.as_secs_f64(),
            t_assembly.as_secs_f64(),
            t_reduce.as_secs_f64(),
            t_setup.as_secs_f64(),
            t_solve.as_secs_f64(),
            (t_assembly + t_setup + t_solve).as_secs_f64()
        );
        let u = reduced.expand(&q)?;
        let max_uz = u
            .iter()
            .skip(2)
            .step_by(3)
            .fold(0.0f64, |m, v| m.max(v.abs()));
        println!("max |u_z| = {max_uz:e} m");
        return Ok(());
    }
    let t = Instant::now();
    let symbolic = SymbolicCholesky::analyze(&k_red, ordering)?;
    let t_symbolic = t.elapsed();
    let t = Instant::now();
    let numeric = symbolic.factor(&k_red)?;
    let t_numeric = t.elapsed();
    let t = Instant::now();
    numeric.solve_in_place(&mut q)?;
    let t_solve = t.elapsed();
    let u = reduced.expand(&q)?;
    let max_uz = u
        .iter()
        .skip(2)
        .step_by(3)
        .fold(0.0f64, |m, v| m.max(v.abs()));
    println!(
        "unknowns {} (reduced {}), elements {}, K nnz(upper) {}, L nnz {}, ordering {:?}, supernodal {}",
        model.dof_count(),
        reduced.dim(),
        model.element_count(),
        k.nnz_upper(),
        symbolic.factor_nnz(),
        symbolic.ordering_used(),
        symbolic.is_supernodal()
    );
    println!(
        "times [s]: mesh+checks {:.3}, pattern {:.3}, assembly {:.3}, reduction {:.3}, symbolic {:.3}, numeric {:.3}, solve {:.3}",
        t_mesh.as_secs_f64(),
        t_pattern.as_secs_f64(),
        t_assembly.as_secs_f64(),
        t_reduce.as_secs_f64(),
        t_symbolic.as_secs_f64(),
        t_numeric.as_secs_f64(),
        t_solve.as_secs_f64()
    );
    println!(
        "assembly / numeric factorisation = {:.3}; max |u_z| = {max_uz:e} m",
        t_assembly.as_secs_f64() / t_numeric.as_secs_f64()
    );
    Ok(())
}
