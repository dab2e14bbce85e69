//! Where the static stage's time goes, for the default scene or a given strip mesh: prints η at
//! the main preload (17 digits, for mesh-to-mesh comparisons) and the stage breakdown (mesh
//! choice and reading, assembly, METIS ordering + symbolic analysis, numeric factorisation,
//! condensation onto the posts, contact solves + η fits) as one JSON line.
//!
//! ```sh
//! cargo run --release -p static-contact --example static_breakdown            # default scene
//! cargo run --release -p static-contact --example static_breakdown -- MESH.msh # that mesh
//! ```
//! Used by `scripts/perf-default.sh`; numbers in the crate README (Speed).

use static_contact::{MeshChoice, RunControl, StaticParams, prepare_strip};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut params = StaticParams::default();
    if let Some(path) = std::env::args_os().nth(1) {
        params.mesh = MeshChoice::File(path.into());
    }
    let strip = prepare_strip(&params)?;
    let r = &strip.analyse(&params, &params.post_springs()?, &RunControl::none())?;
    let f = &r.fem.slider;
    let line = serde_json::json!({
        "mesh_file": r.mesh_file,
        "effective_contact_ratio": r.effective_contact_ratio,
        "nodes": f.nodes,
        "reduced_unknowns": f.reduced_unknowns,
        "factor_nnz": f.factor_nnz,
        "factor_multiply_adds": f.factor_flops,
        "mesh_s": r.timings.mesh_s,
        "assembly_s": f.assembly_s,
        "ordering_symbolic_s": f.analysis_s,
        "numeric_factor_s": f.factor_s - f.analysis_s,
        "condensation_s": f.solve_s,
        "contact_and_fit_s": r.timings.contact_s,
        "static_total_s": r.timings.wall_time_s,
    });
    println!("{line}");
    Ok(())
}
