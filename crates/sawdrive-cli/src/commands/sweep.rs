//! `sawdrive sweep SWEEP.toml [--shard K/N | --merge]`.

use anyhow::bail;
use sawdrive::pipeline::RunControl;
use sawdrive::sweep::{
    Shard, ShardOutcome, SweepFile, SweepOutcome, merge_sweep, run_shard, run_sweep,
};

use crate::cli::SweepArgs;

pub fn run(args: &SweepArgs) -> anyhow::Result<()> {
    let sweep = SweepFile::load(&args.sweep)?;
    if args.merge {
        let outcome = merge_sweep(&sweep, &args.out)?;
        return report_merge(args, &sweep, &outcome);
    }
    let (outcome, failures) = match args.shard {
        Some(shard) => {
            let outcome = run_shard(&sweep, &args.out, args.jobs, shard)?;
            report_shard(args, &sweep, shard, &outcome)?;
            (outcome.points, outcome.failures)
        }
        None => {
            let outcome = run_sweep(&sweep, &args.out, args.jobs, &RunControl::none())?;
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
            (
                outcome.rows.len() + outcome.failures.len(),
                outcome.failures,
            )
        }
    };
    for (overrides, error) in &failures {
        eprintln!("point [{overrides}] failed: {error}");
    }
    if !failures.is_empty() {
        bail!(
            "{} of {} sweep points failed (completed points are kept; rerun to retry)",
            failures.len(),
            outcome
        );
    }
    Ok(())
}

fn report_merge(args: &SweepArgs, sweep: &SweepFile, outcome: &SweepOutcome) -> anyhow::Result<()> {
    if args.json {
        println!("{}", serde_json::to_string_pretty(&outcome.rows)?);
    } else {
        println!(
            "sweep {}: merged {} points, results in {}",
            sweep.name,
            outcome.rows.len(),
            outcome.folder.display()
        );
    }
    Ok(())
}

fn report_shard(
    args: &SweepArgs,
    sweep: &SweepFile,
    shard: Shard,
    outcome: &ShardOutcome,
) -> anyhow::Result<()> {
    if args.json {
        println!("{}", serde_json::to_string_pretty(&outcome.rows)?);
        return Ok(());
    }
    let merged = match outcome.missing {
        0 => format!(
            "every point saved: results merged in {}",
            outcome.folder.display()
        ),
        n => format!(
            "points of the sweep not saved yet: {n} (other shards'); the last shard merges, or run --merge"
        ),
    };
    println!(
        "sweep {} shard {shard}: {} points ({} resumed), {} FEM condensations; {merged}",
        sweep.name, outcome.points, outcome.resumed, outcome.condensations
    );
    Ok(())
}
