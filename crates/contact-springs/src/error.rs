/// Invalid input to a material or spring formula.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpringError {
    /// A parameter outside its physical range.
    #[error("{parameter} = {value}: {accepted}")]
    OutOfRange {
        /// Name of the parameter, with its unit (e.g. `shear_modulus_pa`).
        parameter: &'static str,
        /// The value given.
        value: f64,
        /// The accepted range, in words.
        accepted: &'static str,
    },
}

/// Check that `value` is finite and strictly positive.
pub(crate) fn positive(parameter: &'static str, value: f64) -> Result<f64, SpringError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(SpringError::OutOfRange {
            parameter,
            value,
            accepted: "must be finite and > 0",
        })
    }
}

/// Check that a Poisson ratio lies in the open interval (−1, 1/2) of stable isotropic solids.
pub(crate) fn poisson(value: f64) -> Result<f64, SpringError> {
    if value.is_finite() && value > -1.0 && value < 0.5 {
        Ok(value)
    } else {
        Err(SpringError::OutOfRange {
            parameter: "poisson_ratio",
            value,
            accepted: "must lie in (-1, 0.5); 0.5 itself is incompressible and not supported",
        })
    }
}
