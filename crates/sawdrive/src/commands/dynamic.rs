//! `sawdrive dynamic`: the stick/slip model with the scene's η (or the static stage's).

use anyhow::anyhow;
use sawdrive::output::{ResultKind, StagedDir};
use sawdrive::pipeline::{
    check_dynamic_figures, run_dynamic_stage, run_static, scene_springs, write_dynamic_stage_files,
};
use sawdrive::scene::load_scene;

use crate::cli::StageArgs;

pub fn run(args: &StageArgs) -> anyhow::Result<()> {
    let scene = load_scene(args.input.scene.as_deref(), &args.input.overrides)?;
    let springs = scene_springs(&scene)?;
    let cache = (!args.no_cache).then(|| args.out.join(".cache"));
    let statics = match scene.contact.effective_ratio {
        Some(_) => None,
        None => Some(run_static(&scene, &springs, cache.as_deref(), false)?),
    };
    let eta = match (&statics, scene.contact.effective_ratio) {
        (_, Some(eta)) => eta,
        (Some(outcome), None) => outcome.effective_ratio.ok_or_else(|| {
            anyhow!("the static stage could not identify η: give --set effective_ratio=0.36")
        })?,
        (None, None) => unreachable!("the static stage runs when η is not given"),
    };
    let stage = run_dynamic_stage(&scene, &springs, eta, statics.as_ref(), cache.as_deref())?;
    check_dynamic_figures(&stage)?;
    let staged = StagedDir::create(
        &args.out.join(&scene.name).join("dynamic"),
        ResultKind::Dynamic,
    )?;
    write_dynamic_stage_files(&scene.name, &stage, staged.path())?;
    let folder = staged.commit()?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&stage.json())?);
        return Ok(());
    }
    let run = &stage.lumped;
    let result = &run.result;
    for w in &result.warnings {
        eprintln!("warning: {w}");
    }
    println!(
        "dynamic model of {}: {} ({})",
        scene.name,
        stage.model_name(),
        stage.model_reason()
    );
    if let Some(estimate) = stage.lumped_error_estimate {
        println!(
            "lumped model's estimated error {estimate:.2e} (relative, against the coupled model)"
        );
    }
    if let Some(coupled) = &stage.coupled {
        // The coupled warnings lead with the scene's, printed above with the lumped model's.
        for w in coupled.warnings.iter().skip(scene.warnings.len()) {
            eprintln!("warning: {w}");
        }
        println!(
            "coupled: {} posts, {} steps per period, η_dyn {}",
            coupled.posts,
            coupled.steps_per_period,
            coupled.eta_dyn.map_or("n/a".into(), |e| format!("{e:.4}"))
        );
        println!(
            "stall thrust               {:.4} N   (lumped at the static η: {:.4} N)",
            coupled.stall_thrust_n, result.stall_thrust_n
        );
        println!(
            "no-load speed              {:.4} m/s (lumped at the static η: {:.4} m/s)",
            coupled.no_load_speed_m_per_s, result.no_load_speed_m_per_s
        );
        println!("max efficiency             {:.4}", coupled.efficiency);
        println!(
            "energy balance residual    {:.2e} (relative to the power flow)",
            coupled.energy_balance_residual
        );
        println!("wall time                  {:.3} s", coupled.wall_time_s);
        println!("results in {}", folder.display());
        return Ok(());
    }
    println!(
        "effective posts η·N        {:.0} (η = {eta:.4})",
        result.effective_post_count
    );
    println!(
        "stall thrust               {:.4} N   (friction limit μP = {:.3} N)",
        result.stall_thrust_n, result.friction_limit_n
    );
    println!(
        "no-load speed              {:.4} m/s (crest speed A_t ω = {:.3} m/s)",
        result.no_load_speed_m_per_s, result.crest_speed_m_per_s
    );
    println!("max efficiency             {:.4}", result.efficiency);
    println!("stick fraction             {:.4}", result.stick_fraction);
    let integrator = run
        .scene
        .integrator
        .resolve(result.model, run.scene.wave.period_s());
    let work = run.scene.work_estimate(result.model, &integrator);
    println!(
        "estimated work             {:.2e} post-steps, {} (limit {:.0e})",
        work.post_steps(),
        integrator.name(),
        run.scene.options.max_post_steps
    );
    println!("wall time                  {:.3} s", result.wall_time_s);
    println!("results in {}", folder.display());
    Ok(())
}
