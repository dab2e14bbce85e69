//! The crate's one error type; every variant names the key or constraint at fault.

/// Why a distribution, a statistic or an optimisation was refused or failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// An input is out of its range; `key` is the field as the user wrote it.
    #[error("{key}: {message}")]
    Invalid {
        /// The field at fault (e.g. `scatter.height_scatter`, `variables.post_diameter_m`).
        key: String,
        /// What is wrong and the accepted range.
        message: String,
    },
    /// No evaluated design satisfied every constraint.
    #[error(
        "infeasible: no evaluated design satisfies the constraints; violated at the least-violating design: {}",
        constraints.join(", ")
    )]
    Infeasible {
        /// The constraints violated at the least-violating design, by name.
        constraints: Vec<String>,
    },
    /// The model failed at a point.
    #[error("evaluation failed at {point}: {message}")]
    Evaluation {
        /// The design point, `name = value` pairs.
        point: String,
        /// The model's error.
        message: String,
    },
}

/// Shorthand.
pub type Result<T> = std::result::Result<T, DesignError>;

/// An [`DesignError::Invalid`] for `key`.
pub fn invalid(key: impl Into<String>, message: impl Into<String>) -> DesignError {
    DesignError::Invalid {
        key: key.into(),
        message: message.into(),
    }
}

/// Why a study (`uq`, `design`) or its input was refused or failed; each names the key, the
/// stage or the file at fault.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// An input of the study (a `[scatter]` key, a design-file key, an override, a count) is
    /// invalid; `key` is the field as the user wrote it.
    #[error("{key}: {message}")]
    Input {
        /// The field at fault (`scatter.height_scatter`, `variables.preload`, `--samples`).
        key: String,
        /// What is wrong and what is accepted.
        message: String,
    },
    /// An input without one key to blame (two keys that conflict, a file-level rule).
    #[error("{0}")]
    Conflict(String),
    /// A design file, with the error of its content.
    #[error("{}: {source}", path.display())]
    File {
        /// The design file.
        path: std::path::PathBuf,
        /// What is wrong in it.
        #[source]
        source: Box<StudyError>,
    },
    /// A study could not run as asked (`uq stage: …`, `design stage: …`).
    #[error("{stage} stage: {message}")]
    Study {
        /// `uq` or `design`.
        stage: &'static str,
        /// What is not possible and what to do.
        message: String,
    },
    /// One Monte Carlo sample's model failed; its drawn inputs let it be reproduced.
    #[error(
        "uq stage: sample {index} (seed {seed}, post-height seed {field_seed}; {drawn}): {source}"
    )]
    Sample {
        /// Sample index k.
        index: u64,
        /// The study's seed.
        seed: u64,
        /// The seed of the sample's post heights.
        field_seed: u64,
        /// The drawn inputs, `name = value` pairs.
        drawn: String,
        /// The model's error.
        #[source]
        source: crate::evaluator::ModelError,
    },
    /// The motor model (the evaluator: scene reading, static or dynamic stage) failed.
    #[error(transparent)]
    Model(crate::evaluator::ModelError),
    /// A statistic or the optimiser refused its input or found nothing feasible.
    #[error("design stage: {0}")]
    Design(#[from] DesignError),
    /// Reading an input file or writing results.
    #[error(transparent)]
    Io(#[from] atomic_files::FileError),
    /// A chart.
    #[error("chart: {0}")]
    Chart(#[from] charts::ChartError),
    /// JSON of a result or a saved sample.
    #[error("json: {0}")]
    Json(#[from] serde_json::Error),
}

impl StudyError {
    /// An [`StudyError::Input`] for `key`.
    pub fn input(key: impl Into<String>, message: impl std::fmt::Display) -> Self {
        Self::Input {
            key: key.into(),
            message: message.to_string(),
        }
    }
}
