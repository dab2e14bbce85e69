//! Parameter sweeps over scene keys: grid files, points, resumable parallel runs, one CSV and
//! charts of all results; shards of a sweep on a cluster and their merge.

mod cancel;
mod error;
mod file;
mod locks;
mod run;
mod shard;

pub use cancel::Cancel;
pub use error::{MAX_JOBS, MAX_LISTED_POINTS, NUMERIC_COLUMNS, SweepRunError};
pub use file::{ChartSpec, MAX_SWEEP_POINTS, SweepError, SweepFile, SweepPoint, Variant};
pub use run::{PointRow, SweepOutcome, results_csv, run_sweep};
pub use shard::{Shard, ShardOutcome, merge_sweep, run_shard};
