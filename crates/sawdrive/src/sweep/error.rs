//! The sweep's shared terms, below the run, the shards and the locks that use them: why a
//! sweep could not run ([`SweepRunError`]), the result columns a chart may use, the bound on
//! worker threads and how a list of missing points is named.

use std::path::PathBuf;

/// Numeric result columns a chart may use.
pub const NUMERIC_COLUMNS: [&str; 11] = [
    "preload_n",
    "post_count",
    "post_diameter_m",
    "mu_kinetic",
    "normal_amplitude_m",
    "effective_contact_ratio",
    "effective_post_count",
    "stall_thrust_n",
    "no_load_speed_m_per_s",
    "efficiency",
    "stick_fraction",
];

/// Most worker threads a sweep starts (`--jobs`). Every point is CPU-bound, so threads beyond the
/// cores only cost memory (a stack and a solver workspace each); the bound turns a typo such as
/// `--jobs 100000` into an error instead of a hundred thousand threads. Unit: threads.
pub const MAX_JOBS: usize = 256;

/// Most missing points the merge error names one by one (the rest are counted), to keep it one
/// readable line. Unit: points.
pub const MAX_LISTED_POINTS: usize = 20;

/// Why a sweep could not run (individual point failures are reported in [`super::SweepOutcome`]).
#[derive(Debug, thiserror::Error)]
pub enum SweepRunError {
    /// The sweep file.
    #[error(transparent)]
    File(#[from] super::file::SweepError),
    /// A chart names a column that does not exist.
    #[error("chart {which}: unknown column \"{column}\"; columns: {}", NUMERIC_COLUMNS.join(", "))]
    UnknownColumn {
        /// Which chart (1-based).
        which: usize,
        /// The name given.
        column: String,
    },
    /// The first point's scene does not load: every point would fail.
    #[error("sweep point {overrides}: {source}")]
    Scene {
        /// The overrides of the point.
        overrides: String,
        /// The scene error.
        source: crate::scene::SceneError,
    },
    /// Writing results.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    /// Charts.
    #[error(transparent)]
    Chart(#[from] charts::ChartError),
    /// More worker threads asked for than [`MAX_JOBS`], or none.
    #[error(
        "--jobs {jobs}: must be between 1 and {MAX_JOBS} worker threads (this machine has {cores} core{})",
        if *cores == 1 { "" } else { "s" }
    )]
    Jobs {
        /// Jobs asked for.
        jobs: usize,
        /// Cores available.
        cores: usize,
    },
    /// `--shard K/N` with K outside 1..=N, or more shards than points.
    #[error("--shard {shard}: {message}")]
    Shard {
        /// The shard as given (`K/N`).
        shard: String,
        /// What is wrong, and how the points are split.
        message: String,
    },
    /// `--merge` while points of the sweep are not saved yet.
    #[error(
        "sweep {sweep}: {} of {total} points not saved yet in {}: {}; rerun the shards that own them (shard K of N runs points K, K+N, K+2N, …), then --merge",
        missing.len(), folder.display(), point_list(missing)
    )]
    MissingPoints {
        /// Sweep name.
        sweep: String,
        /// Folder of the saved points.
        folder: PathBuf,
        /// Missing points: number (1-based, sweep order) and overrides.
        missing: Vec<(usize, String)>,
        /// Points in the sweep.
        total: usize,
    },
    /// A lock file of the shared FEM cache could not be created or locked.
    #[error(
        "cannot lock {}: {source}{}",
        path.display(),
        lock_hint(source)
    )]
    Lock {
        /// The lock file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// The sweep was stopped ([`crate::pipeline::RunControl`]) before every point ran: the points saved so far are
    /// kept (a rerun resumes them); `results.csv` and the charts are not written.
    #[error(
        "sweep {sweep}: cancelled with {saved} of {total} points saved in {}; rerun to resume",
        folder.display()
    )]
    Cancelled {
        /// Sweep name.
        sweep: String,
        /// Folder of the saved points.
        folder: PathBuf,
        /// Points saved (this run's and earlier runs').
        saved: usize,
        /// Points in the sweep.
        total: usize,
    },
    /// Thread pool.
    #[error("cannot start {jobs} worker threads: {message}")]
    Pool {
        /// Jobs asked for.
        jobs: usize,
        /// The error.
        message: String,
    },
}

/// The file-system hint of a lock error: only where the file system refused locking itself
/// (no lock support), not for a lock path that is a folder or unwritable.
fn lock_hint(source: &std::io::Error) -> &'static str {
    /// ENOLCK: no locks available (Linux).
    const ENOLCK: i32 = 37;
    let unsupported =
        source.kind() == std::io::ErrorKind::Unsupported || source.raw_os_error() == Some(ENOLCK);
    if unsupported {
        " (shards sharing OUT/.cache need a file system with file locks, e.g. NFSv4, or Lustre mounted with -o flock)"
    } else {
        ""
    }
}

/// `#2 [preload=0.4 N], #5 [...]`, at most [`MAX_LISTED_POINTS`] named, the rest counted.
pub(super) fn point_list(points: &[(usize, String)]) -> String {
    let mut parts: Vec<String> = points
        .iter()
        .take(MAX_LISTED_POINTS)
        .map(|(n, overrides)| format!("#{n} [{overrides}]"))
        .collect();
    if points.len() > MAX_LISTED_POINTS {
        parts.push(format!("and {} more", points.len() - MAX_LISTED_POINTS));
    }
    parts.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_missing_lists_are_cut_and_counted() {
        let points: Vec<(usize, String)> = (1..=25).map(|n| (n, format!("p={n}"))).collect();
        let text = point_list(&points);
        assert!(text.starts_with("#1 [p=1], #2 [p=2]"), "{text}");
        assert!(text.ends_with("#20 [p=20], and 5 more"), "{text}");
    }
}
