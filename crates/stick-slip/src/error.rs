//! The crate's error type and the non-fatal warnings attached to results.

use std::fmt;
use std::path::PathBuf;

use serde::Serialize;

/// Everything that can go wrong in `stick-slip`. Each variant names the parameter, integrator
/// or quantity at fault (the scene's field path, e.g. `slider.preload_n`).
#[derive(Debug, thiserror::Error)]
pub enum StickSlipError {
    /// A scalar input outside its valid range (negative friction, zero preload, ...).
    #[error("stick-slip input `{parameter}` = {value:e} is invalid: {requirement}")]
    InvalidParameter {
        /// Field path of the parameter, e.g. `contact.mu_static`.
        parameter: &'static str,
        /// The offending value.
        value: f64,
        /// What the value must satisfy.
        requirement: String,
    },
    /// A wave the stator material cannot carry (too fast, or strained beyond linear elasticity).
    #[error("stick-slip input `{parameter}` = {value:e} is unphysical: {reason} (limit {limit:e})")]
    UnphysicalWave {
        /// Field path of the parameter, e.g. `wave.phase_velocity_m_per_s`.
        parameter: &'static str,
        /// The offending value.
        value: f64,
        /// The bound it exceeds.
        limit: f64,
        /// Why the bound exists.
        reason: &'static str,
    },
    /// A post layout that cannot be built (no posts, mismatched gap list, ...).
    #[error("stick-slip input `slider.layout`: {detail}")]
    InvalidLayout {
        /// What is wrong, naming the entry at fault.
        detail: String,
    },
    /// A step size beyond the integrator's stability limit (refused unless the scene's
    /// stability policy asks for a warning instead).
    #[error(
        "integrator `{integrator}`: `{parameter}` = {step_s:e} s exceeds the stability limit {limit_s:e} s ({criterion})"
    )]
    StepAboveStabilityLimit {
        /// Integrator name, e.g. `post-mass`.
        integrator: &'static str,
        /// Field path of the step, e.g. `integrator.dt_s`.
        parameter: &'static str,
        /// Requested step.
        step_s: f64,
        /// Largest stable step.
        limit_s: f64,
        /// The stability criterion, with the mode that sets it.
        criterion: String,
    },
    /// An integrator that needs a post mass was chosen without `contact.post_mass_kg`.
    #[error(
        "integrator `{integrator}` needs `contact.post_mass_kg` (posts with their own mass), which is not set"
    )]
    MissingPostMass {
        /// Integrator name.
        integrator: &'static str,
    },
    /// The integration produced a non-finite or runaway state.
    #[error("integrator `{integrator}` diverged at t = {time_s:e} s: {quantity} = {value:e}")]
    Diverged {
        /// Integrator name.
        integrator: &'static str,
        /// Simulated time of the failure.
        time_s: f64,
        /// The quantity that blew up.
        quantity: &'static str,
        /// Its value.
        value: f64,
    },
    /// An iteration (root finding, periodic steady state) ran out of iterations.
    #[error(
        "{model}: {what} did not converge after {iterations} iterations (last residual {residual:e})"
    )]
    NotConverged {
        /// Model or solver name.
        model: &'static str,
        /// What was iterated.
        what: &'static str,
        /// Iterations spent.
        iterations: usize,
        /// Last residual or change.
        residual: f64,
    },
    /// The requested model cannot represent the scene (e.g. periodic-average with a burst).
    #[error("model `{model}` cannot represent this scene: {reason}")]
    ModelNotApplicable {
        /// Model name.
        model: &'static str,
        /// The scene feature it cannot represent.
        reason: String,
    },
    /// A run whose estimated memory exceeds the limit (checked before allocating).
    #[error(
        "the run would hold ≈ {estimate_bytes:.3e} bytes, above the limit of {limit_bytes:.3e} bytes (`options.max_memory_bytes`); the largest part is set by `{parameter}`: reduce it"
    )]
    MemoryLimit {
        /// The option that sets the largest part of the estimate.
        parameter: &'static str,
        /// Estimated memory (bytes).
        estimate_bytes: f64,
        /// The limit (bytes).
        limit_bytes: f64,
    },
    /// A run whose estimated work exceeds the limit (checked before integrating).
    #[error(
        "integrator `{integrator}`: estimated cost {estimate_post_steps:.3e} post-steps ({detail}) exceeds the limit {limit_post_steps:.1e} post-steps (`options.max_post_steps`, minutes of run time): use a larger time step, fewer periods, or the return-mapping / event-driven integrator"
    )]
    CostLimit {
        /// Integrator name.
        integrator: &'static str,
        /// Estimated post-steps.
        estimate_post_steps: f64,
        /// The limit.
        limit_post_steps: f64,
        /// The factors of the estimate.
        detail: String,
    },
    /// The caller asked the run to stop (its [`crate::RunControl`]) before `before`.
    #[error("cancelled before {before}")]
    Cancelled {
        /// The step that did not start, e.g. `curve point 3 of 12`.
        before: String,
    },
    /// Writing an output file failed.
    #[error("cannot write {path}: {source}")]
    Io {
        /// File at fault.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// Writing a chart failed.
    #[cfg(feature = "charts")]
    #[error("chart {path}: {source}")]
    Chart {
        /// Chart stem at fault.
        path: PathBuf,
        /// Underlying error.
        source: charts::ChartError,
    },
}

/// A non-fatal finding about the input or the run (accuracy limit approached, unphysical but
/// allowed setting, steady state not reached, ...). Serialised as `{parameter, message}`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Warning {
    /// Field path or topic the warning is about.
    pub parameter: String,
    /// What was found and what the limit is.
    pub message: String,
}

impl Warning {
    /// A warning about `parameter`.
    pub fn new(parameter: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            parameter: parameter.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.parameter, self.message)
    }
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, StickSlipError>;

/// Check that `value` is finite and strictly positive.
pub(crate) fn require_positive(parameter: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(StickSlipError::InvalidParameter {
            parameter,
            value,
            requirement: "must be finite and > 0".into(),
        })
    }
}

/// Check that `value` is finite and ≥ 0.
pub(crate) fn require_non_negative(parameter: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(StickSlipError::InvalidParameter {
            parameter,
            value,
            requirement: "must be finite and ≥ 0".into(),
        })
    }
}

/// Check that `value` is finite.
pub(crate) fn require_finite(parameter: &'static str, value: f64) -> Result<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(StickSlipError::InvalidParameter {
            parameter,
            value,
            requirement: "must be finite".into(),
        })
    }
}

/// `Err(Cancelled)` naming the step `before` if the caller asked to stop. A run asks before
/// each long step (each point of the speed–thrust curve, each transient run); once the stop
/// request answers yes it ends with
/// [`StickSlipError::Cancelled`](crate::StickSlipError::Cancelled) and returns nothing.
pub(crate) fn stop_check(
    control: &run_control::RunControl,
    before: impl FnOnce() -> String,
) -> Result<()> {
    match control.should_stop() {
        true => Err(crate::StickSlipError::Cancelled { before: before() }),
        false => Ok(()),
    }
}
