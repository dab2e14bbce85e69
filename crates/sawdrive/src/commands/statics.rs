//! `sawdrive static`: post forces and η.

use sawdrive::output::StagedDir;
use sawdrive::pipeline::{run_static, write_static_files};
use sawdrive::scene::load_scene;

use crate::cli::StageArgs;

pub fn run(args: &StageArgs) -> anyhow::Result<()> {
    let scene = load_scene(args.input.scene.as_deref(), &args.input.overrides)?;
    let cache = (!args.no_cache).then(|| args.out.join(".cache"));
    let outcome = run_static(&scene, cache.as_deref(), true)?;
    let staged = StagedDir::create(&args.out.join(&scene.name).join("static"))?;
    write_static_files(&outcome, staged.path())?;
    let folder = staged.commit()?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&outcome.report_json)?);
        return Ok(());
    }
    let r = &outcome.report_json;
    let number = |key: &str| {
        r[key]
            .as_f64()
            .map_or("n/a".to_owned(), |v| format!("{v:.4}"))
    };
    println!(
        "static contact of {} ({} posts in the strip of {})",
        scene.name, r["posts_in_strip"], r["posts_total"]
    );
    println!(
        "effective contact ratio η   {}",
        number("effective_contact_ratio")
    );
    if let Some(note) = r["effective_contact_ratio_note"].as_str() {
        println!("  note: {note}");
    }
    println!(
        "η at full contact          {}  (the high-preload limit)",
        number("eta_full_contact")
    );
    println!("load sharing               {}", number("load_sharing"));
    println!("contact fraction           {}", number("contact_fraction"));
    println!(
        "complementarity residual   {:.2e}",
        r["complementarity_residual"].as_f64().unwrap_or(f64::NAN)
    );
    println!("active-set iterations      {}", r["iterations"]);
    println!(
        "wall time                  {:.2} s{}",
        r["timings"]["wall_time_s"].as_f64().unwrap_or(0.0),
        if outcome.cached { " (cached)" } else { "" }
    );
    println!("results in {}", folder.display());
    Ok(())
}
