//! Where the method fails, shown on the punch: near-incompressible material (Tet4 volumetric
//! locking vs Tet10), a singular system (a floating body), and badly shaped elements.

use contact_springs::Material as SpringMaterial;
use elastic_fem::{
    Constraints, Dirichlet, Model, SolverMethod, SolverOptions, StaticProblem, solve_static,
};
use serde::{Deserialize, Serialize};

use crate::error::ValidationError;
use crate::punch::{AssembledPunch, PunchSolveOptions, fem_material};
use crate::punch_mesh::PunchMesh;
use crate::spring::Spring;

/// One row of the locking study: k_sn on a Tet4 and a Tet10 mesh of similar size at ν.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LockingPoint {
    /// Poisson ratio.
    pub poisson_ratio: f64,
    /// Tet4 stiffness / analytic k_sn = 4Ga/(1 − ν).
    #[serde(deserialize_with = "crate::serde_nan::f64_or_nan")]
    pub tet4_over_analytic: f64,
    /// Tet10 stiffness / analytic k_sn.
    #[serde(deserialize_with = "crate::serde_nan::f64_or_nan")]
    pub tet10_over_analytic: f64,
}

/// Locking study of k_sn for each ν on the given Tet4 and Tet10 meshes (shear modulus of
/// `material`, its ν replaced).
pub fn locking_study(
    tet4: &PunchMesh,
    tet10: &PunchMesh,
    material: &SpringMaterial,
    poisson_ratios: &[f64],
    options: &PunchSolveOptions,
) -> Result<Vec<LockingPoint>, ValidationError> {
    let mut points = Vec::with_capacity(poisson_ratios.len());
    for &nu in poisson_ratios {
        let m = SpringMaterial {
            name: format!("{} with nu = {nu}", material.name),
            poisson_ratio: nu,
            ..material.clone()
        };
        let ratio = |mesh: &PunchMesh| -> Result<f64, ValidationError> {
            let k = AssembledPunch::new(mesh, &m)?
                .solve(Spring::FrictionlessNormal, options)?
                .stiffness_n_per_m;
            Ok(k / Spring::FrictionlessNormal.analytic_n_per_m(&m, mesh.radius_m)?)
        };
        points.push(LockingPoint {
            poisson_ratio: nu,
            tet4_over_analytic: ratio(tet4)?,
            tet10_over_analytic: ratio(tet10)?,
        });
    }
    Ok(points)
}

/// The error messages of a punch that floats: only u_z prescribed on the punch disk, no far
/// field, so that translations x, y and the rotation about z are free.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SingularSystemReport {
    /// What the rigid-mode check before factorising says.
    pub with_rigid_mode_check: String,
    /// What the solver `auto` picks says when the rigid-mode check is switched off.
    pub without_rigid_mode_check: String,
    /// The direct path without the rigid-mode check: its null-space check (before the
    /// Cholesky pivot check, which misses this graded mesh's free motions).
    #[serde(default)]
    pub direct_without_check: String,
    /// The iterative path without the rigid-mode check: its null-space check at set-up.
    #[serde(default)]
    pub iterative_without_check: String,
}

/// Solves the floating punch through elastic-fem's `solve_static` with its rigid-mode check,
/// then without it by each path (`auto`, direct, iterative), and returns the errors. An `Ok`
/// solution is itself an error here: every path must refuse a singular system.
pub fn singular_system(
    mesh: &PunchMesh,
    material: &SpringMaterial,
) -> Result<SingularSystemReport, ValidationError> {
    let model = Model::new(
        mesh.nodes.clone(),
        mesh.connectivity.clone(),
        fem_material(material)?,
    )
    .map_err(|source| ValidationError::Fem {
        context: format!("floating punch on {}", mesh.source),
        source,
    })?;
    let constraints = Constraints {
        dirichlet: vec![Dirichlet::component(
            mesh.punch_nodes.clone(),
            2,
            -1e-3 * mesh.radius_m,
        )],
        ..Default::default()
    };
    let load = vec![0.0; model.dof_count()];
    let problem = StaticProblem {
        model: &model,
        constraints: &constraints,
        load_n: &load,
    };
    let attempt = |check: bool, method: SolverMethod| -> Result<String, ValidationError> {
        let options = SolverOptions {
            check_rigid_body_modes: check,
            method,
            ..SolverOptions::default()
        };
        match solve_static(&problem, &options) {
            Err(e) => Ok(e.to_string()),
            Ok(solution) => Err(ValidationError::BadPunchMesh {
                mesh: mesh.source.clone(),
                detail: format!(
                    "a floating punch was solved without error (rigid-mode check {check}, {} solver: {}); first displacement {:e} m",
                    solution.choice.method.name(),
                    solution.choice.reason,
                    solution.displacement_m.first().copied().unwrap_or(f64::NAN)
                ),
            }),
        }
    };
    Ok(SingularSystemReport {
        with_rigid_mode_check: attempt(true, SolverMethod::Auto)?,
        without_rigid_mode_check: attempt(false, SolverMethod::Auto)?,
        direct_without_check: attempt(false, SolverMethod::Direct)?,
        iterative_without_check: attempt(false, SolverMethod::Iterative)?,
    })
}

/// One row of the distorted-mesh study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DistortionPoint {
    /// Interior corner nodes moved by up to this fraction of their shortest edge.
    pub amplitude: f64,
    /// Smallest element shape quality (1 = regular), or NaN if the mesh was refused.
    #[serde(deserialize_with = "crate::serde_nan::f64_or_nan")]
    pub min_quality: f64,
    /// Elements below elastic-fem's "poor" quality threshold.
    pub poor_elements: usize,
    /// FEM stiffness / analytic for the spring, or NaN if the mesh was refused.
    #[serde(deserialize_with = "crate::serde_nan::f64_or_nan")]
    pub stiffness_over_analytic: f64,
    /// elastic-fem's error if the mesh was refused (inverted or degenerate element), else empty.
    pub refusal: String,
}

/// splitmix64: a tiny deterministic generator so that the distorted meshes are reproducible.
fn splitmix64(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Uniform number in [−1, 1).
fn symmetric_unit(state: &mut u64) -> f64 {
    (splitmix64(state) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

/// The mesh with every interior corner node moved by a pseudo-random vector of length up to
/// `amplitude` × its shortest incident edge; Tet10 midside nodes follow (edge midpoints).
pub fn distorted(mesh: &PunchMesh, amplitude: f64, seed: u64) -> PunchMesh {
    let interior = mesh.interior_mask();
    let mut shortest = vec![f64::INFINITY; mesh.nodes.len()];
    let corners = |e: usize| -> [usize; 4] {
        let en = mesh.connectivity.element_nodes(e);
        [en[0], en[1], en[2], en[3]]
    };
    let dist = |a: usize, b: usize| {
        (0..3)
            .map(|j| (mesh.nodes[a][j] - mesh.nodes[b][j]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    for e in 0..mesh.element_count() {
        let c = corners(e);
        for i in 0..4 {
            for j in (i + 1)..4 {
                let l = dist(c[i], c[j]);
                shortest[c[i]] = shortest[c[i]].min(l);
                shortest[c[j]] = shortest[c[j]].min(l);
            }
        }
    }
    let mut state = seed;
    let mut nodes = mesh.nodes.clone();
    let mut is_corner = vec![false; mesh.nodes.len()];
    for e in 0..mesh.element_count() {
        for n in corners(e) {
            is_corner[n] = true;
        }
    }
    for n in 0..nodes.len() {
        if interior[n] && is_corner[n] {
            for x in nodes[n].iter_mut() {
                *x += amplitude * shortest[n] * symmetric_unit(&mut state) / 3f64.sqrt();
            }
        }
    }
    if let elastic_fem::Connectivity::Tet10(t) = &mesh.connectivity {
        // gmsh Tet10 edges of the midside nodes 4..9.
        const EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)];
        for e in t {
            for (k, &(a, b)) in EDGES.iter().enumerate() {
                let m = e[4 + k];
                if interior[e[a]] || interior[e[b]] {
                    nodes[m] = std::array::from_fn(|j| 0.5 * (nodes[e[a]][j] + nodes[e[b]][j]));
                }
            }
        }
    }
    PunchMesh {
        source: format!("{} distorted by {amplitude}", mesh.source),
        nodes,
        ..mesh.clone()
    }
}

/// The stiffness of `spring` on distorted copies of `mesh`, one per amplitude.
pub fn distortion_study(
    mesh: &PunchMesh,
    material: &SpringMaterial,
    spring: Spring,
    amplitudes: &[f64],
    options: &PunchSolveOptions,
) -> Result<Vec<DistortionPoint>, ValidationError> {
    let analytic = spring.analytic_n_per_m(material, mesh.radius_m)?;
    let mut points = Vec::new();
    for &amplitude in amplitudes {
        let distorted = distorted(mesh, amplitude, DISTORTION_SEED);
        match AssembledPunch::new(&distorted, material) {
            Ok(assembled) => {
                let quality = assembled.model().quality().clone();
                let k = assembled.solve(spring, options)?.stiffness_n_per_m;
                points.push(DistortionPoint {
                    amplitude,
                    min_quality: quality.min_quality,
                    poor_elements: quality.poor_elements.len(),
                    stiffness_over_analytic: k / analytic,
                    refusal: String::new(),
                });
            }
            Err(ValidationError::Fem { source, .. }) => points.push(DistortionPoint {
                amplitude,
                min_quality: f64::NAN,
                poor_elements: 0,
                stiffness_over_analytic: f64::NAN,
                refusal: source.to_string(),
            }),
            Err(other) => return Err(other),
        }
    }
    Ok(points)
}

/// Seed of the distorted meshes (any fixed value; results are reproducible).
pub const DISTORTION_SEED: u64 = 0x5A_D1_5E;
