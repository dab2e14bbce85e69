//! The default slider's row (100 posts of 20 µm at 40 µm, Si on LiNbO3, 40 N) on the strip's
//! condensed normal and tangential compliance: the coupled 50-point curve, its cost per point,
//! the growth of the cost with the post count, and η_dyn against the lumped model.
//!
//! Heavy (meshes and factors the default strip, tens of seconds): run with
//! `cargo test -p coupled-dynamics --test default_row -- --ignored --nocapture`.

use std::time::Instant;

use contact_springs::{Material, post_springs};
use coupled_dynamics::{CoupledModel, CoupledScene, PreloadBalance, solve};
use nalgebra::DMatrix;
use static_contact::{StaticParams, prepare_strip};
use stick_slip::{DynamicScene, Wave};

fn scene_of(
    x: Vec<f64>,
    cn: DMatrix<f64>,
    ct: DMatrix<f64>,
    share: f64,
    preload_n: f64,
) -> CoupledScene {
    let mut scene =
        CoupledScene::independent_posts(Wave::paper_default(), x, 1.0, 1.0, 0.3, 0.3, preload_n);
    scene.normal_compliance_m_per_n = cn;
    scene.tangential_compliance_m_per_n = ct;
    scene.strip_share = share;
    scene.preload_balance = PreloadBalance::Instant;
    scene.steps_per_period = 128;
    scene
}

#[test]
#[ignore = "meshes and factors the default 100-post strip; see the module docs for the command"]
fn default_row_coupled_curve_cost_and_eta_dyn() {
    let params = StaticParams::default();
    let t = Instant::now();
    let strip = prepare_strip(&params).expect("default strip");
    let tips = strip.model.tip_compliance().expect("tip compliance");
    eprintln!(
        "strip: {} posts, prepared in {:.1} s (+ tip compliance {:.1} s total); cross ratios slider {:.3e}, stator {:.3e}",
        strip.model.post_count(),
        strip.mesh_s + strip.condensation_s,
        t.elapsed().as_secs_f64(),
        tips.cross_ratio(&tips.slider_cross_m_per_n),
        tips.cross_ratio(&tips.stator_cross_m_per_n)
    );
    let n_all = strip.model.post_count();
    let x_all: Vec<f64> = strip.model.posts.iter().map(|p| p.x_m).collect();
    let share = params.strip_share();
    let springs = post_springs(&Material::silicon(), &Material::lithium_niobate(), 10e-6).unwrap();
    for n in [25, 50, 100].into_iter().filter(|&n| n <= n_all) {
        let first = (n_all - n) / 2;
        let idx: Vec<usize> = (first..first + n).collect();
        let sub = |m: &DMatrix<f64>| DMatrix::from_fn(n, n, |i, j| m[(idx[i], idx[j])]);
        let scene = scene_of(
            idx.iter().map(|&i| x_all[i]).collect(),
            sub(&tips.normal_m_per_n),
            sub(&tips.tangential_m_per_n),
            share * n as f64 / n_all as f64,
            params.preload_n,
        );
        let t = Instant::now();
        let model = CoupledModel::new(&scene).expect("coupled model");
        let normal_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let result = solve(&model, None).expect("coupled curve");
        let curve_s = t.elapsed().as_secs_f64();
        let evaluations = result.curve.len();
        eprintln!(
            "n = {n}: normal grid {normal_s:.2} s, curve {curve_s:.2} s ({:.1} ms per curve point over {evaluations} points plus the no-load root), stall {:.4} N, no-load {:.4} m/s, max energy residual {:.3e}, max solver residual {:.1e}",
            1e3 * curve_s / evaluations as f64,
            result.stall_thrust_n,
            result.no_load_speed_m_per_s,
            result.energy_balance_residual,
            result.max_solver_residual
        );
        if n == n_all.min(100) {
            let mut lumped = DynamicScene::paper_default(springs.k_n_n_per_m, springs.k_t_n_per_m);
            lumped.slider.preload_n = params.preload_n;
            let (eta, misfit) =
                coupled_dynamics::fit_eta_dyn(&result.curve, result.stall_thrust_n, &lumped)
                    .expect("η_dyn");
            let static_eta = lumped.slider.effective_ratio;
            let at_static = coupled_dynamics::lumped_misfit(
                &result.curve,
                result.stall_thrust_n,
                &lumped,
                static_eta,
            )
            .unwrap();
            eprintln!(
                "η_dyn = {eta:.4} (rms thrust misfit {misfit:.3e} of the stall thrust); lumped at the paper's η = {static_eta}: misfit {at_static:.3e}"
            );
            assert!(result.stall_thrust_n > 0.0, "the default slider runs");
        }
    }
}
