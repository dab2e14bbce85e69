//! `sawdrive validate …`: validation studies.

use sawdrive::scene::load_scene;
use validation::stick_slip::{ValidationLevel, ValidationSetup, run_validation};

use crate::cli::{ValidateSpringsArgs, ValidateStickSlipArgs};

pub fn stick_slip(args: &ValidateStickSlipArgs) -> anyhow::Result<()> {
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
    let level = match args.level.as_str() {
        "smoke" => ValidationLevel::Smoke,
        "quick" => ValidationLevel::Quick,
        _ => ValidationLevel::Full,
    };
    let setup = ValidationSetup {
        k_n_n_per_m: s20.k_n_n_per_m,
        k_t_n_per_m: s20.k_t_n_per_m,
        post_mass_kg: paper.motor.post_mass_kg(),
        k_n_50um_n_per_m: s50.k_n_n_per_m,
        k_t_50um_n_per_m: s50.k_t_n_per_m,
        level,
    };
    let report = run_validation(&setup, &args.out)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!(
            "stick-slip validation ({}) written to {}",
            args.level,
            args.out.display()
        );
        println!(
            "reference stall thrust {:.6} N, no-load speed {:.6} m/s",
            report.reference_stall_thrust_n, report.reference_no_load_speed_m_per_s
        );
    }
    Ok(())
}

pub fn springs(args: &ValidateSpringsArgs) -> anyhow::Result<()> {
    let mut options = if args.smoke {
        validation::SpringsOptions::smoke()
    } else {
        validation::SpringsOptions::default()
    };
    options.progress = !args.json;
    let result = validation::validate_springs(&options)?;
    validation::report::write_charts(&result, &args.out)?;
    sawdrive::output::write_atomically(&args.out.join("cases.json"), result.cases_json()?)?;
    if args.json {
        println!("{}", result.cases_json()?);
    } else {
        println!("{result}");
        println!("charts and cases.json in {}", args.out.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use clap::Parser;

    use crate::cli::{Cli, Command, ValidateCommand};

    /// The `--out` folder `sawdrive validate stick-slip ARGS` would write to.
    fn stick_slip_out(args: &[&str]) -> std::path::PathBuf {
        let cli = Cli::try_parse_from(["sawdrive", "validate", "stick-slip"].iter().chain(args))
            .expect("valid command line");
        match cli.command {
            Command::Validate(ValidateCommand::StickSlip(a)) => a.out,
            other => panic!("parsed as {other:?}"),
        }
    }

    #[test]
    fn stick_slip_study_writes_under_out_relative_to_the_working_folder_by_default() {
        assert_eq!(
            stick_slip_out(&[]),
            Path::new("out/validation/stick-slip"),
            "default output folder of the stick-slip study"
        );
        assert_eq!(
            stick_slip_out(&["--out", "elsewhere"]),
            Path::new("elsewhere"),
            "--out folder of the stick-slip study"
        );
    }
}
