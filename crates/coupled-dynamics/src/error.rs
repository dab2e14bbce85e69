//! Errors of the coupled model: each names the field or the solve at fault.

/// Everything that can go wrong in `coupled-dynamics`.
#[derive(Debug, thiserror::Error)]
pub enum CoupledError {
    /// A scene field out of range.
    #[error("invalid {parameter} = {value}: {requirement}")]
    InvalidParameter {
        /// Field name with unit suffix.
        parameter: &'static str,
        /// The value given.
        value: f64,
        /// What it must satisfy.
        requirement: String,
    },
    /// Sizes of the scene's vectors and matrices disagree.
    #[error("{what} has size {found}, expected {expected} (one per post)")]
    DimensionMismatch {
        /// The field.
        what: &'static str,
        /// Expected size.
        expected: usize,
        /// Size found.
        found: usize,
    },
    /// A compliance matrix is not symmetric positive definite.
    #[error("{what} is not symmetric positive definite")]
    NotPositiveDefinite {
        /// The field.
        what: &'static str,
    },
    /// A contact solve did not converge.
    #[error(
        "{what} did not converge after {iterations} iterations (residual {residual:.3e} > tolerance {tolerance:.1e}) {context}"
    )]
    NotConverged {
        /// Which solve.
        what: &'static str,
        /// Iterations done.
        iterations: usize,
        /// Last residual (scaled).
        residual: f64,
        /// Tolerance.
        tolerance: f64,
        /// Where (speed, step).
        context: String,
    },
    /// The normal contact problem (static-contact's solver).
    #[error("normal contact: {0}")]
    Static(#[from] static_contact::ContactError),
    /// The whole slider's static contact or compliance operator (slider-contact).
    #[error("whole slider: {0}")]
    Slider(#[from] slider_contact::SliderError),
    /// The lumped model used for η_dyn.
    #[error("lumped model: {0}")]
    Lumped(#[from] stick_slip::StickSlipError),
}

/// Result alias.
pub type Result<T> = std::result::Result<T, CoupledError>;
