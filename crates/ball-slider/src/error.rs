//! The crate's one error type: every variant names the field or the quantity at fault.

/// Result with [`BallError`].
pub type Result<T> = std::result::Result<T, BallError>;

/// What went wrong, and where.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BallError {
    /// An input outside its physical range (negative diameter, zero mass, μ ≤ 0, NaN, …).
    #[error("{field} = {value}: {requirement}")]
    InvalidParameter {
        /// The field, as the scene names it (e.g. `ball.diameter_m`).
        field: &'static str,
        /// The value given.
        value: f64,
        /// What the field must satisfy.
        requirement: &'static str,
    },
    /// A material constant refused by `contact-springs`.
    #[error("{field}: {source}")]
    Material {
        /// Which material (e.g. `ball.material`, `stator`).
        field: &'static str,
        /// The refusal.
        source: contact_springs::SpringError,
    },
    /// A wave feature this model does not represent.
    #[error("{field}: {reason}")]
    UnsupportedWave {
        /// The wave field (e.g. `wave.decay_length_m`).
        field: &'static str,
        /// Why it is refused.
        reason: &'static str,
    },
    /// A tangential load at or above the friction limit asked of a partial-slip formula.
    #[error(
        "tangential load {load_n} N is not below the friction limit μN = {limit_n} N: the contact slides (no partial-slip state)"
    )]
    TangentialLoadBeyondFriction {
        /// The tangential load asked for (N).
        load_n: f64,
        /// μN (N).
        limit_n: f64,
    },
    /// The contact grew beyond the spring bed laid for it.
    #[error(
        "contact half-width {contact_m} m exceeds the spring bed's extent {bed_m} m at t = {time_s} s: the ball pressed far deeper than its static approach plus the wave"
    )]
    ContactBeyondBed {
        /// Contact radius reached (m).
        contact_m: f64,
        /// Extent of the discretised bed (m).
        bed_m: f64,
        /// Time (s).
        time_s: f64,
    },
    /// The implicit step's fixed point did not converge: the step is too long for the
    /// ball–contact resonance.
    #[error(
        "implicit step at t = {time_s} s did not converge in {iterations} iterations (last change {change:e} of the scale); use more steps per period"
    )]
    StepDidNotConverge {
        /// Time of the step (s).
        time_s: f64,
        /// Iterations made.
        iterations: usize,
        /// Last relative change.
        change: f64,
    },
    /// The contact at imposed speed did not become periodic.
    #[error(
        "contact at imposed speed {speed_m_per_s} m/s not periodic after {periods} periods (state change {change:e})"
    )]
    NotPeriodic {
        /// Imposed speed (m/s).
        speed_m_per_s: f64,
        /// Periods integrated.
        periods: usize,
        /// Last change of the contact state between period starts (relative).
        change: f64,
    },
    /// No steady state found where one was required.
    #[error("{what}")]
    NoSteadyState {
        /// What failed, with the numbers.
        what: String,
    },
}

/// Refuse a non-finite or non-positive value, naming the field.
pub(crate) fn positive(field: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(BallError::InvalidParameter {
            field,
            value,
            requirement: "must be finite and > 0",
        })
    }
}

/// Refuse a non-finite or negative value, naming the field.
pub(crate) fn non_negative(field: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(BallError::InvalidParameter {
            field,
            value,
            requirement: "must be finite and ≥ 0",
        })
    }
}

/// Validate a material, naming which one.
pub(crate) fn material(field: &'static str, m: &contact_springs::Material) -> Result<()> {
    m.validate()
        .map_err(|source| BallError::Material { field, source })
}
