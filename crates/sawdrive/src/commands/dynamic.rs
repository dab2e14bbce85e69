//! `sawdrive dynamic`: the stick/slip model with the scene's η (or the static stage's).

use anyhow::anyhow;
use sawdrive::output::StagedDir;
use sawdrive::pipeline::{run_dynamic, run_static, scene_springs, write_dynamic_files};
use sawdrive::scene::load_scene;

use crate::cli::StageArgs;

pub fn run(args: &StageArgs) -> anyhow::Result<()> {
    let scene = load_scene(args.input.scene.as_deref(), &args.input.overrides)?;
    let springs = scene_springs(&scene)?;
    let eta = match scene.contact.effective_ratio {
        Some(eta) => eta,
        None => {
            let cache = (!args.no_cache).then(|| args.out.join(".cache"));
            let outcome = run_static(&scene, &springs, cache.as_deref(), false)?;
            outcome.effective_ratio.ok_or_else(|| {
                anyhow!("the static stage could not identify η: give --set effective_ratio=0.36")
            })?
        }
    };
    let run = run_dynamic(&scene, &springs, eta)?;
    let result = &run.result;
    let staged = StagedDir::create(&args.out.join(&scene.name).join("dynamic"))?;
    write_dynamic_files(&scene.name, &run, staged.path())?;
    let folder = staged.commit()?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(result)?);
        return Ok(());
    }
    for w in &result.warnings {
        eprintln!("warning: {w}");
    }
    println!(
        "dynamic model of {}: {} ({})",
        scene.name,
        serde_json::to_value(result.model)?.as_str().unwrap_or(""),
        result.model_reason
    );
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
