//! `sawdrive run`: the whole pipeline.

use sawdrive::pipeline::{RunOptions, run_pipeline};
use sawdrive::scene::load_scene;

use crate::cli::StageArgs;
use crate::progress::Spinner;

pub fn run(args: &StageArgs) -> anyhow::Result<()> {
    let scene = load_scene(args.input.scene.as_deref(), &args.input.overrides)?;
    let options = RunOptions {
        out_dir: args.out.clone(),
        cache_dir: (!args.no_cache).then(|| args.out.join(".cache")),
        write_files: true,
    };
    let spinner = Spinner::new(!args.json);
    let (summary, folder) = run_pipeline(&scene, &options, spinner.control())?;
    spinner.finish();
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
        return Ok(());
    }
    for w in &scene.warnings {
        eprintln!("warning: {}: {}", w.parameter, w.message);
    }
    let t = &summary.timings;
    println!(
        "{}: η = {:.4} ({}), N_eff = {:.0}",
        scene.name,
        summary.effective_contact_ratio,
        summary.effective_contact_ratio_source,
        summary.effective_post_count
    );
    println!("stall thrust   {:.4} N", summary.stall_thrust_n);
    println!("no-load speed  {:.4} m/s", summary.no_load_speed_m_per_s);
    println!(
        "efficiency     {:.4} (max along the curve)",
        summary.efficiency
    );
    println!(
        "model          {} ({})",
        summary.model, summary.model_reason
    );
    println!(
        "timings        static {:.2} s, dynamic {:.3} s, output {:.2} s, total {:.2} s",
        t.static_s, t.dynamic_s, t.output_s, t.total_s
    );
    println!("results in {}", folder.display());
    Ok(())
}
