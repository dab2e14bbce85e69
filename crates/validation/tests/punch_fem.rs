//! Punch FEM on the committed meshes (fast): exactness of the symmetry conditions, the far-field
//! condition, bounds and tolerances against the exact formulas.

use contact_springs::Material;
use validation::{AssembledPunch, MeshSymmetry, MirrorPlane, PunchMesh, PunchSolveOptions, Spring};

fn committed(name: &str) -> PunchMesh {
    PunchMesh::read(&workspace_root().join("meshes").join(name))
        .expect("committed punch mesh reads")
}

fn quarter() -> PunchMesh {
    committed("punch-quarter_a10um_R100a_tet10_8k.msh")
}

/// Relative agreement expected between two discretely identical problems: round-off of a
/// Cholesky solve with ~10⁵ unknowns (condition number ~10⁷ of K_red).
const ROUND_OFF: f64 = 1e-8;

#[test]
fn committed_meshes_have_the_expected_symmetry_radius_and_truncation() {
    let q = quarter();
    assert_eq!(q.symmetry, MeshSymmetry::Quarter, "quarter mesh symmetry");
    assert!(
        (q.radius_m / 10e-6 - 1.0).abs() < 1e-9,
        "punch radius {} m",
        q.radius_m
    );
    assert!(
        (q.truncation_ratio() / 100.0 - 1.0).abs() < 1e-9,
        "R/a = {}",
        q.truncation_ratio()
    );
    let full = committed("punch_a10um_R20a_tet4_5k.msh");
    assert_eq!(full.symmetry, MeshSymmetry::Full, "full Tet4 mesh symmetry");
    assert_eq!(full.order, 1, "element order of the Tet4 mesh");
}

/// The mirrored mesh is the symmetric extension of the quarter mesh, so the discrete solution on
/// it is exactly (anti)symmetric: quarter and half models must give the same stiffness to
/// round-off, for normal (symmetric in x = 0) and tangential (antisymmetric in x = 0) springs.
#[test]
fn symmetry_conditions_are_exact_quarter_model_equals_mirrored_half_model() {
    let q = quarter();
    let half = q.mirrored(MirrorPlane::X0).unwrap();
    assert_eq!(
        half.symmetry,
        MeshSymmetry::Half,
        "mirrored quarter is a half model"
    );
    assert_eq!(
        half.element_count(),
        2 * q.element_count(),
        "mirrored element count"
    );
    let material = Material::lithium_niobate();
    let options = PunchSolveOptions::default();
    let on_quarter = AssembledPunch::new(&q, &material).unwrap();
    let on_half = AssembledPunch::new(&half, &material).unwrap();
    for spring in [Spring::FrictionlessNormal, Spring::BondedTangential] {
        let kq = on_quarter.solve(spring, &options).unwrap();
        let kh = on_half.solve(spring, &options).unwrap();
        for (what, a, b) in [
            (
                "point-force far field",
                kq.stiffness_n_per_m,
                kh.stiffness_n_per_m,
            ),
            (
                "clamped far field",
                kq.clamped_stiffness_n_per_m,
                kh.clamped_stiffness_n_per_m,
            ),
        ] {
            assert!(
                (a / b - 1.0).abs() < ROUND_OFF,
                "{spring} stiffness ({what}): quarter {a:e} vs half {b:e} N/m"
            );
        }
    }
}

/// Clamping the hemisphere adds a constraint (stiffer) and the conforming FEM of a displacement-
/// driven problem is stiffer than its exact solution: the clamped FEM stiffness bounds the exact
/// half-space stiffness from above (k_sn, k_st: formulas exact). The point-force far field
/// removes most of the truncation error: on this mesh (R = 100a) the clamped result is ≈ 1 %
/// higher.
#[test]
fn clamped_stiffness_bounds_the_exact_value_and_the_point_force_far_field_is_closer() {
    let q = quarter();
    let material = Material::lithium_niobate();
    let assembled = AssembledPunch::new(&q, &material).unwrap();
    for spring in [Spring::FrictionlessNormal, Spring::FreeNormalTangential] {
        let r = assembled
            .solve(spring, &PunchSolveOptions::default())
            .unwrap();
        let exact = spring.analytic_n_per_m(&material, q.radius_m).unwrap();
        assert!(
            r.clamped_stiffness_n_per_m > exact,
            "{spring}: clamped FEM {:e} must exceed exact {exact:e} N/m",
            r.clamped_stiffness_n_per_m
        );
        let truncation_shift = r.clamped_stiffness_n_per_m / r.stiffness_n_per_m - 1.0;
        assert!(
            (0.005..0.015).contains(&truncation_shift),
            "{spring}: clamped/point-force stiffness - 1 = {truncation_shift} (expected ~1 a/R = 0.01 at R = 100a)"
        );
    }
}

/// Tolerance of the committed coarse quarter mesh (h_e = 0.05a, g = 0.3): its measured
/// discretisation error is +0.9…+1.1 % for all four springs (see validation/springs/README.md);
/// 1.5 % leaves room for round-off of the mesh file, not for a wrong boundary condition (the
/// partner conditions differ by 2–4 %).
const COARSE_MESH_TOLERANCE: f64 = 0.015;

#[test]
fn committed_quarter_mesh_matches_the_formulas_within_its_discretisation_error() {
    let q = quarter();
    for material in [Material::silicon(), Material::lithium_niobate()] {
        let assembled = AssembledPunch::new(&q, &material).unwrap();
        for spring in Spring::ALL {
            let k = assembled
                .solve(spring, &PunchSolveOptions::default())
                .unwrap()
                .stiffness_n_per_m;
            let ratio = k / spring.analytic_n_per_m(&material, q.radius_m).unwrap();
            assert!(
                ratio > 1.0 && ratio < 1.0 + COARSE_MESH_TOLERANCE,
                "{spring} ({}): FEM/formula = {ratio} outside (1, 1 + {COARSE_MESH_TOLERANCE})",
                material.name
            );
        }
    }
}

/// Stiffness scales exactly with G·a at fixed ν: the same mesh scaled by 2.5 and a material with
/// twice the shear modulus gives 5 × the stiffness, to round-off.
#[test]
fn stiffness_scales_with_shear_modulus_times_radius() {
    let q = quarter();
    let mut scaled = q.clone();
    let factor = 2.5;
    scaled
        .nodes
        .iter_mut()
        .for_each(|x| x.iter_mut().for_each(|v| *v *= factor));
    scaled.radius_m *= factor;
    scaled.truncation_radius_m *= factor;
    let material = Material::silicon();
    let stiffer = Material {
        shear_modulus_pa: 2.0 * material.shear_modulus_pa,
        ..material.clone()
    };
    let k = AssembledPunch::new(&q, &material)
        .unwrap()
        .solve(Spring::BondedNormal, &PunchSolveOptions::default())
        .unwrap();
    let k_scaled = AssembledPunch::new(&scaled, &stiffer)
        .unwrap()
        .solve(Spring::BondedNormal, &PunchSolveOptions::default())
        .unwrap();
    let ratio = k_scaled.stiffness_n_per_m / k.stiffness_n_per_m;
    assert!(
        (ratio / (2.0 * factor) - 1.0).abs() < ROUND_OFF,
        "k_pn scaling with G a: ratio {ratio}, expected {}",
        2.0 * factor
    );
}

#[test]
fn tangential_springs_on_the_committed_half_mesh_are_told_apart() {
    // Bonded vs u_z-free tangential on one mesh: the FEM values differ by ≈ 2 % (formulas: 2.0 %
    // for Si), far above the discretisation error difference between the two conditions.
    let half = committed("punch-half_a10um_R100a_tet10_14k.msh");
    let material = Material::silicon();
    let assembled = AssembledPunch::new(&half, &material).unwrap();
    let bonded = assembled
        .solve(Spring::BondedTangential, &PunchSolveOptions::default())
        .unwrap()
        .stiffness_n_per_m;
    let free = assembled
        .solve(Spring::FreeNormalTangential, &PunchSolveOptions::default())
        .unwrap()
        .stiffness_n_per_m;
    let difference = bonded / free - 1.0;
    assert!(
        (0.012..0.03).contains(&difference),
        "bonded / u_z-free tangential stiffness - 1 = {difference}"
    );
}

/// The checkout (tests read its committed meshes).
fn workspace_root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}
