//! Richardson extrapolation of a mesh sequence with an error estimate.
//!
//! Model: k(h) = k∞ + C h^p + (higher order), with h the mesh parameter (here the element size
//! at the punch edge) and refinement ratio r = h_coarse / h_fine between successive levels.
//! For the rigid punch the leading error comes from the edge singularity (stress ∝ d^(−1/2)): an
//! element layer of size h_e around the edge carries an energy error ∝ h_e, whatever the element
//! order, so p = 1 (checked by the observed order). With the levels h₀ > h₁ > h₂:
//!
//! - observed order p_obs = ln((k₀ − k₁)/(k₁ − k₂)) / ln r;
//! - first-order extrapolations of successive pairs: k∞(i, i+1) = k_{i+1} + (k_{i+1} − k_i)/(r − 1);
//! - the reported value is the finest one, k∞(1, 2);
//! - its error estimate is |k∞(1, 2) − k∞(0, 1)|. If the remainder is O(h²), the error of
//!   k∞(1, 2) is a third of that difference (see [`Extrapolation::error_estimate`]), so the estimate
//!   carries a safety factor 3 and also absorbs level-to-level mesh noise of unstructured meshes.

use serde::{Deserialize, Serialize};

use crate::error::ValidationError;

/// Observed orders outside this range mean the sequence is not in its asymptotic range (or is
/// dominated by noise); the result is flagged. Dimensionless; default [0.5, 2.0] around p = 1.
pub const ASYMPTOTIC_ORDER_RANGE: (f64, f64) = (0.5, 2.0);

/// Leading order of the discretisation error of the punch stiffness in the edge size h_e.
pub const THEORETICAL_ORDER: f64 = 1.0;

/// The result of a three-or-more-level extrapolation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Extrapolation {
    /// Extrapolated value k∞ from the two finest levels with the theoretical order.
    pub value: f64,
    /// Estimated absolute error of `value`: |k∞(finest pair) − k∞(previous pair)|.
    pub error_estimate: f64,
    /// Observed order from the three finest levels (NaN if the differences change sign).
    #[serde(deserialize_with = "crate::serde_nan::f64_or_nan")]
    pub observed_order: f64,
    /// Whether the observed order is inside [`ASYMPTOTIC_ORDER_RANGE`].
    pub asymptotic: bool,
    /// Value on the finest level.
    pub finest: f64,
}

/// Extrapolates `values[i]` computed at mesh parameters `h[i]` (decreasing, constant ratio).
pub fn extrapolate(
    quantity: &str,
    h: &[f64],
    values: &[f64],
) -> Result<Extrapolation, ValidationError> {
    let fail = |reason: String| ValidationError::Extrapolation {
        quantity: quantity.to_string(),
        reason,
    };
    if h.len() != values.len() {
        return Err(fail(format!(
            "{} mesh parameters for {} values",
            h.len(),
            values.len()
        )));
    }
    if h.len() < 3 {
        return Err(fail(format!("needs at least 3 levels, got {}", h.len())));
    }
    if values.iter().chain(h).any(|v| !v.is_finite()) || h.iter().any(|&v| v <= 0.0) {
        return Err(fail(
            "non-finite value or non-positive mesh parameter".into(),
        ));
    }
    let n = h.len();
    let ratio = h[n - 2] / h[n - 1];
    for i in 1..n {
        let r = h[i - 1] / h[i];
        if r.is_nan() || r <= 1.0 || (r / ratio - 1.0).abs() > RATIO_TOLERANCE {
            return Err(fail(format!(
                "refinement ratios must be equal and > 1 (level {i}: {r}, finest {ratio})"
            )));
        }
    }
    let (k0, k1, k2) = (values[n - 3], values[n - 2], values[n - 1]);
    let pair =
        |coarse: f64, fine: f64| fine + (fine - coarse) / (ratio.powf(THEORETICAL_ORDER) - 1.0);
    let value = pair(k1, k2);
    let previous = pair(k0, k1);
    let q = (k0 - k1) / (k1 - k2);
    let observed_order = if q > 0.0 {
        q.ln() / ratio.ln()
    } else {
        f64::NAN
    };
    let asymptotic =
        observed_order >= ASYMPTOTIC_ORDER_RANGE.0 && observed_order <= ASYMPTOTIC_ORDER_RANGE.1;
    Ok(Extrapolation {
        value,
        error_estimate: (value - previous).abs(),
        observed_order,
        asymptotic,
        finest: k2,
    })
}

/// Relative tolerance on equal refinement ratios. Dimensionless; default 1e-6.
const RATIO_TOLERANCE: f64 = 1e-6;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_order_sequence_extrapolates_exactly_with_zero_error_estimate() {
        let h = [0.04, 0.02, 0.01];
        let k: Vec<f64> = h.iter().map(|h| 3.0 + 2.0 * h).collect();
        let e = extrapolate("stiffness", &h, &k).unwrap();
        assert!(
            (e.value - 3.0).abs() < 1e-12,
            "extrapolated stiffness {}",
            e.value
        );
        assert!(
            e.error_estimate < 1e-12,
            "error estimate {}",
            e.error_estimate
        );
        assert!(
            (e.observed_order - 1.0).abs() < 1e-9,
            "observed order {}",
            e.observed_order
        );
        assert!(e.asymptotic, "a pure first-order sequence is asymptotic");
    }

    #[test]
    fn error_estimate_bounds_a_second_order_remainder() {
        let h = [0.04, 0.02, 0.01];
        let k: Vec<f64> = h.iter().map(|h| 3.0 + 2.0 * h + 50.0 * h * h).collect();
        let e = extrapolate("stiffness", &h, &k).unwrap();
        let true_error = (e.value - 3.0).abs();
        assert!(true_error > 0.0, "a quadratic remainder leaves an error");
        assert!(
            (e.error_estimate / true_error - 3.0).abs() < 1e-9,
            "estimate {} is 3 × the true error {}",
            e.error_estimate,
            true_error
        );
    }

    #[test]
    fn oscillating_sequence_is_flagged_not_asymptotic() {
        let e = extrapolate("stiffness", &[0.04, 0.02, 0.01], &[3.1, 3.0, 3.05]).unwrap();
        assert!(
            e.observed_order.is_nan() && !e.asymptotic,
            "sign change of the differences must be flagged"
        );
    }

    #[test]
    fn too_few_levels_or_unequal_ratios_are_refused() {
        assert!(
            extrapolate("k", &[0.02, 0.01], &[1.0, 1.0]).is_err(),
            "two levels"
        );
        assert!(
            extrapolate("k", &[0.04, 0.02, 0.005], &[1.0, 1.0, 1.0]).is_err(),
            "unequal ratios"
        );
        assert!(
            extrapolate("k", &[0.01, 0.02, 0.04], &[1.0, 1.0, 1.0]).is_err(),
            "increasing h"
        );
    }
}
