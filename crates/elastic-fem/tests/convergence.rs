//! Manufactured solution: u_i = sin(κ_i · x + φ_i) on the unit cube, body force
//! b = −div σ(u) = μ |κ_j|² u_j e_j + (λ + μ) Σ_i κ_ii κ_i sin(θ_i), Dirichlet u = u_exact at all
//! boundary nodes. Asserted convergence rates (least-squares fit over 3 meshes, h halved):
//! - Tet4: L2 rate 2 and energy rate 1, each within ±0.25;
//! - Tet10: L2 rate 3 and energy rate 2, each within ±0.25.

mod common;

use common::{fitted_rate, model_of};
use elastic_fem::element::physical_gradients;
use elastic_fem::mesh_gen::BoxMesh;
use elastic_fem::quadrature::tet_degree5;
use elastic_fem::shape::{Tet4, Tet10, TetShape};
use elastic_fem::{
    Connectivity, Constraints, Dirichlet, LameParameters, Material, Model, SolverOptions,
    StaticProblem, loads, solve_static,
};

const KAPPA: [[f64; 3]; 3] = [[1.1, 0.6, 0.4], [0.5, 1.3, -0.7], [-0.6, 0.3, 0.9]];
const PHASE: [f64; 3] = [0.3, -0.2, 0.5];

fn theta(i: usize, x: [f64; 3]) -> f64 {
    KAPPA[i][0] * x[0] + KAPPA[i][1] * x[1] + KAPPA[i][2] * x[2] + PHASE[i]
}

fn exact(x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| theta(i, x).sin())
}

/// ∂u_i/∂x_j.
fn exact_gradient(x: [f64; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| KAPPA[i][j] * theta(i, x).cos()))
}

fn body_force(l: LameParameters, x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|j| {
        let k2: f64 = KAPPA[j].iter().map(|v| v * v).sum();
        let grad_div: f64 = (0..3)
            .map(|i| KAPPA[i][i] * KAPPA[i][j] * theta(i, x).sin())
            .sum();
        l.mu * k2 * theta(j, x).sin() + (l.lambda + l.mu) * grad_div
    })
}

/// (L2 error, energy-norm error) of the FE solution u.
fn errors<const N: usize, S: TetShape<N>>(
    model: &Model,
    conn: &[[usize; N]],
    u: &[f64],
    lame: LameParameters,
) -> (f64, f64) {
    let c = lame.voigt_stiffness();
    let rule = tet_degree5();
    let (mut l2, mut energy) = (0.0, 0.0);
    for el in conn {
        let x = el.map(|n| model.nodes()[n]);
        for (xi, w) in rule.points.iter().zip(&rule.weights) {
            let (g, det) = physical_gradients::<N, S>(&x, *xi).unwrap();
            let shape = S::values(*xi);
            let mut pos = [0.0; 3];
            let mut uh = [0.0; 3];
            let mut grad = [[0.0; 3]; 3];
            for a in 0..N {
                for i in 0..3 {
                    pos[i] += shape[a] * x[a][i];
                    uh[i] += shape[a] * u[3 * el[a] + i];
                    for j in 0..3 {
                        grad[i][j] += u[3 * el[a] + i] * g[a][j];
                    }
                }
            }
            let ue = exact(pos);
            let ge = exact_gradient(pos);
            l2 += w * det * (0..3).map(|i| (uh[i] - ue[i]).powi(2)).sum::<f64>();
            let d: [[f64; 3]; 3] =
                std::array::from_fn(|i| std::array::from_fn(|j| grad[i][j] - ge[i][j]));
            let eps = nalgebra::Vector6::from(elastic_fem::element::voigt_strain(&d));
            energy += w * det * eps.dot(&(c * eps));
        }
    }
    (l2.sqrt(), energy.sqrt())
}

fn solve_level(mesh: &BoxMesh, lame: LameParameters) -> (f64, f64) {
    let model = model_of(mesh, Material::Isotropic(lame));
    let mut f = vec![0.0; model.dof_count()];
    loads::add_body_force(&model, |x| body_force(lame, x), &mut f).unwrap();
    let dirichlet = mesh
        .boundary_nodes()
        .into_iter()
        .map(|n| Dirichlet {
            nodes: vec![n],
            displacement_m: exact(mesh.nodes[n]).map(Some),
        })
        .collect();
    let constraints = Constraints {
        dirichlet,
        ..Default::default()
    };
    let sol = solve_static(
        &StaticProblem {
            model: &model,
            constraints: &constraints,
            load_n: &f,
        },
        &SolverOptions::default(),
    )
    .unwrap();
    match model.connectivity() {
        Connectivity::Tet4(c) => errors::<4, Tet4>(&model, c, &sol.displacement_m, lame),
        Connectivity::Tet10(c) => errors::<10, Tet10>(&model, c, &sol.displacement_m, lame),
    }
}

fn check_rates(label: &str, meshes: &[BoxMesh], l2_rate: f64, energy_rate: f64) {
    let lame = LameParameters::from_young_poisson(1.0, 0.3).unwrap();
    let h: Vec<f64> = meshes.iter().map(|m| 1.0 / m.divisions[0] as f64).collect();
    let (l2, en): (Vec<f64>, Vec<f64>) = meshes.iter().map(|m| solve_level(m, lame)).unzip();
    let (r_l2, r_en) = (fitted_rate(&h, &l2), fitted_rate(&h, &en));
    eprintln!(
        "{label}: h = {h:?}, L2 errors = {l2:?} (rate {r_l2:.3}), energy errors = {en:?} (rate {r_en:.3})"
    );
    assert!(
        (r_l2 - l2_rate).abs() <= 0.25,
        "{label}: L2 convergence rate {r_l2:.3}, expected {l2_rate} ± 0.25"
    );
    assert!(
        (r_en - energy_rate).abs() <= 0.25,
        "{label}: energy-norm convergence rate {r_en:.3}, expected {energy_rate} ± 0.25"
    );
}

#[test]
fn tet4_manufactured_solution_converges_at_order_two_in_l2_and_one_in_energy() {
    let meshes: Vec<BoxMesh> = [4, 8, 16]
        .iter()
        .map(|&n| BoxMesh::tet4([1.0; 3], [n; 3]))
        .collect();
    check_rates("Tet4", &meshes, 2.0, 1.0);
}

#[test]
fn tet10_manufactured_solution_converges_at_order_three_in_l2_and_two_in_energy() {
    let meshes: Vec<BoxMesh> = [2, 4, 8]
        .iter()
        .map(|&n| BoxMesh::tet10([1.0; 3], [n; 3]))
        .collect();
    check_rates("Tet10", &meshes, 3.0, 2.0);
}
