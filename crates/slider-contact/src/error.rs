//! The crate's error type: every variant names the input field, file or iteration at fault.

/// Errors of the whole-slider contact model.
#[derive(Debug, thiserror::Error)]
pub enum SliderError {
    /// A parameter is out of its valid range (the field is named with its unit suffix).
    #[error("invalid parameter `{field}` = {value}: {reason}")]
    InvalidParameter {
        /// Field name (with its unit suffix), e.g. `height_scatter_m`.
        field: &'static str,
        /// The value given.
        value: f64,
        /// What is wrong.
        reason: String,
    },
    /// A measured post-height map could not be read or does not fit the lattice.
    #[error("posts.height_map {file}: {detail}")]
    HeightMap {
        /// The CSV file.
        file: String,
        /// What is wrong, with the line number where there is one.
        detail: String,
    },
    /// The constrained conjugate-gradient iteration did not converge.
    #[error(
        "constrained conjugate gradient did not converge after {iterations} iterations \
         (scaled complementarity residual {residual:.3e} > tolerance {tolerance:.1e}, \
         {active} of {posts} posts in contact){context}"
    )]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// Last scaled residual.
        residual: f64,
        /// Tolerance asked.
        tolerance: f64,
        /// Posts in contact at the last iterate.
        active: usize,
        /// Number of posts.
        posts: usize,
        /// Where (preload, phase), empty if unknown.
        context: String,
    },
    /// The strip FEM used to calibrate the near field failed or does not fit.
    #[error("near-field calibration from the strip FEM: {0}")]
    Strip(#[from] static_contact::ContactError),
}

/// Result alias of the crate.
pub type Result<T> = std::result::Result<T, SliderError>;

pub(crate) fn invalid(field: &'static str, value: f64, reason: impl Into<String>) -> SliderError {
    SliderError::InvalidParameter {
        field,
        value,
        reason: reason.into(),
    }
}
