//! When is the lumped model (N_eff = η·N independent posts) good enough? A cheap estimate of its
//! relative error against the coupled model, from what the static stage already computed, and
//! the `auto` choice between the two (issue 14 points 4 and 5).
//!
//! Estimate: e_lumped ≈ [`LUMPED_ERROR_PER_FIT_MISFIT`] · r_fit, where r_fit is the static η
//! fit's relative rms misfit of the post forces (static_contact::EtaFit::relative_rms_residual).
//! Reasoning: the lumped model is exact when the posts do not interact (r_fit = 0: every post
//! force is the lumped k_n⟨w − z⟩₊ of its own height); the interaction the scalar η cannot
//! represent shows first in the static force misfit, and the dynamic error (max of the relative
//! stall-thrust and no-load-speed errors at the static η) stays below the envelope factor times
//! that misfit over the study's 24 scenes (validation/coupled-dynamics/README.md, where the
//! factor is measured). Valid inside the study's range: Si posts of 20–50 µm on LiNbO3, 1089 to
//! 10000 posts, 10–100 N, μ = 0.3, the paper's wave; outside it the estimate is an
//! extrapolation and [`choose_model`] says so.

use serde::Serialize;

use crate::error::{CoupledError, Result};

/// Envelope factor of the lumped model's relative error over the static η fit misfit
/// (dimensionless): the largest ratio (lumped error at the static η)/(fit misfit) over the
/// study's scenes, rounded up. Default 0.5 (validation/coupled-dynamics/README.md).
pub const LUMPED_ERROR_PER_FIT_MISFIT: f64 = 0.5;
/// Error floor of the lumped closed form against the coupled model for non-interacting posts:
/// the coupled model's own step error at the study's T/128 (dimensionless). Default 2e-3.
pub const LUMPED_ERROR_FLOOR: f64 = 2e-3;
/// Default tolerance of the `auto` choice: the lumped model is used when its estimated error is
/// at most this (dimensionless). Default 0.02 (issue 14's 2 %).
pub const DEFAULT_AUTO_TOLERANCE: f64 = 0.02;

/// What the static stage knows about a scene (all in its report: `StaticReport`
/// `effective_contact_ratio`, `preloads[0].eta_fit.relative_rms_residual`, `posts_in_strip`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StaticEvidence {
    /// Relative rms misfit of the static η fit of the post forces (dimensionless).
    pub eta_fit_misfit: f64,
    /// The static η (dimensionless).
    pub effective_contact_ratio: f64,
    /// Posts of the static strip.
    pub posts_in_strip: usize,
}

/// Estimated relative error of the lumped model at the static η against the coupled model
/// (max of the stall-thrust and no-load-speed errors), see the module docs. NaN evidence gives
/// NaN (the caller then treats the error as unknown).
pub fn lumped_error_estimate(evidence: &StaticEvidence) -> f64 {
    LUMPED_ERROR_FLOOR + LUMPED_ERROR_PER_FIT_MISFIT * evidence.eta_fit_misfit
}

/// The dynamic model to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum DynamicsChoice {
    /// The lumped period-average model (stick_slip) at the static η.
    Lumped,
    /// This crate's coupled model.
    Coupled,
}

/// The `auto` decision with its reason.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelDecision {
    /// The model chosen.
    pub model: DynamicsChoice,
    /// Estimated relative error of the lumped model ([`lumped_error_estimate`]).
    pub lumped_error_estimate: f64,
    /// Tolerance used.
    pub tolerance: f64,
    /// One sentence for the summary.
    pub reason: String,
}

/// Strip sizes the study covered (posts of the static strip). Below or above, the estimate is
/// extrapolated.
const STUDY_STRIP_POSTS: (usize, usize) = (8, 120);

/// The cheapest model within `tolerance` of the coupled one: the lumped model if its estimated
/// error is at most `tolerance`, else the coupled model. Errors: tolerance outside (0, 1),
/// evidence not finite.
pub fn choose_model(evidence: &StaticEvidence, tolerance: f64) -> Result<ModelDecision> {
    if !(tolerance > 0.0 && tolerance < 1.0) {
        return Err(CoupledError::InvalidParameter {
            parameter: "model.tolerance",
            value: tolerance,
            requirement: "must lie in (0, 1)".into(),
        });
    }
    for (parameter, value) in [
        ("eta_fit_misfit", evidence.eta_fit_misfit),
        ("effective_contact_ratio", evidence.effective_contact_ratio),
    ] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(CoupledError::InvalidParameter {
                parameter,
                value,
                requirement: "the static stage must give a finite, non-negative value".into(),
            });
        }
    }
    let estimate = lumped_error_estimate(evidence);
    let extrapolated =
        !(STUDY_STRIP_POSTS.0..=STUDY_STRIP_POSTS.1).contains(&evidence.posts_in_strip);
    let note = if extrapolated {
        format!(
            " (a strip of {} posts lies outside the study's {}–{}: the estimate is extrapolated)",
            evidence.posts_in_strip, STUDY_STRIP_POSTS.0, STUDY_STRIP_POSTS.1
        )
    } else {
        String::new()
    };
    let (model, reason) = if estimate <= tolerance {
        (
            DynamicsChoice::Lumped,
            format!(
                "lumped: estimated error {:.1} % ≤ tolerance {:.1} % (static η fit misfit {:.1} %){note}",
                100.0 * estimate,
                100.0 * tolerance,
                100.0 * evidence.eta_fit_misfit
            ),
        )
    } else {
        (
            DynamicsChoice::Coupled,
            format!(
                "coupled: the lumped model's estimated error {:.1} % exceeds the tolerance {:.1} % (static η fit misfit {:.1} %){note}",
                100.0 * estimate,
                100.0 * tolerance,
                100.0 * evidence.eta_fit_misfit
            ),
        )
    };
    Ok(ModelDecision {
        model,
        lumped_error_estimate: estimate,
        tolerance,
        reason,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn evidence(misfit: f64) -> StaticEvidence {
        StaticEvidence {
            eta_fit_misfit: misfit,
            effective_contact_ratio: 0.6,
            posts_in_strip: 31,
        }
    }

    #[test]
    fn the_estimate_grows_with_the_static_fit_misfit() {
        let small = lumped_error_estimate(&evidence(0.01));
        let large = lumped_error_estimate(&evidence(0.2));
        assert!(
            small < large,
            "lumped error estimate: {small} at 1 % misfit vs {large} at 20 %"
        );
        assert_eq!(
            lumped_error_estimate(&evidence(0.0)),
            LUMPED_ERROR_FLOOR,
            "no interaction: only the floor"
        );
    }

    #[test]
    fn auto_picks_the_lumped_model_below_the_tolerance_and_the_coupled_above() {
        let tight =
            0.5 * (DEFAULT_AUTO_TOLERANCE - LUMPED_ERROR_FLOOR) / LUMPED_ERROR_PER_FIT_MISFIT;
        let loose = 4.0 * DEFAULT_AUTO_TOLERANCE / LUMPED_ERROR_PER_FIT_MISFIT;
        let a = choose_model(&evidence(tight), DEFAULT_AUTO_TOLERANCE).unwrap();
        assert_eq!(a.model, DynamicsChoice::Lumped, "{}", a.reason);
        assert!(a.reason.starts_with("lumped"), "reason: {}", a.reason);
        let b = choose_model(&evidence(loose), DEFAULT_AUTO_TOLERANCE).unwrap();
        assert_eq!(b.model, DynamicsChoice::Coupled, "{}", b.reason);
        assert!(b.reason.contains("exceeds"), "reason: {}", b.reason);
    }

    #[test]
    fn auto_refuses_a_bad_tolerance_and_missing_evidence_naming_them() {
        let err = choose_model(&evidence(0.1), 0.0).unwrap_err();
        assert!(err.to_string().contains("model.tolerance"), "{err}");
        let err = choose_model(&evidence(f64::NAN), 0.02).unwrap_err();
        assert!(err.to_string().contains("eta_fit_misfit"), "{err}");
    }
}
