use std::path::PathBuf;

/// Why a chart could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ChartError {
    /// No series holds a point that can be drawn on the chart's axes.
    #[error("chart '{title}': no finite data to draw (log axes drop values ≤ 0)")]
    NoData {
        /// Title of the chart at fault.
        title: String,
    },
    /// A category map whose cell grid does not match its axes.
    #[error("category map '{title}': {what}")]
    BadGrid {
        /// Title of the map at fault.
        title: String,
        /// What does not fit.
        what: String,
    },
    /// Creating the folder of a chart failed.
    #[error("cannot create the chart folder {path}: {source}")]
    Io {
        /// Folder at fault.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// Writing a chart file (atomically) failed; names the verb and the file.
    #[error("chart file: {0}")]
    File(#[from] atomic_files::FileError),
    /// plotters failed while drawing.
    #[error("drawing chart '{title}' failed: {message}")]
    Draw {
        /// Title of the chart at fault.
        title: String,
        /// plotters' message.
        message: String,
    },
}
