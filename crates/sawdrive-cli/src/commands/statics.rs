//! `sawdrive static`: post forces and η.

use std::io::Write;

use sawdrive::output::{ResultKind, StagedDir};
use sawdrive::pipeline::{
    RunControl, StaticDetails, StaticOutcome, run_static, scene_springs, write_static_files,
};
use sawdrive::scene::load_scene;

use crate::cli::StageArgs;

/// A number with four decimals, or `n/a`.
fn number(value: Option<f64>) -> String {
    value.map_or("n/a".to_owned(), |v| format!("{v:.4}"))
}

pub fn run(args: &StageArgs) -> anyhow::Result<()> {
    let scene = load_scene(args.input.scene.as_deref(), &args.input.overrides)?;
    let cache = (!args.no_cache).then(|| args.out.join(".cache"));
    let springs = scene_springs(&scene)?;
    let outcome = run_static(
        &scene,
        &springs,
        cache.as_deref(),
        true,
        &RunControl::none(),
    )?;
    let staged = StagedDir::create(
        &args.out.join(&scene.name).join("static"),
        ResultKind::Static,
    )?;
    write_static_files(&outcome, staged.path())?;
    let folder = staged.commit()?;
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&outcome.report)?)?;
        return Ok(());
    }
    print_summary(&mut out, &scene.name, &outcome)?;
    writeln!(out, "results in {}", folder.display())?;
    Ok(())
}

/// The table `sawdrive static` prints: the model and why, η and the contact figures, the cost.
fn print_summary(
    out: &mut impl Write,
    scene_name: &str,
    outcome: &StaticOutcome,
) -> std::io::Result<()> {
    let r = &outcome.report;
    match &r.details {
        StaticDetails::Strip(strip) => writeln!(
            out,
            "static contact of {}, strip model ({} posts in the strip of {})",
            scene_name, strip.posts_in_strip, strip.posts_total
        )?,
        StaticDetails::Slider(stage) => writeln!(
            out,
            "static contact of {}, whole-slider model ({} × {} posts, {} back)",
            scene_name,
            stage.report.posts_x,
            stage.report.posts_y,
            stage.report.mechanism.name()
        )?,
    }
    writeln!(out, "  model: {}", r.model_reason)?;
    if let StaticDetails::Strip(strip) = &r.details {
        let fem = &strip.fem;
        let (solver, reason) = (fem.slider.solver.name(), &fem.slider_solver_reason);
        writeln!(out, "  FEM solver: {solver} ({reason})")?;
    }
    writeln!(
        out,
        "effective contact ratio η   {}",
        number(r.effective_contact_ratio)
    )?;
    if let Some(note) = &r.effective_contact_ratio_note {
        writeln!(out, "  note: {note}")?;
    }
    if let StaticDetails::Strip(strip) = &r.details {
        writeln!(
            out,
            "η at full contact          {}  (the high-preload limit)",
            number(strip.eta_full_contact)
        )?;
    }
    writeln!(
        out,
        "load sharing               {}",
        number(Some(r.load_sharing))
    )?;
    writeln!(
        out,
        "contact fraction           {}",
        number(Some(r.contact_fraction))
    )?;
    writeln!(
        out,
        "complementarity residual   {:.2e}",
        r.complementarity_residual
    )?;
    writeln!(out, "solver iterations          {}", r.iterations)?;
    writeln!(
        out,
        "wall time                  {:.2} s{}",
        r.wall_time_s,
        if outcome.cached { " (cached)" } else { "" }
    )?;
    if outcome.cell_fem_s > 0.0 {
        writeln!(
            out,
            "one-off cell FEM           {:.2} s  (near field, now cached)",
            outcome.cell_fem_s
        )?;
    }
    Ok(())
}
