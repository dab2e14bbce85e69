//! The whole slider's static η at the local amplitude of the energy-conserving wave
//! (docs/physics.md §5.5): with `static.model = "slider"`, a lumped dynamic model and
//! `wave.attenuation` on, the posts near the trailing edge see a smaller wave than A₀, and the
//! whole slider's η, fitted to the contact forces of every post on the wave it sees, moves with
//! that (on the default slider η is 0.653 at 20 nm and 0.523 at 10 nm everywhere).
//!
//! Fixed point between the stages: η₀ (the static stage at the constant wave) → the attenuated
//! lumped curve → its amplitude profile at stall, A(x)/A₀, interpolated linearly onto the post
//! columns → the static stage's contact solves of every post on that wave
//! (`slider_contact::SliderParams::amplitude_scale_x`, cached like the constant-wave solve) →
//! η₁ → the curve again at η₁ → … until |η_{k+1} − η_k| < [`ETA_TOLERANCE`] η_k; the curve
//! reported is the one at the last η, whose own profile gives the next η within the tolerance.
//!
//! Assumptions and limits: one η for the whole curve, the one at the stall profile, where the
//! wave falls most (near no load the posts draw little and the profile is nearly flat, so η
//! there lies between η₀ and the reported one); the profile of the lumped model's bins (its
//! columns along x, the same on every row); the strip's static model and the coupled strip need
//! none of this (the coupled model solves its normal contact at each post's own amplitude).

use std::path::Path;

use contact_springs::PostSprings;
use serde::Serialize;

use super::dynamic_stage::attenuation::{AmplitudeProfile, LumpedAttenuation, attenuate_lumped};
use super::static_stage::slider::slider_eta_at_profile;
use super::{DynamicRun, run_dynamic};
use super::{PipelineError, RunControl};
use super::{StaticDetails, StaticOutcome};
use crate::scene::Scene;

/// Relative change of η between two passes below which η is settled. Default 1e-3 (the lumped
/// thrust moves by about as much: far below the whole slider's η fit misfit).
pub const ETA_TOLERANCE: f64 = 1e-3;
/// Static–dynamic passes at most. Default 8.
pub const MAX_PASSES: usize = 8;

/// The whole slider's η at the local amplitude, reported in `dynamic --json` and the summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LocalAmplitudeEta {
    /// η the reported curve ran at: the whole slider's on the wave of the stall profile.
    pub effective_contact_ratio: f64,
    /// η of the static stage on the constant-amplitude wave.
    pub constant_wave_effective_contact_ratio: f64,
    /// Static solves at a profile (passes of the fixed point).
    pub passes: usize,
    /// |Δη|/η of the last pass.
    pub last_change: f64,
    /// A/A₀ at stall along the slider, the profile the η belongs to.
    pub stall_profile: AmplitudeProfile,
}

/// The fixed point of the module docs, from the lumped run `lumped` at the static stage's η
/// (`attenuation` its energy-conserving wave): both are replaced by the run at the settled η.
/// `None` when it does not apply (the strip's static stage, attenuation off).
pub(super) fn settle(
    scene: &Scene,
    springs: &PostSprings,
    statics: &StaticOutcome,
    cache_dir: Option<&Path>,
    control: &RunControl,
    lumped: &mut DynamicRun,
    attenuation: &mut LumpedAttenuation,
) -> Result<Option<LocalAmplitudeEta>, PipelineError> {
    let StaticDetails::Slider(stage) = &statics.report.details else {
        return Ok(None);
    };
    let (Some(mut profile), Some(eta_constant)) =
        (attenuation.stall_profile.clone(), statics.effective_ratio)
    else {
        return Ok(None);
    };
    let g = &stage.geometry;
    let columns: Vec<f64> = (0..g.posts_x)
        .map(|i| g.x_m(i) - 0.5 * g.slider_length_m)
        .collect();
    let mut eta = eta_constant;
    for pass in 1..=MAX_PASSES {
        PipelineError::check(control, "static (whole slider at the local amplitude)")?;
        let scale: Vec<f64> = columns.iter().map(|&x| profile.at(x)).collect();
        let next = slider_eta_at_profile(scene, cache_dir, &scale)?.ok_or_else(|| {
            unsupported(format!(
                "η is not identifiable on the attenuated wave of the stall profile \
                 (A/A₀ from {:.3} to {:.3})",
                scale.first().copied().unwrap_or(1.0),
                scale.last().copied().unwrap_or(1.0)
            ))
        })?;
        let change = (next - eta).abs() / eta;
        if change < ETA_TOLERANCE {
            return Ok(Some(LocalAmplitudeEta {
                effective_contact_ratio: eta,
                constant_wave_effective_contact_ratio: eta_constant,
                passes: pass,
                last_change: change,
                stall_profile: profile,
            }));
        }
        eta = next;
        *lumped = run_dynamic(scene, springs, eta, control)?;
        *attenuation = attenuate_lumped(scene, &lumped.scene, &mut lumped.result)?;
        profile = attenuation.stall_profile.clone().ok_or_else(|| {
            unsupported(format!(
                "at the whole slider's η = {eta:.6} on the attenuated wave the energy-conserving \
                 wave turned off ({}); set wave.attenuation = \"on\" or \"off\"",
                attenuation.wave.reason
            ))
        })?;
    }
    Err(unsupported(format!(
        "the whole slider's η at the local amplitude did not settle to {ETA_TOLERANCE:e} in \
         {MAX_PASSES} static–dynamic passes (last η {eta:.6})"
    )))
}

fn unsupported(message: String) -> PipelineError {
    PipelineError::Unsupported {
        stage: "static (whole slider at the local amplitude)",
        message,
    }
}
