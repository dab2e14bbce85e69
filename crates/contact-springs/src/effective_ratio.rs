//! The contract for the effective contact ratio η = N_eff/N (docs/physics.md §4), one rule for the
//! scene, the static and the dynamic crates.
//!
//! η scales the number of independent posts of Johnson stiffness k_n that carry the preload.
//! It is a fit, not a fraction: the static FEM contact reports η slightly above 1 for sparse
//! arrays at low preload (1.03 at 5 N for 20 µm posts at 40 µm pitch, 1.185 for 50 µm posts at
//! 20 N, from the strip's end posts; validation/static-contact/README.md, "Reading the
//! numbers"), so η ≤ 1 is not a law of the model and a value the FEM reports must be accepted
//! when typed back into a scene.
//!
//! Rule: η is finite and 0 < η ≤ [`MAX_EFFECTIVE_RATIO`].

use crate::error::SpringError;

/// Largest accepted η. Default 1.5: above every η of the static study (at most 1.185 for the
/// whole strip, 1.12 for its central posts, η_pair ≤ 1.023 for a post pair) with a margin for
/// other meshes and preloads; η = 1.5 would mean posts half again stiffer than the Johnson
/// series spring, which no studied array approaches.
pub const MAX_EFFECTIVE_RATIO: f64 = 1.5;

/// Check η against the contract: finite, > 0 and ≤ [`MAX_EFFECTIVE_RATIO`]. Returns η.
///
/// ```
/// use contact_springs::effective_ratio::{check, MAX_EFFECTIVE_RATIO};
/// assert_eq!(check(1.03), Ok(1.03)); // as the static stage reports it for sparse arrays
/// assert!(check(0.0).is_err() && check(f64::NAN).is_err());
/// assert!(check(MAX_EFFECTIVE_RATIO * 1.01).is_err());
/// ```
pub fn check(eta: f64) -> Result<f64, SpringError> {
    if eta.is_finite() && eta > 0.0 && eta <= MAX_EFFECTIVE_RATIO {
        Ok(eta)
    } else {
        Err(SpringError::OutOfRange {
            parameter: "effective_ratio",
            value: eta,
            accepted: "must be finite, > 0 and ≤ 1.5 (contact_springs::effective_ratio::MAX_EFFECTIVE_RATIO; the static FEM reports values slightly above 1 for sparse arrays)",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_eta_the_static_study_reports_is_accepted() {
        for eta in [0.47, 0.6, 1.0, 1.027, 1.03, 1.122, 1.185] {
            assert_eq!(
                check(eta),
                Ok(eta),
                "η = {eta} from validation/static-contact"
            );
        }
    }

    #[test]
    fn non_positive_non_finite_and_excessive_eta_are_refused() {
        for eta in [0.0, -0.1, f64::NAN, f64::INFINITY, 1.6, 5e-324 * 0.0] {
            assert!(check(eta).is_err(), "η = {eta} refused");
        }
    }
}
