//! Parameter sweeps over scene keys: grid files, points, resumable parallel runs, one CSV and
//! charts of all results.

mod file;
mod run;

pub use file::{ChartSpec, SweepError, SweepFile, SweepPoint, Variant};
pub use run::{NUMERIC_COLUMNS, PointRow, SweepOutcome, SweepRunError, results_csv, run_sweep};
