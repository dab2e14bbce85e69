//! `static.fem_solver` in the strip: the iterative (PCG) condensation gives the direct one's
//! compliances within the stated bound, reports that it ran, and η does not move.

mod common;

use nalgebra::DMatrix;
use static_contact::analysis::prepare_strip;
use static_contact::{FemSolver, StaticParams};

fn strip(fem_solver: FemSolver) -> static_contact::analysis::PreparedStrip {
    prepare_strip(&StaticParams {
        fem_solver,
        ..common::ten_post_tet4()
    })
    .expect("strip model")
}

/// max |A − B|_ij / √(B_ii B_jj): the entry error relative to the bound's scale.
fn scaled_difference(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    let mut worst: f64 = 0.0;
    for i in 0..b.nrows() {
        for j in 0..b.ncols() {
            let scale = (b[(i, i)] * b[(j, j)]).sqrt();
            worst = worst.max((a[(i, j)] - b[(i, j)]).abs() / scale);
        }
    }
    worst
}

#[test]
fn iterative_strip_compliance_equals_the_direct_one_within_the_pcg_tolerance() {
    let direct = strip(FemSolver::Direct);
    let iterative = strip(FemSolver::Iterative);
    let (d, i) = (&direct.model.slider, &iterative.model.slider);
    assert_eq!(d.stats.solver, FemSolver::Direct, "reported solver");
    assert_eq!(i.stats.solver, FemSolver::Iterative, "reported solver");
    assert!(i.stats.pcg_iterations > 0, "PCG iterations are reported");
    assert_eq!(i.solver_reason, "requested", "reason of a requested solver");
    // ε = 1e-6 (elastic-fem condense.rs); PCG's estimate is tight within ≈ 1.5.
    let normal = scaled_difference(&i.compliance_m_per_n, &d.compliance_m_per_n);
    assert!(
        normal <= 2e-6,
        "normal tip compliance differs by {normal:e} of √(C_ii C_jj)"
    );
    let (dt, it) = (
        d.tangential_compliance().expect("direct tangential"),
        i.tangential_compliance().expect("iterative tangential"),
    );
    let tangential = scaled_difference(&it.tangential_m_per_n, &dt.tangential_m_per_n);
    assert!(
        tangential <= 2e-6,
        "tangential tip compliance differs by {tangential:e} of √(C_ii C_jj)"
    );
    assert_eq!(
        iterative.model.slider.solver_reason, "requested",
        "the reason of the solver is reported"
    );
}

#[test]
fn auto_picks_direct_for_the_small_strip_and_reports_why() {
    let auto = strip(FemSolver::Auto);
    assert_eq!(auto.model.slider.stats.solver, FemSolver::Direct);
    let reason = &auto.model.slider.solver_reason;
    assert!(
        reason.starts_with("auto: ") && reason.contains("unknowns"),
        "the reason of auto's choice gives the size: {reason}"
    );
}

/// The default strip (Tet10 half strip, 100 posts, ≈ 186k unknowns) both ways: times, PCG
/// iterations and agreement, printed. Heavy (minutes for the 100 PCG columns):
/// `cargo test -p static-contact --test iterative_body -- --ignored --nocapture`
/// (`SAWDRIVE_MESH_CACHE` may point at an existing mesh cache).
#[test]
#[ignore]
fn default_strip_direct_against_iterative() {
    let run = |fem_solver| {
        prepare_strip(&StaticParams {
            fem_solver,
            ..StaticParams::default()
        })
        .expect("default strip")
    };
    let direct = run(FemSolver::Direct);
    let iterative = run(FemSolver::Iterative);
    let (d, i) = (&direct.model.slider, &iterative.model.slider);
    let normal = scaled_difference(&i.compliance_m_per_n, &d.compliance_m_per_n);
    println!(
        "direct: {} unknowns, analysis {:.2} s, factor {:.2} s, condensation {:.4} s",
        d.stats.reduced_unknowns, d.stats.analysis_s, d.stats.factor_s, d.stats.solve_s
    );
    println!(
        "iterative: set-up {:.2} s, {} columns {:.2} s, {} PCG iterations",
        i.stats.factor_s,
        i.compliance_m_per_n.ncols(),
        i.stats.solve_s,
        i.stats.pcg_iterations
    );
    println!("normal compliance: max |ΔC_ij| / √(C_ii C_jj) = {normal:e}");
    let auto = &direct.notes;
    println!("notes: {auto:?}");
    assert!(normal <= 2e-6, "normal compliance differs by {normal:e}");
}
