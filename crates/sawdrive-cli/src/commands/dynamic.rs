//! `sawdrive dynamic`: the stick/slip model with the scene's η (or the static stage's); for a
//! ball slider (`slider.shape = "ball"`), the ball model.

use sawdrive::output::{ResultKind, StagedDir};
use sawdrive::pipeline::{
    RunControl, check_dynamic_figures, effective_ratio, run_ball_stage, run_dynamic_stage,
    scene_springs, write_ball_stage_files, write_dynamic_stage_files,
};
use sawdrive::scene::{Scene, load_scene};

use crate::cli::StageArgs;

pub fn run(args: &StageArgs) -> anyhow::Result<()> {
    let scene = load_scene(args.input.scene.as_deref(), &args.input.overrides)?;
    if scene.ball.is_some() {
        return run_ball(args, &scene);
    }
    let springs = scene_springs(&scene)?;
    let cache = (!args.no_cache).then(|| args.out.join(".cache"));
    let given_or_fem = effective_ratio(
        &scene,
        &springs,
        cache.as_deref(),
        false,
        &RunControl::none(),
    )?;
    let (eta, statics) = (given_or_fem.value, given_or_fem.statics);
    let stage = run_dynamic_stage(
        &scene,
        &springs,
        eta,
        statics.as_ref(),
        cache.as_deref(),
        &RunControl::none(),
    )?;
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
    if stage.coupled.is_some() {
        print_coupled(&stage, scene.warnings.len());
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

/// The coupled run's figures (its warnings after the scene's `scene_warnings`, printed with
/// the lumped model's), with the lumped model's at the static η beside them.
fn print_coupled(stage: &sawdrive::pipeline::DynamicStage, scene_warnings: usize) {
    let Some(coupled) = &stage.coupled else {
        return;
    };
    // The coupled warnings lead with the scene's, printed above with the lumped model's.
    for w in coupled.warnings.iter().skip(scene_warnings) {
        eprintln!("warning: {w}");
    }
    let lattice = stage.coupled_slider.as_ref().map_or(String::new(), |s| {
        format!(" (whole slider, {} × {})", s.posts_x, s.posts_y)
    });
    println!(
        "coupled: {} posts{lattice}, {} steps per period, η_dyn {}",
        coupled.posts,
        coupled.steps_per_period,
        coupled.eta_dyn.map_or("n/a".into(), |e| format!("{e:.4}"))
    );
    if let Some(half) = stage.coupled_slider.as_ref().and_then(|s| s.maps.get(1)) {
        let (i, j) = half.hottest_post();
        println!(
            "hottest post at {:.4} m/s   column {i}, row {j}: {:.3e} W of friction (mean {:.3e} W)",
            half.means.speed_m_per_s,
            half.means.friction_power_w[i * half.posts_y + j],
            half.total_friction_power_w() / coupled.posts as f64
        );
    }
    println!(
        "stall thrust               {:.4} N   (lumped at the static η: {:.4} N)",
        coupled.stall_thrust_n, stage.lumped.result.stall_thrust_n
    );
    println!(
        "no-load speed              {:.4} m/s (lumped at the static η: {:.4} m/s)",
        coupled.no_load_speed_m_per_s, stage.lumped.result.no_load_speed_m_per_s
    );
    println!("max efficiency             {:.4}", coupled.efficiency);
    println!(
        "energy balance residual    {:.2e} (relative to the power flow)",
        coupled.energy_balance_residual
    );
    println!("wall time                  {:.3} s", coupled.wall_time_s);
}

/// The ball model of a ball scene: `dynamic.json`, `curve.csv`, the speed–thrust chart.
fn run_ball(args: &StageArgs, scene: &Scene) -> anyhow::Result<()> {
    let stage = run_ball_stage(scene)?;
    let staged = StagedDir::create(
        &args.out.join(&scene.name).join("dynamic"),
        ResultKind::Dynamic,
    )?;
    write_ball_stage_files(&scene.name, &stage, staged.path())?;
    let folder = staged.commit()?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&stage.json())?);
        return Ok(());
    }
    for w in &stage.warnings {
        eprintln!("warning: {w}");
    }
    let r = &stage.result;
    let hertz = &r.static_contact.hertz;
    println!(
        "ball slider of {}: {} diameter, preload {} N",
        scene.name,
        sawdrive::units::format_quantity(
            stage.scene.ball.diameter_m,
            sawdrive::units::Dimension::Length
        ),
        stage.scene.preload_n
    );
    println!(
        "Hertz contact radius       {:.4e} m (static approach {:.2} wave amplitudes)",
        hertz.contact_radius_m, r.static_contact.approach_over_amplitude
    );
    println!(
        "stall thrust               {:.4e} N (friction limit μP = {:.4e} N)",
        r.stall_thrust_n, r.friction_limit_n
    );
    println!(
        "no-load speed              {:.4} m/s (crest speed A_t ω = {:.3} m/s)",
        r.no_load_speed_m_per_s, r.crest_speed_m_per_s
    );
    println!("max efficiency             {:.4}", r.max_efficiency);
    println!("wave                       {}", stage.wave.reason);
    if let Some(d) = &stage.drive {
        println!(
            "electrical input {:.4} W, overall efficiency {:.3e}",
            d.electrical_power_w, d.overall_efficiency
        );
    }
    println!("energy residual            {:.2e}", r.max_energy_residual);
    println!("wall time                  {:.3} s", stage.wall_time_s);
    println!("results in {}", folder.display());
    Ok(())
}
