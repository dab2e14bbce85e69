//! `sawdrive uq`: Monte Carlo bands of a scene under its `[scatter]` section (crate `design`'s
//! study on the library's motor model, [`SceneEvaluator`]).

use design::ModelFidelity as Fidelity;
use design::scatter::load_uq_inputs;
use design::uq::{UqOptions, run_uq};
use sawdrive::pipeline::evaluate::SceneEvaluator;

use crate::cli::UqArgs;

pub fn run(args: &UqArgs) -> anyhow::Result<()> {
    let ev = SceneEvaluator;
    let (scene, scatter) = load_uq_inputs(&ev, args.input.scene.as_deref(), &args.input.overrides)?;
    let options = UqOptions {
        samples: args.samples,
        seed: args.seed,
        out_dir: args.out.clone(),
        fidelity: if args.patch {
            Fidelity::Patch
        } else {
            Fidelity::Slider
        },
        write_files: true,
    };
    let (report, folder) = run_uq(&ev, &scene, &scatter, &options)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    println!(
        "{}: {} samples (seed {}, {} resumed), static model {}, {:.1} s",
        report.scene,
        report.samples,
        report.seed,
        report.resumed_samples,
        report.fidelity,
        report.wall_time_s
    );
    println!(
        "dynamics: {} ({} of {} samples coupled)",
        report.dynamics, report.coupled_samples, report.samples
    );
    println!(
        "{:<26} {:>11} {:>11} {:>11} {:>11} {:>11}",
        "output", "determ.", "mean", "P5", "P50", "P95"
    );
    let rows = [
        ("effective_contact_ratio", &report.effective_contact_ratio),
        ("stall_thrust_n", &report.stall_thrust_n),
        ("no_load_speed_m_per_s", &report.no_load_speed_m_per_s),
        ("max_output_power_w", &report.max_output_power_w),
        ("efficiency", &report.efficiency),
    ];
    for (k, (name, b)) in rows.iter().enumerate() {
        println!(
            "{name:<26} {:>11.5} {:>11.5} {:>11.5} {:>11.5} {:>11.5}",
            report.deterministic[k].1, b.mean, b.p5, b.p50, b.p95
        );
    }
    print_cost(&report.cost);
    println!("{} samples failed", report.failed_samples.len());
    for (k, e) in &report.failed_samples {
        println!("sample {k} failed (left out of the bands): {e}");
    }
    for (output, ranking) in &report.sensitivity {
        if let Some(top) = ranking.first().filter(|s| s.spearman_rho.is_some()) {
            println!(
                "spread of {output} driven most by {} (Spearman ρ = {:.2})",
                top.input,
                top.spearman_rho.unwrap_or(0.0)
            );
        }
    }
    println!("results in {}", folder.display());
    Ok(())
}

/// The cost lines: the static and dynamic parts of a sample, and the coupled samples' pieces.
fn print_cost(c: &design::uq::UqCost) {
    println!(
        "cost: operator {:.3} s once; per sample {:.3} s static (of which {:.3} s its own \
         operator) + {:.4} s dynamic ({} computed, {} built their own operator)",
        c.operator_s,
        c.static_s,
        c.sample_operator_s,
        c.dynamic_s,
        c.computed_samples,
        c.operators_built
    );
    if c.coupled_samples > 0 {
        let k = &c.coupled;
        println!(
            "cost of a coupled sample (wall on its thread, {} computed): normal grid {:.2} s, \
             stall {:.2} s, no-load search {:.2} s, other points {:.2} s ({} periods, every \
             solved speed)",
            c.coupled_samples, k.normal_grid_s, k.stall_s, k.no_load_s, k.points_s, k.periods
        );
    }
}
