//! `sawdrive design`: the texture optimiser (crate `design`'s study on the library's motor
//! model, [`SceneEvaluator`]).

use design::study::{DesignSpec, describe_variables, run_design};
use sawdrive::pipeline::evaluate::SceneEvaluator;

use crate::cli::DesignArgs;

pub fn run(args: &DesignArgs) -> anyhow::Result<()> {
    let ev = SceneEvaluator;
    let spec = DesignSpec::read(&ev, &args.design)?;
    let (report, folder) = run_design(&ev, &spec, &args.out, true)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    let o = &report.optimum;
    println!(
        "{}: optimum {}",
        report.name,
        describe_variables(&ev, &spec, &o.variables)
    );
    println!(
        "  {} = {:.6} ({}, stage {}{})",
        o.objective,
        o.objective_value,
        o.fidelity,
        o.stage,
        report
            .quantile
            .map_or(String::new(), |q| format!(", quantile {q}"))
    );
    if let Some(b) = &report.baseline {
        println!(
            "  scene's own design: {} = {} ({})",
            o.objective,
            b.objective
                .map_or("infeasible".into(), |v| format!("{v:.6}")),
            b.fidelity
        );
    }
    println!("  dynamics: {}", report.dynamics);
    for (fidelity, n, s) in &report.cost {
        println!("  {n} evaluations at {fidelity}, {s:.2} s each");
    }
    if report.resumed_evaluations > 0 {
        println!(
            "  {} evaluations reused from saved results (an earlier run, or a design met twice)",
            report.resumed_evaluations
        );
    }
    println!(
        "  {:.1} s; results in {}",
        report.wall_time_s,
        folder.display()
    );
    Ok(())
}
