//! Parameter sweeps over scene keys: grid files, points, resumable results.

mod file;

pub use file::{ChartSpec, SweepError, SweepFile, SweepPoint, Variant};
