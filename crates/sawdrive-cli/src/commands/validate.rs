//! `sawdrive validate <case> --level smoke|quick|full [--out DIR] [--json] [--summary [FILE]]`,
//! `sawdrive validate all --level …` and `sawdrive validate --list`: every validation study as
//! a case of the validation crate ([`validation::cases`]), its checks printed as a table or as
//! `{"checks": [...]}`; a failing check exits non-zero with one line naming it.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, bail};
use sawdrive::scene::load_scene;
use validation::cases::{self, CASES, CaseInfo, CaseOutcome, Level};
use validation::stick_slip::{ValidationSetup, run_validation};

use crate::cli::ValidateArgs;

/// Default output folder of a case: `out/validation/<case>` under the current folder.
pub const DEFAULT_OUT: &str = "out/validation";

pub fn run(args: &ValidateArgs) -> anyhow::Result<()> {
    if args.list {
        for c in CASES {
            let note = c.regenerate.map_or(String::new(), |r| {
                format!(" [checks not yet ported; today: {r}]")
            });
            println!("{:<17} {}{note}", c.name, c.description);
        }
        return Ok(());
    }
    let level = Level::parse(&args.level).context("level")?;
    let name = args.case.as_deref().unwrap_or("all");
    let all = name == "all";
    let selected: Vec<&CaseInfo> = if all {
        CASES.iter().collect()
    } else {
        vec![cases::case(name).with_context(|| {
            format!(
                "unknown validation case `{name}`; known: {}, all (sawdrive validate --list)",
                CASES.iter().map(|c| c.name).collect::<Vec<_>>().join(", ")
            )
        })?]
    };
    let mut outcomes = Vec::new();
    for info in selected {
        let out = case_out(args, info.name);
        let started = Instant::now();
        let mut outcome = run_case(info, level, &out, !args.json)?;
        outcome.wall_s = started.elapsed().as_secs_f64();
        cases::drop_png_duplicates(&out)
            .with_context(|| format!("removing PNG copies of SVG figures in {}", out.display()))?;
        if !outcome.checks.is_empty() {
            sawdrive::output::write_atomically(
                &out.join("results/checks.json"),
                cases::checks_json(std::slice::from_ref(&outcome)),
            )?;
        }
        if !args.json {
            print_outcome(&outcome, &out);
        }
        outcomes.push(outcome);
    }
    if let Some(path) = &args.summary {
        // The sections of the cases not run here stay as they were (each row names its
        // level and commit).
        let previous = std::fs::read_to_string(path).ok();
        let text = cases::update_summary(previous.as_deref(), &outcomes, &commit());
        sawdrive::output::write_atomically(path, text)?;
        if !args.json {
            println!("summary written to {}", path.display());
        }
    }
    if args.json {
        println!("{}", cases::checks_json(&outcomes));
    }
    let failed: Vec<_> = outcomes
        .iter()
        .flat_map(|o| &o.checks)
        .filter(|c| !c.pass)
        .collect();
    if let Some(first) = failed.first() {
        bail!(
            "validation check failed{}: {}",
            if failed.len() > 1 {
                format!(" ({} checks failed, first)", failed.len())
            } else {
                String::new()
            },
            first.line()
        );
    }
    Ok(())
}

/// The short commit of the current folder's git checkout, or `unknown`.
fn commit() -> String {
    std::process::Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

fn print_outcome(outcome: &CaseOutcome, out: &Path) {
    println!(
        "== {} ({} level, {:.1} s)",
        outcome.case,
        outcome.level.name(),
        outcome.wall_s
    );
    if let Some(reason) = &outcome.skipped {
        println!("   skipped: {reason}");
        return;
    }
    for c in &outcome.checks {
        println!("   {} {}", if c.pass { "ok  " } else { "FAIL" }, c.line());
    }
    println!("   files in {}", out.display());
}

/// Runs one case at `level`, writing its files into `out`.
fn run_case(
    info: &CaseInfo,
    level: Level,
    out: &Path,
    progress: bool,
) -> anyhow::Result<CaseOutcome> {
    let outcome = |checks| CaseOutcome {
        case: info.name.into(),
        level,
        checks,
        skipped: None,
        wall_s: 0.0,
    };
    match info.name {
        "springs" => {
            let (study, checks) = cases::springs::run(level, out, progress)?;
            if progress {
                eprintln!("{study}");
            }
            Ok(outcome(checks))
        }
        "stick-slip" => {
            let report = run_validation(&stick_slip_setup(level)?, &out.join("figures"))?;
            let results = out.join("results");
            std::fs::create_dir_all(&results)?;
            std::fs::rename(out.join("figures/report.json"), results.join("report.json"))?;
            Ok(outcome(cases::stick_slip::checks(&report, level)))
        }
        "design" => Ok(outcome(cases::design::run(level, out)?)),
        "static-contact" => Ok(outcome(cases::static_contact::run(level, out)?)),
        "whole-slider" => Ok(outcome(cases::whole_slider::run(level, out)?)),
        "coupled-dynamics" => Ok(outcome(cases::coupled_dynamics::run(
            level,
            out,
            &whole_row_point,
        )?)),
        "paper-figures" => Ok(outcome(cases::paper_figures::run(
            level,
            out,
            &pipeline_point,
        )?)),
        "fem-peers" => Ok(cases::fem_peers::run(level)),
        _ => Ok(cases::not_ported(info, level)),
    }
}

/// The pipeline of one scene as a sweep point (no files besides the FEM cache,
/// `out/validation/.cache` under the working folder, shared by every run from it).
fn pipeline_summary(sets: &[String]) -> Result<sawdrive::pipeline::RunSummary, String> {
    let scene = load_scene(None, sets).map_err(|e| format!("{e:#}"))?;
    let options = sawdrive::pipeline::RunOptions {
        out_dir: std::env::temp_dir().join(format!("sawdrive-validate-{}", std::process::id())),
        cache_dir: Some(Path::new(DEFAULT_OUT).join(".cache")),
        write_files: false,
    };
    let none = sawdrive::pipeline::RunControl::none();
    let (summary, folder) =
        sawdrive::pipeline::run_pipeline(&scene, &options, &none).map_err(|e| e.to_string())?;
    let _ = std::fs::remove_dir_all(folder);
    Ok(summary)
}

/// The coupled-dynamics case's runner: one whole-row scene, coupled and lumped figures.
fn whole_row_point(sets: &[String]) -> Result<cases::coupled_dynamics::WholeRowFigures, String> {
    let summary = pipeline_summary(sets)?;
    let coupled = summary
        .coupled
        .as_ref()
        .ok_or("the scene did not run the coupled model (model.dynamics = coupled)")?;
    Ok(cases::coupled_dynamics::WholeRowFigures {
        stall_thrust_n: summary.stall_thrust_n,
        no_load_speed_m_per_s: summary.no_load_speed_m_per_s,
        lumped_stall_thrust_n: coupled.lumped.stall_thrust_n,
        lumped_no_load_speed_m_per_s: coupled.lumped.no_load_speed_m_per_s,
        lumped_error_estimate: summary.lumped_error_estimate.unwrap_or(f64::NAN),
        energy_balance_residual: coupled.energy_balance_residual,
    })
}

/// The paper-figures case's runner: the default scene with `sets` through the whole pipeline.
fn pipeline_point(sets: &[String]) -> Result<cases::paper_figures::PointFigures, String> {
    let summary = pipeline_summary(sets)?;
    Ok(cases::paper_figures::PointFigures {
        stall_thrust_n: summary.stall_thrust_n,
        no_load_speed_m_per_s: summary.no_load_speed_m_per_s,
        effective_contact_ratio: summary.effective_contact_ratio,
    })
}

/// The stick-slip study's inputs from the paper scene: the springs of 20 µm and 50 µm posts.
fn stick_slip_setup(level: Level) -> anyhow::Result<ValidationSetup> {
    let paper = load_scene(None, &[])?;
    let springs_at = |diameter: &str| -> anyhow::Result<_> {
        let scene = load_scene(
            None,
            &[
                format!("posts.diameter={diameter}"),
                "posts.count=50x50".into(),
            ],
        )?;
        Ok(sawdrive::pipeline::scene_springs(&scene)?)
    };
    let (s20, s50) = (springs_at("20 um")?, springs_at("50 um")?);
    Ok(ValidationSetup {
        k_n_n_per_m: s20.k_n_n_per_m,
        k_t_n_per_m: s20.k_t_n_per_m,
        post_mass_kg: paper.motor.post_mass_kg(),
        k_n_50um_n_per_m: s50.k_n_n_per_m,
        k_t_50um_n_per_m: s50.k_t_n_per_m,
        level: cases::stick_slip::study_level(level),
    })
}

/// The folder a case writes to: `--out` itself for one case, `--out`/CASE for `all`, else
/// [`DEFAULT_OUT`]/CASE.
pub fn case_out(args: &ValidateArgs, case: &str) -> PathBuf {
    match (&args.out, args.case.as_deref()) {
        (Some(dir), Some("all")) => dir.join(case),
        (Some(dir), _) => dir.clone(),
        (None, _) => Path::new(DEFAULT_OUT).join(case),
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use clap::Parser;

    use super::case_out;
    use crate::cli::{Cli, Command};

    fn args(line: &[&str]) -> crate::cli::ValidateArgs {
        let cli = Cli::try_parse_from(["sawdrive", "validate"].iter().chain(line))
            .expect("valid command line");
        match cli.command {
            Command::Validate(a) => a,
            other => panic!("parsed as {other:?}"),
        }
    }

    #[test]
    fn a_case_writes_under_out_relative_to_the_working_folder_by_default() {
        assert_eq!(
            case_out(&args(&["stick-slip"]), "stick-slip"),
            Path::new("out/validation/stick-slip")
        );
        assert_eq!(
            case_out(&args(&["stick-slip", "--out", "elsewhere"]), "stick-slip"),
            Path::new("elsewhere")
        );
        assert_eq!(
            case_out(&args(&["all", "--out", "elsewhere"]), "springs"),
            Path::new("elsewhere/springs")
        );
    }

    #[test]
    fn level_defaults_to_full_and_summary_to_the_committed_table() {
        let a = args(&["springs"]);
        assert_eq!(a.level, "full");
        assert_eq!(a.summary, None);
        let a = args(&["all", "--level", "smoke", "--summary"]);
        assert_eq!(
            a.summary.as_deref(),
            Some(Path::new("validation/SUMMARY.md"))
        );
        assert!(args(&["--list"]).list);
    }
}
