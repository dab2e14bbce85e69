//! The `springs` case: the springs study ([`crate::study::validate_springs`]) at a level, and
//! its checks.
//!
//! - `full`: [`SpringsOptions::default`] (Si and LiNbO3, a = 10 and 25 µm, three Tet10 levels
//!   at R = 100a, truncation study, work-precision, stability): every FEM value within
//!   [`FULL_AGREEMENT`] of its formula and converged to [`crate::study::ERROR_TOLERANCE`].
//! - `quick`: the same sections (convergence, truncation, work-precision Tet4 vs Tet10,
//!   locking, floating punch on every solver path, distorted meshes) on the smoke family
//!   (h_e = 0.2a, g = 0.6, R = 20a, a = 10 µm) and a coarse Tet4 family.
//! - `smoke`: [`SpringsOptions::smoke`] (convergence and truncation only).
//!
//! At every level one case is also solved by both solver paths (direct Cholesky and PCG with
//! the p-multigrid), which must agree to [`SOLVER_AGREEMENT`]: `auto` picks either, by size.

use std::path::Path;

use contact_springs::Material;

use super::{Check, Level};
use crate::error::ValidationError;
use crate::family::MeshFamily;
use crate::punch::{AssembledPunch, PunchSolveOptions};
use crate::punch_mesh::{MeshSymmetry, PunchMesh};
use crate::spring::Spring;
use crate::study::{
    AGREEMENT_TOLERANCE, ERROR_TOLERANCE, SpringsOptions, SpringsValidation, StabilityOptions,
    WorkPrecisionOptions, validate_springs,
};

const CASE: &str = "springs";

/// Largest |FEM / formula − 1| of the full study (the measured agreement is ≤ 0.008 %).
/// Dimensionless; 1e-4.
pub const FULL_AGREEMENT: f64 = 1e-4;

/// Largest |FEM / formula − 1| of the coarse smoke and quick meshes (h_e = 0.2a, R = 20a:
/// extrapolated values within ≈ 0.5 %). Dimensionless; 0.01.
pub const COARSE_AGREEMENT: f64 = 0.01;

/// Largest relative difference of a stiffness between the direct and the iterative path: the
/// iterative energy-error tolerance 1e-6 changes an energy quantity by ≈ 1e-12. Dimensionless;
/// 1e-8.
pub const SOLVER_AGREEMENT: f64 = 1e-8;

/// Largest change of the Tet10 k_sn between ν = 0.25 and ν = 0.499 (no volumetric locking) on
/// the full study's mesh (23k unknowns: +2.0 %). Dimensionless; 0.03.
pub const TET10_LOCKING_LIMIT: f64 = 0.03;

/// [`TET10_LOCKING_LIMIT`] on the quick level's coarse mesh (3k unknowns: +5.3 %, against
/// +226 % for Tet4). Dimensionless; 0.08.
pub const TET10_LOCKING_LIMIT_COARSE: f64 = 0.08;

/// Smallest Tet4 stiffening between ν = 0.25 and ν = 0.499 that shows its locking. 1.5.
pub const TET4_LOCKING_SHOWN: f64 = 1.5;

/// Coarse Tet4 family of the quick work-precision and locking study: h_e = 0.1a, g = 0.6,
/// R = 20a.
pub fn coarse_tet4_family() -> MeshFamily {
    MeshFamily {
        order: 1,
        h_edge_over_a: 0.1,
        growth: 0.6,
        refinement_ratio: 2.0,
        truncation_ratio: 20.0,
        h_max_over_a: 0.0,
    }
}

/// The study's options at `level`.
pub fn options(level: Level) -> SpringsOptions {
    match level {
        Level::Full => SpringsOptions::default(),
        Level::Smoke => SpringsOptions::smoke(),
        Level::Quick => SpringsOptions {
            work_precision: Some(WorkPrecisionOptions {
                spring: Spring::FrictionlessNormal,
                material: "linbo3".into(),
                radius_m: 10e-6,
                tet10_levels: 3,
                tet4_family: coarse_tet4_family(),
                tet4_levels: 3,
            }),
            stability: Some(StabilityOptions {
                poisson_ratios: vec![0.25, 0.4, 0.49, 0.499],
                tet4_level: 0,
                tet10_level: 0,
                distortion_amplitudes: vec![0.1, 0.2, 0.45],
            }),
            ..SpringsOptions::smoke()
        },
    }
}

/// Runs the study at `level`, writes its charts into `out/figures` and `results.json` and
/// `cases.json` into `out/results`, returns it and its checks.
pub fn run(
    level: Level,
    out: &Path,
    progress: bool,
) -> Result<(SpringsValidation, Vec<Check>), ValidationError> {
    let mut options = options(level);
    options.progress = progress;
    let study = validate_springs(&options)?;
    crate::report::write_charts(&study, &out.join("figures"))?;
    crate::report::write_json(&study, &out.join("results"))?;
    let mut checks = checks(&study, level);
    checks.push(solver_paths(&options)?);
    Ok((study, checks))
}

/// The checks of a finished study.
pub fn checks(study: &SpringsValidation, level: Level) -> Vec<Check> {
    let agreement = if level == Level::Full {
        FULL_AGREEMENT
    } else {
        COARSE_AGREEMENT.max(AGREEMENT_TOLERANCE)
    };
    let mut checks = Vec::new();
    for c in &study.cases {
        let name = format!("{} ({}, a = {} um)", c.spring, c.material, c.radius_m * 1e6);
        checks.push(Check::relative(
            CASE,
            format!("{name}: extrapolated FEM stiffness (N/m)"),
            c.fem_n_per_m,
            c.analytic_n_per_m,
            agreement,
            "contact-springs formula (docs/physics.md §3)",
        ));
        if level == Level::Full {
            checks.push(Check::at_most(
                CASE,
                format!("{name}: estimated FEM error (discretisation + truncation)"),
                c.fem_error_estimate,
                ERROR_TOLERANCE,
                "acceptance of the springs study (validation/springs/README.md)",
            ));
        }
    }
    if let (Some(t10), Some(t4)) = (
        study
            .work_precision
            .iter()
            .filter(|p| p.order == 2)
            .max_by_key(|p| p.level),
        study
            .work_precision
            .iter()
            .filter(|p| p.order == 1)
            .max_by_key(|p| p.level),
    ) {
        checks.push(Check::at_most(
            CASE,
            format!(
                "work-precision: Tet10 error on {} unknowns, at most the Tet4 error on {}",
                t10.unknowns, t4.unknowns
            ),
            t10.relative_error,
            t4.relative_error,
            "Tet10 converges as h², Tet4 as h (validation/springs/README.md)",
        ));
    }
    if let Some(st) = &study.stability {
        if let (Some(first), Some(last)) = (st.locking.first(), st.locking.last()) {
            checks.push(Check::relative(
                CASE,
                format!(
                    "locking: Tet10 k_sn at nu = {} over nu = {}",
                    last.poisson_ratio, first.poisson_ratio
                ),
                last.tet10_over_analytic / first.tet10_over_analytic,
                1.0,
                if level == Level::Full {
                    TET10_LOCKING_LIMIT
                } else {
                    TET10_LOCKING_LIMIT_COARSE
                },
                "Tet10 does not lock (validation/springs/README.md, stability)",
            ));
            checks.push(Check::at_least(
                CASE,
                format!(
                    "locking: Tet4 k_sn at nu = {} over nu = {}",
                    last.poisson_ratio, first.poisson_ratio
                ),
                last.tet4_over_analytic / first.tet4_over_analytic,
                TET4_LOCKING_SHOWN,
                "Tet4 locks as nu -> 1/2 (the failure mode the study shows)",
            ));
        }
        let s = &st.singular_system;
        let refused = [
            &s.with_rigid_mode_check,
            &s.without_rigid_mode_check,
            &s.direct_without_check,
            &s.iterative_without_check,
        ]
        .iter()
        .filter(|m| !m.is_empty())
        .count();
        checks.push(Check::at_least(
            CASE,
            "floating punch: solver paths that refuse it (rigid-mode check, auto, direct, iterative)",
            refused as f64,
            4.0,
            "a singular system is refused by every path (elastic-fem iterative module docs)",
        ));
        if let Some(first) = st.distortion.iter().find(|p| p.refusal.is_empty()) {
            for p in st
                .distortion
                .iter()
                .filter(|p| p.refusal.is_empty() && p.amplitude > first.amplitude)
            {
                checks.push(Check::relative(
                    CASE,
                    format!(
                        "distorted mesh: k_sn at amplitude {} over amplitude {}",
                        p.amplitude, first.amplitude
                    ),
                    p.stiffness_over_analytic / first.stiffness_over_analytic,
                    1.0,
                    0.005,
                    "valid distorted Tet10 elements keep the stiffness (springs README, stability)",
                ));
            }
        }
    }
    checks
}

/// k_sn of LiNbO3 on level 0 of the study's family (quarter model) by the direct and by the
/// iterative path: the two paths `auto` picks between agree.
fn solver_paths(options: &SpringsOptions) -> Result<Check, ValidationError> {
    let material = Material::lithium_niobate();
    let radius_m = options.radii_m[0];
    let parameters = options.family.with_truncation(
        0,
        radius_m,
        MeshSymmetry::Quarter,
        options.family.truncation_ratio,
    );
    let mesh = PunchMesh::read(&options.cache.punch_mesh(&parameters)?)?;
    let assembled = AssembledPunch::new(&mesh, &material)?;
    let solve = |method| {
        assembled.solve(
            Spring::FrictionlessNormal,
            &PunchSolveOptions {
                method,
                ..options.solve
            },
        )
    };
    let direct = solve(elastic_fem::SolverMethod::Direct)?;
    let iterative = solve(elastic_fem::SolverMethod::Iterative)?;
    Ok(Check::relative(
        CASE,
        format!(
            "k_sn (linbo3, {} unknowns): iterative path over direct path",
            direct.unknowns
        ),
        iterative.stiffness_n_per_m,
        direct.stiffness_n_per_m,
        SOLVER_AGREEMENT,
        "iterative stopping rule: energy error 1e-6 (elastic-fem iterative module docs)",
    ))
}
