//! One-shot stage timings of the punch FEM (k_sn, LiNbO3, quarter or any punch mesh): unknowns,
//! assembly, symbolic and numeric factorisation, solve, time per unknown, factor memory and peak
//! resident memory. One JSON object per mesh on stdout.
//!
//! ```sh
//! cargo run --release -p validation --example punch_scaling -- MESH.msh [MESH.msh ...]
//! cargo run --release -p validation --example punch_scaling -- --level 3   # family level (gmsh)
//! cargo run --release -p validation --example punch_scaling -- --method iterative MESH.msh
//! ```
//! `--method auto|direct|iterative` picks the linear solver (default auto, elastic-fem's cost
//! model; the JSON carries the method, its reason and the PCG iterations);
//! `--mesh-only` prints the mesh paths (after generating them) and stops;
//! `--clamped-only` solves problem A only (the clamped far field, one right-hand side), the
//! problem the peers of scripts/compare-peers.sh solve; `k_sn_n_per_m` is then null;
//! `--discretisation-error E` sets the iterative stopping rule (CG tolerance 0.01 E).
//! `--level L` takes the quarter Tet10 mesh of level L of the springs study family (generated
//! into the mesh cache if missing); a fraction lies between two levels (4.2: h_e = h_e(4) / 2^0.2,
//! ≈ 1.1M unknowns). Used by scripts/compare-peers.sh and
//! scripts/fem-scaling.sh.

use contact_springs::Material;
use elastic_fem::{IterativeOptions, SolverMethod};
use validation::{AssembledPunch, PunchMesh, PunchSolveOptions, Spring, benchmark_punch_mesh};

/// Peak resident set size of this process (MB), from /proc/self/status (Linux), or NaN.
fn peak_rss_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut paths = Vec::new();
    let mut options = PunchSolveOptions::default();
    let mut mesh_only = false;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--mesh-only" {
            mesh_only = true;
        } else if arg == "--method" {
            let text = args
                .next()
                .ok_or("--method needs auto, direct or iterative")?;
            options.method = SolverMethod::parse(&text)
                .ok_or_else(|| format!("--method: `{text}` is not auto, direct or iterative"))?;
        } else if arg == "--clamped-only" {
            options.clamped_only = true;
        } else if arg == "--discretisation-error" {
            let e: f64 = args
                .next()
                .ok_or("--discretisation-error needs a number")?
                .parse()?;
            options.iterative = IterativeOptions::for_discretisation_error(e);
            options.iterative.validate()?;
        } else if arg == "--level" {
            let level = args.next().ok_or("--level needs a number")?;
            paths.push(benchmark_punch_mesh(&level)?);
        } else {
            paths.push(arg.into());
        }
    }
    if mesh_only {
        paths.iter().for_each(|p| println!("{}", p.display()));
        return Ok(());
    }
    let material = Material::lithium_niobate();
    for path in paths {
        let t = std::time::Instant::now();
        let mesh = PunchMesh::read(&path)?;
        let read_s = t.elapsed().as_secs_f64();
        let assembled = AssembledPunch::new(&mesh, &material)?;
        let r = assembled.solve(Spring::FrictionlessNormal, &options)?;
        let analytic = Spring::FrictionlessNormal.analytic_n_per_m(&material, mesh.radius_m)?;
        let t = r.timings;
        let json = serde_json::json!({
            "mesh": path.display().to_string(),
            "order": mesh.order,
            "nodes": mesh.node_count(),
            "elements": mesh.element_count(),
            "unknowns": r.unknowns,
            "k_sn_n_per_m": r.stiffness_n_per_m,
            "k_sn_clamped_n_per_m": r.clamped_stiffness_n_per_m,
            "k_sn_over_analytic": r.stiffness_n_per_m / analytic,
            "k_sn_clamped_over_analytic": r.clamped_stiffness_n_per_m / analytic,
            "read_s": read_s,
            "pattern_s": t.pattern_s,
            "assembly_s": t.assembly_s,
            "reduction_s": t.reduction_s,
            "symbolic_s": t.symbolic_s,
            "numeric_s": t.numeric_s,
            "solve_s": t.solve_s,
            "multigrid_setup_s": {
                "fine_csr": t.multigrid_fine_csr_s,
                "transfer": t.multigrid_transfer_s,
                "coarse_operator": t.multigrid_coarse_operator_s,
                "coarse_solver": t.multigrid_coarse_solver_s,
                "smoother": t.multigrid_smoother_s,
            },
            "total_s": t.total_s(),
            "assembly_over_numeric": (t.pattern_s + t.assembly_s) / t.numeric_s,
            "total_us_per_unknown": 1e6 * t.total_s() / r.unknowns as f64,
            "method": r.method,
            "method_reason": r.method_reason,
            "iterations": r.iterations,
            "threads": std::env::var("RAYON_NUM_THREADS").unwrap_or_default(),
            "factor_nnz": r.factor_nnz,
            "factor_mb": r.factor_nnz as f64 * 8.0 / 1e6,
            "peak_rss_mb": peak_rss_mb(),
        });
        println!("{json}");
    }
    Ok(())
}
