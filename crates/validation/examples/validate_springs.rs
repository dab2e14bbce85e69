//! Runs the springs validation without the sawdrive CLI.
//!
//! ```sh
//! cargo run --release -p validation --example validate_springs -- [--json] [--smoke] \
//!     [--quarter-tangential] [--out DIR] [--quiet] [--from-json results.json]
//! ```
//! `--out DIR` writes results.json, cases.json and the charts there (the committed study uses
//! `validation/springs`). `--json` prints the cases array instead of the table. `--smoke` runs
//! the small pipeline check (coarse meshes; not for conclusions). `--from-json` reloads a
//! results.json instead of computing (to redraw charts and the table). Meshes are cached in
//! the cache folder (`gmsh_mesh::cache::meshes_dir`). Exit status 1 if a case fails acceptance.

use std::path::PathBuf;

use validation::{MeshSymmetry, SpringsOptions, report, validate_springs};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut options = SpringsOptions {
        progress: true,
        ..SpringsOptions::default()
    };
    let mut json = false;
    let mut out: Option<PathBuf> = None;
    let mut from_json: Option<PathBuf> = None;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--json" => json = true,
            "--smoke" => {
                options = SpringsOptions {
                    progress: options.progress,
                    ..SpringsOptions::smoke()
                }
            }
            "--quarter-tangential" => options.tangential_symmetry = MeshSymmetry::Quarter,
            "--quiet" => options.progress = false,
            "--from-json" => {
                from_json = Some(PathBuf::from(
                    args.next().ok_or("--from-json needs a results.json")?,
                ))
            }
            "--out" => out = Some(args.next().ok_or("--out needs a folder")?.into()),
            "--help" | "-h" => {
                println!(
                    "validate_springs [--json] [--smoke] [--quarter-tangential] [--out DIR] [--quiet] [--from-json results.json]"
                );
                return Ok(());
            }
            other => return Err(format!("unknown argument `{other}` (see --help)").into()),
        }
    }
    let validation = match &from_json {
        Some(path) => report::read_results(path)?,
        None => validate_springs(&options)?,
    };
    if let Some(dir) = &out {
        // A reloaded study only redraws its charts; its JSON files stay as computed.
        let json_files = if from_json.is_some() {
            Vec::new()
        } else {
            report::write_json(&validation, dir)?
        };
        for file in json_files
            .into_iter()
            .chain(report::write_charts(&validation, dir)?)
        {
            eprintln!("wrote {}", file.display());
        }
        // The case's figures are SVG (the chart writer draws a PNG copy too).
        validation::cases::drop_png_duplicates(dir)?;
    }
    if json {
        println!("{}", validation.cases_json()?);
    } else {
        println!("{validation}");
    }
    if !validation.all_pass() {
        std::process::exit(1);
    }
    Ok(())
}
