//! `sawdrive sweep SWEEP.toml`.

use anyhow::bail;
use sawdrive::sweep::{SweepFile, run_sweep};

use crate::cli::SweepArgs;

pub fn run(args: &SweepArgs) -> anyhow::Result<()> {
    let sweep = SweepFile::load(&args.sweep)?;
    let outcome = run_sweep(&sweep, &args.out, args.jobs)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&outcome.rows)?);
    } else {
        println!(
            "sweep {}: {} points ({} resumed), results in {}",
            sweep.name,
            outcome.rows.len() + outcome.failures.len(),
            outcome.resumed,
            outcome.folder.display()
        );
    }
    for (overrides, error) in &outcome.failures {
        eprintln!("point [{overrides}] failed: {error}");
    }
    if !outcome.failures.is_empty() {
        bail!(
            "{} of {} sweep points failed (completed points are kept; rerun to retry)",
            outcome.failures.len(),
            outcome.failures.len() + outcome.rows.len()
        );
    }
    Ok(())
}
