//! The punch stiffness with elastic-fem's iterative path (p-multigrid PCG) equals the direct
//! Cholesky value on the committed quarter Tet10 mesh, for every spring, to the accuracy its
//! stopping rule promises for an energy-type quantity.

use contact_springs::Material;
use elastic_fem::SolverMethod;
use validation::{AssembledPunch, PunchMesh, PunchSolveOptions, Spring};

/// Relative agreement of the stiffness (an energy uᵀ K u / δ², second order in the algebraic
/// energy error ε ≤ 1e-6 of the default stopping rule, so ≈ 1e-12; bound set with margin for
/// the lower-bound nature of the error estimate and round-off).
const STIFFNESS_AGREEMENT: f64 = 1e-9;

#[test]
fn iterative_and_direct_punch_stiffnesses_agree_on_the_committed_quarter_mesh() {
    let mesh = PunchMesh::read(
        &workspace_root()
            .join("meshes")
            .join("punch-quarter_a10um_R100a_tet10_8k.msh"),
    )
    .expect("committed quarter mesh");
    let assembled = AssembledPunch::new(&mesh, &Material::lithium_niobate()).unwrap();
    let with = |method| PunchSolveOptions {
        method,
        ..PunchSolveOptions::default()
    };
    for spring in [
        Spring::FrictionlessNormal,
        Spring::BondedNormal,
        Spring::BondedTangential,
        Spring::FreeNormalTangential,
    ] {
        let direct = assembled
            .solve(spring, &with(SolverMethod::Direct))
            .unwrap();
        let iterative = assembled
            .solve(spring, &with(SolverMethod::Iterative))
            .unwrap();
        assert_eq!(
            iterative.method,
            "iterative",
            "method reported for {}",
            spring.label()
        );
        assert!(
            iterative.iterations.iter().all(|&i| i > 0 && i < 80),
            "PCG iterations of {}: {:?}",
            spring.label(),
            iterative.iterations
        );
        for (what, a, b) in [
            (
                "point-force far field",
                iterative.stiffness_n_per_m,
                direct.stiffness_n_per_m,
            ),
            (
                "clamped far field",
                iterative.clamped_stiffness_n_per_m,
                direct.clamped_stiffness_n_per_m,
            ),
        ] {
            assert!(
                (a / b - 1.0).abs() < STIFFNESS_AGREEMENT,
                "{} stiffness ({what}): iterative {a:e} N/m, direct {b:e} N/m",
                spring.label()
            );
        }
    }
}

/// The checkout (tests read its committed meshes).
fn workspace_root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}
