//! The constrained CG on the lattice operator against references: a dense active-set solve of
//! the densified operator, the analytic rigid punch on springs (tilt), convergence in the number
//! of rows.

use nalgebra::DMatrix;
use slider_contact::{
    CgOptions, ConstrainedCg, Imperfections, ImperfectionsExt, LatticeKernel, LatticeOperator,
    SliderModel, SliderParams,
};
use static_contact::{ActiveSetSolver, ContactProblem};

/// The CG solved to 1e-9 (tighter than its default): these checks compare forces to 1e-7–1e-8
/// of P/N.
const TIGHT: CgOptions = CgOptions {
    tolerance: 1e-9,
    max_iterations: slider_contact::solver::DEFAULT_MAX_ITERATIONS,
};

/// A 10 × 10 corner of the default slider with the default per-post load (4 mN), solved to 1e-9.
fn small_slider(scatter_m: f64) -> SliderParams {
    SliderParams {
        solver: TIGHT,
        posts_x: 10,
        posts_y: 10,
        slider_length_m: 10.0 * 40e-6,
        slider_width_m: 10.0 * 40e-6,
        preload_n: 0.4,
        imperfections: Imperfections {
            height_scatter_m: scatter_m,
            scatter_seed: 3,
            ..Imperfections::default()
        },
        ..SliderParams::default()
    }
}

#[test]
fn the_cg_matches_a_dense_active_set_solve_on_a_ten_by_ten_lattice() {
    for scatter in [0.0, 5e-9] {
        let params = small_slider(scatter);
        let model = SliderModel::build(&params).unwrap();
        let dense = LatticeKernel::new(&params.operator_spec())
            .unwrap()
            .to_dense();
        for phase in [0.0, 1.3] {
            let h = model.obstacle_heights(Some(phase));
            let cg = model.solve_phase(params.preload_n, Some(phase)).unwrap();
            let reference = ActiveSetSolver::default()
                .solve(&ContactProblem {
                    compliance_m_per_n: dense.clone(),
                    obstacle_height_m: h,
                    preload_n: params.preload_n,
                    length_scale_m: Some(20e-9),
                })
                .unwrap();
            let mean = params.preload_n / 100.0;
            for i in 0..100 {
                assert!(
                    (cg.force_n[i] - reference.force_n[i]).abs() < 1e-7 * mean,
                    "post force {i} (σ = {scatter} m, θ₀ = {phase}): CG {} vs active set {}",
                    cg.force_n[i],
                    reference.force_n[i]
                );
            }
            assert!(
                (cg.reference_height_m - reference.reference_height_m).abs() < 1e-7 * 20e-9,
                "slider approach: CG {} vs active set {}",
                cg.reference_height_m,
                reference.reference_height_m
            );
        }
    }
}

/// Forces of a rigid flat punch tilted by τ across length L on a bed of n_x × n_y independent
/// springs k (rows identical): f = k⟨−τ x_i/L − z⟩₊, the contact closing the columns of lowest
/// tip first; z from Σf = P for the number m of columns in contact that is consistent.
fn rigid_punch_on_springs(
    x_m: &[f64],
    rows: usize,
    k: f64,
    tilt_m: f64,
    l: f64,
    p: f64,
) -> Vec<f64> {
    let d: Vec<f64> = x_m.iter().map(|x| -tilt_m * x / l).collect();
    let mut order: Vec<usize> = (0..d.len()).collect();
    order.sort_by(|&a, &b| d[b].total_cmp(&d[a]));
    let per_row = p / (k * rows as f64);
    for m in 1..=d.len() {
        let z = (order[..m].iter().map(|&i| d[i]).sum::<f64>() - per_row) / m as f64;
        if order.get(m).is_none_or(|&j| d[j] <= z) {
            return d.iter().map(|di| k * (di - z).max(0.0)).collect();
        }
    }
    unreachable!("all columns in contact is always consistent")
}

#[test]
fn a_pure_tilt_on_independent_springs_gives_the_rigid_punch_load_distribution() {
    let k = 1.8e6;
    let params = SliderParams {
        wave_amplitude_m: 0.0,
        ..small_slider(0.0)
    };
    let g = params.geometry();
    let l = g.slider_length_m;
    let x: Vec<f64> = (0..g.posts_x).map(|i| g.x_m(i) - 0.5 * l).collect();
    let diag = DMatrix::<f64>::identity(g.len(), g.len()) / k;
    // Small tilt: every post touches (linear load); large tilt: part of the slider lifts off.
    for tilt in [1e-9, 20e-9] {
        let offsets = Imperfections {
            tilt_x_m: tilt,
            ..Imperfections::default()
        }
        .post_offsets_m(&g)
        .unwrap();
        let sol = ConstrainedCg::new(TIGHT)
            .solve(&diag, &offsets, params.preload_n, tilt)
            .unwrap();
        let expected = rigid_punch_on_springs(&x, g.posts_y, k, tilt, l, params.preload_n);
        for (i, e) in expected.iter().enumerate() {
            for j in 0..g.posts_y {
                let f = sol.force_n[g.index(i, j)];
                assert!(
                    (f - e).abs() < 1e-8 * params.preload_n / g.len() as f64,
                    "post ({i}, {j}) under tilt {tilt} m: force {f} vs rigid punch {e}"
                );
            }
        }
    }
}

#[test]
fn eta_converges_with_the_number_of_identical_rows() {
    // 10 posts along x (one wavelength), the per-post load of 40 N on the default slider; the
    // rows beyond ≈ t/p = 12 of each edge see the same neighbourhood, so η settles as rows grow.
    // Measured: 0.8265, 0.8193, 0.8160, 0.8143: the step halves per doubling (the edge rows'
    // share, ∝ 1/rows).
    let etas: Vec<f64> = [25usize, 50, 100, 200]
        .iter()
        .map(|&rows| {
            let params = SliderParams {
                posts_x: 10,
                posts_y: rows,
                slider_length_m: 10.0 * 40e-6,
                slider_width_m: rows as f64 * 40e-6,
                preload_n: 4e-3 * (10 * rows) as f64,
                ..SliderParams::default()
            };
            slider_contact::run(&params)
                .unwrap()
                .effective_contact_ratio
                .unwrap()
        })
        .collect();
    println!("η with 25, 50, 100, 200 rows: {etas:?}");
    let steps: Vec<f64> = etas.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    assert!(
        steps[2] < steps[0] && steps[2] < 0.01 * etas[3],
        "η must settle as rows are added: {etas:?}"
    );
}

#[test]
fn the_fft_operator_and_the_dense_kernel_agree_on_the_default_lattice_diagonal() {
    use slider_contact::ComplianceOperator;
    let params = SliderParams::default();
    let op = LatticeOperator::new(&params.operator_spec()).unwrap();
    // C e_k of one unit force reproduces the kernel at every offset from post k.
    let kernel = LatticeKernel::new(&params.operator_spec()).unwrap();
    let g = params.geometry();
    let k = g.index(37, 61);
    let mut e = vec![0.0; g.len()];
    e[k] = 1.0;
    let mut u = vec![0.0; g.len()];
    op.apply(&e, &mut u);
    for (i, j) in [(37, 61), (0, 0), (99, 99), (38, 61), (37, 90)] {
        let expected = kernel.at_offset(i as i64 - 37, j as i64 - 61);
        assert!(
            (u[g.index(i, j)] / expected - 1.0).abs() < 1e-9,
            "compliance between posts (37, 61) and ({i}, {j}): FFT {} vs kernel {expected}",
            u[g.index(i, j)]
        );
    }
    assert!(
        (op.diagonal()[k] / kernel.parts().total_m_per_n() - 1.0).abs() < 1e-15,
        "diagonal of C"
    );
}
