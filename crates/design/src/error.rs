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
