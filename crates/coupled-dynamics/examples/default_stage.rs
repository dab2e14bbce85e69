//! The coupled dynamic stage of the default `sawdrive run`, alone: the paper motor on a cached
//! strip compliance, 64 steps per period, the 50-point curve, the post histories at half the
//! no-load speed and the two coarse-step (T/32) points of the step-error estimate — the work
//! `sawdrive`'s `pipeline::coupled::run_coupled_model` does after the static stage (η_dyn, a
//! lumped-model fit, left out).
//!
//! `cargo run --release -p coupled-dynamics --example default_stage -- COMPLIANCE.json [--repeat N] [--bits FILE] [--no-eta-dyn]`
//!
//! COMPLIANCE.json is the compliance cache entry `sawdrive run` writes beside its static report
//! (`out/.cache/compliance-<geometry key>.json`: the 100-post strip's normal and tangential tip
//! compliances). Prints wall time per repeat and the process CPU time; `--bits` writes every
//! curve point's speed and thrust bits (hex) and the headline numbers, for comparing runs;
//! `--no-eta-dyn` leaves the η_dyn fit out.

use std::fmt::Write as _;
use std::time::Instant;

mod common;
use common::cpu_s;

use contact_springs::{Material, post_springs};
use coupled_dynamics::{CoupledModel, CoupledScene, solve};
use stick_slip::DynamicScene;

/// Steps per period of the default coupled run (`sawdrive`'s `DEFAULT_COUPLED_STEPS_PER_PERIOD`).
const STEPS_PER_PERIOD: usize = 64;

fn run(
    scene: &CoupledScene,
    lumped: Option<&DynamicScene>,
) -> Result<String, coupled_dynamics::CoupledError> {
    let model = CoupledModel::new(scene)?;
    let result = solve(&model, lumped)?;
    let speed = 0.5 * result.no_load_speed_m_per_s;
    let (histories, coarse) = rayon::join(
        || model.post_histories(speed),
        || {
            let mut coarse = scene.clone();
            coarse.steps_per_period = STEPS_PER_PERIOD / 2;
            let coarse = CoupledModel::new(&coarse)?;
            let (a, b) = rayon::join(|| coarse.at_speed(0.0), || coarse.at_speed(speed));
            Ok::<_, coupled_dynamics::CoupledError>([a?.thrust_n, b?.thrust_n])
        },
    );
    let (at_half, _) = histories?;
    let coarse = coarse?;
    let mut bits = String::new();
    for p in &result.curve {
        let _ = writeln!(
            bits,
            "{:016x} {:016x} periods {} iterations {}",
            p.speed_m_per_s.to_bits(),
            p.thrust_n.to_bits(),
            p.periods,
            p.solver_iterations
        );
    }
    let _ = writeln!(
        bits,
        "stall {:.12e} N, no-load {:.12e} m/s, at v0/2 {:.12e} N, coarse {:.12e} {:.12e} N, eta_dyn {:.6}, max energy residual {:.3e}, max solver residual {:.3e}",
        result.stall_thrust_n,
        result.no_load_speed_m_per_s,
        at_half.thrust_n,
        coarse[0],
        coarse[1],
        result.eta_dyn.unwrap_or(f64::NAN),
        result.energy_balance_residual,
        result.max_solver_residual
    );
    Ok(bits)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!(
            "error: usage: default_stage COMPLIANCE.json [--repeat N] [--bits FILE] [--no-eta-dyn]"
        );
        std::process::exit(2);
    };
    let option = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|k| args.get(k + 1))
    };
    let repeat: usize = match option("--repeat").map(|v| v.parse()) {
        None => 1,
        Some(Ok(r)) if r > 0 => r,
        Some(_) => {
            eprintln!("error: --repeat must be a positive integer");
            std::process::exit(2);
        }
    };
    let scene = common::cached_strip(path, STEPS_PER_PERIOD).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(1);
    });
    let springs = post_springs(
        &Material::silicon(),
        &Material::lithium_niobate(),
        common::RADIUS_M,
    )
    .unwrap_or_else(|e| {
        eprintln!("error: post springs: {e}");
        std::process::exit(1);
    });
    let lumped = DynamicScene::paper_default(springs.k_pn_n_per_m, springs.k_pt_n_per_m);
    let cpu0 = cpu_s();
    let mut bits = String::new();
    for r in 0..repeat {
        let started = Instant::now();
        bits = run(
            &scene,
            (!args.iter().any(|a| a == "--no-eta-dyn")).then_some(&lumped),
        )
        .unwrap_or_else(|e| {
            eprintln!("error: {e}");
            std::process::exit(1);
        });
        println!(
            "repeat {r}: coupled stage {:.3} s wall",
            started.elapsed().as_secs_f64()
        );
    }
    println!(
        "CPU {:.2} s over {repeat} repeats ({} threads); load average {}",
        cpu_s() - cpu0,
        rayon::current_num_threads(),
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    );
    print!("{}", bits.lines().last().unwrap_or_default());
    println!();
    if let Some(file) = option("--bits") {
        std::fs::write(file, &bits).unwrap_or_else(|e| {
            eprintln!("error: --bits {file}: {e}");
            std::process::exit(1);
        });
    }
}
