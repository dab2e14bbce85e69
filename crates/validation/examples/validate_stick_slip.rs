//! Run the stick-slip validation study and write its charts and `report.json`.
//!
//! `cargo run -p validation --example validate_stick_slip --release [-- OUT_DIR] [--quick | --smoke]`
//! (default OUT_DIR: validation/stick-slip/figures, the committed figures).

use std::path::PathBuf;

use validation::stick_slip::{ValidationLevel, ValidationSetup, run_validation};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let level = if args.iter().any(|a| a == "--smoke") {
        ValidationLevel::Smoke
    } else if args.iter().any(|a| a == "--quick") {
        ValidationLevel::Quick
    } else {
        ValidationLevel::Full
    };
    let out = args
        .iter()
        .find(|a| !a.starts_with("--"))
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../../validation/stick-slip/figures"
            ))
        });
    let setup = ValidationSetup::paper_posts(level).expect("Johnson springs of the paper posts");
    match run_validation(&setup, &out) {
        Ok(report) => {
            println!(
                "stall thrust {:.6} N, no-load speed {:.6} m/s (closed form, {:.2e} s)",
                report.reference_stall_thrust_n,
                report.reference_no_load_speed_m_per_s,
                report.reference_wall_time_s
            );
            println!(
                "return-mapping observed order (stall, no-load): {:.2?}",
                report.return_mapping_order
            );
            for p in &report.work_precision {
                println!(
                    "{:>22} T/dt = {:>7} time {:.3e} s  stall err {:.2e}  v0 err {:.2e}",
                    p.scheme, p.steps_per_period, p.wall_time_s, p.stall_error, p.no_load_error
                );
            }
            let a = &report.agreement;
            println!(
                "transient vs period average: max speed difference {:.2e}; stall {:.4} vs {:.4} N; no-load {:.5} vs {:.5} m/s; transient solve {:.2} s",
                a.max_speed_difference,
                a.stall_thrust_n.0,
                a.stall_thrust_n.1,
                a.no_load_speed_m_per_s.0,
                a.no_load_speed_m_per_s.1,
                a.transient_wall_time_s
            );
            println!(
                "incommensurate 33x33 @ 121 um, 10 N: no-load {:.5} (period avg) vs {:.5} m/s (transient)",
                a.incommensurate_no_load_m_per_s.0, a.incommensurate_no_load_m_per_s.1
            );
            println!(
                "burst 20 periods: displacement {:.3e} m, peak speed {:.4} m/s",
                a.burst_displacement_m, a.burst_peak_speed_m_per_s
            );
            for map in &report.stability_maps {
                println!(
                    "stability map {}: limits dt/T {:?}",
                    map.scheme,
                    map.theoretical_limit_over_period
                        .iter()
                        .map(|l| format!("{l:.2e}"))
                        .collect::<Vec<_>>()
                );
                for (row, value) in map.cells.iter().zip(&map.values) {
                    println!("  {value:.1e}: {row:?}");
                }
            }
            for file in &report.files {
                println!("wrote {}", file.display());
            }
        }
        Err(e) => {
            eprintln!("validation failed: {e}");
            std::process::exit(1);
        }
    }
}
