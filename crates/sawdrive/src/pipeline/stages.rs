//! Where the static and the dynamic stage meet: the effective contact ratio η the dynamics run
//! with, given by the scene (`contact.effective_ratio`) or identified by the static stage.
//!
//! This is the one place that branches on "η given or from the FEM": `sawdrive run`
//! ([`super::run_pipeline`]), `sawdrive dynamic` and the Python bindings all call
//! [`effective_ratio`]. Range of validity: η ∈ (0, 1] by `contact_springs`' rule; a static stage
//! that cannot identify η (no post in contact over a whole wave period) is refused, naming the
//! scene key that gives it by hand.

use std::path::Path;

use contact_springs::PostSprings;

use super::{PipelineError, RunControl, StaticOutcome, run_static};
use crate::scene::Scene;

/// η for the dynamic stage and where it came from.
#[derive(Debug)]
pub struct EffectiveRatio {
    /// η (dimensionless).
    pub value: f64,
    /// `given` (the scene's `contact.effective_ratio`) or `fem` (the static stage).
    pub source: &'static str,
    /// The static stage's outcome, when it ran.
    pub statics: Option<StaticOutcome>,
}

/// η of `scene`: the scene's `contact.effective_ratio` when given, else the static stage's
/// ([`run_static`] with `cache_dir`, `with_fields` and `control`, told to `control` as the
/// stage "static FEM contact (η)"). Refused, naming the key, when
/// the static stage cannot identify it.
pub fn effective_ratio(
    scene: &Scene,
    springs: &PostSprings,
    cache_dir: Option<&Path>,
    with_fields: bool,
    control: &RunControl,
) -> Result<EffectiveRatio, PipelineError> {
    if let Some(value) = scene.contact.effective_ratio {
        return Ok(EffectiveRatio {
            value,
            source: "given",
            statics: None,
        });
    }
    control.stage("static FEM contact (η)");
    let outcome = run_static(scene, springs, cache_dir, with_fields, control)?;
    let value = outcome
        .effective_ratio
        .ok_or_else(|| PipelineError::Unsupported {
            stage: "static",
            message: format!(
                "η is not identifiable for this scene ({}); give it as a number \
                 (contact.effective_ratio, e.g. --set effective_ratio=0.36)",
                outcome
                    .report
                    .effective_contact_ratio_note
                    .as_deref()
                    .unwrap_or("no reason given")
            ),
        })?;
    Ok(EffectiveRatio {
        value,
        source: "fem",
        statics: Some(outcome),
    })
}
