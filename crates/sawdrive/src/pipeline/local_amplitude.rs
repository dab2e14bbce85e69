//! The whole slider's static η at the local amplitude of the energy-conserving wave
//! (docs/physics.md §5.5): with `static.model = "slider"`, a lumped dynamic model and
//! `wave.attenuation` on, the posts near the trailing edge see a smaller wave than A₀, and the
//! whole slider's η, fitted to the contact forces of every post on the wave it sees, moves with
//! that (on the default slider η is 0.653 at 20 nm and 0.523 at 10 nm everywhere).
//!
//! Fixed point between the stages, η = g(η): η₀ (the static stage at the constant wave) → the
//! attenuated lumped model's amplitude profile at stall, A(x)/A₀, interpolated linearly onto
//! the post columns → the static stage's contact solves of every post on that wave
//! (`slider_contact::SliderParams::amplitude_scale_x`) → g(η₀) = η₁ → … until
//! |g(η) − η| < [`ETA_TOLERANCE`] η (4–5 passes on the default slider and on 30 µm posts at
//! 60 N; a secant on g(η) − η saved none: g is not smooth at 1e-3). A pass needs only the stall
//! profile (the period average's stall point, warm-started from the previous pass), so the
//! curve is solved once more, at the settled η; the reported curve is the one at that η, whose
//! own profile gives g(η) within the tolerance.
//!
//! Assumptions and limits: one η for the whole curve, the one at the stall profile, where the
//! wave falls most (near no load the posts draw little and the profile is nearly flat, so η
//! there lies between η₀ and the reported one); the profile of the lumped model's bins (its
//! columns along x, the same on every row); the strip's static model and the coupled strip need
//! none of this (the coupled model solves its normal contact at each post's own amplitude).

use std::path::Path;

use contact_springs::PostSprings;
use serde::Serialize;

use super::dynamic_stage::attenuation::{
    AmplitudeProfile, LumpedAttenuation, attenuate_lumped, is_transient, lumped_stall_profile,
};
use super::static_stage::slider::slider_eta_at_profile;
use super::{DynamicRun, dynamic_scene, run_dynamic};
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
    let (Some(profile), Some(eta_constant)) =
        (attenuation.stall_profile.clone(), statics.effective_ratio)
    else {
        return Ok(None);
    };
    let transient = is_transient(lumped.result.model);
    let settled = settle_eta(
        &post_columns_m(&stage.geometry),
        eta_constant,
        profile,
        |scale| {
            PipelineError::check(control, "static (whole slider at the local amplitude)")?;
            slider_eta_at_profile(scene, cache_dir, scale)
        },
        |eta, warm| {
            PipelineError::check(control, "dynamic (whole slider at the local amplitude)")?;
            stall_profile_at(scene, springs, eta, transient, warm)
        },
    )?;
    if settled.passes > 1 {
        let eta = settled.effective_contact_ratio;
        *lumped = run_dynamic(scene, springs, eta, control)?;
        *attenuation = attenuate_lumped(scene, &lumped.scene, &mut lumped.result)?;
        if attenuation.stall_profile.is_none() {
            return Err(attenuation_off(eta, &attenuation.wave.reason));
        }
    }
    Ok(Some(settled))
}

/// The post columns' x (m, relative to the slider's centre, ascending) of a lattice.
pub(crate) fn post_columns_m(g: &slider_contact::LatticeGeometry) -> Vec<f64> {
    (0..g.posts_x)
        .map(|i| g.x_m(i) - 0.5 * g.slider_length_m)
        .collect()
}

/// The lumped model's stall profile at η on the energy-conserving wave (the period average's
/// stall point alone, warm-started from `warm`; the transient's curve), or the error saying
/// `auto` turned the wave off there.
pub(crate) fn stall_profile_at(
    scene: &Scene,
    springs: &PostSprings,
    eta: f64,
    transient: bool,
    warm: &AmplitudeProfile,
) -> Result<AmplitudeProfile, PipelineError> {
    let dynamic = dynamic_scene(scene, springs, eta)?;
    lumped_stall_profile(scene, &dynamic, transient, Some(warm))?
        .map_err(|reason| attenuation_off(eta, &reason))
}

/// The fixed point of the module docs over any static model and lumped model: `eta_at(scale)`
/// is the static η on the wave A/A₀ = `scale` per post column (`columns_m`; `None`: not
/// identifiable), `stall_profile(η, warm)` the lumped model's stall profile at η (warm-started
/// from the previous one). Starts from η₀ = `eta_constant` and its curve's `profile`. Only the
/// stall profile enters η, so the passes solve no curve: when more than one pass was needed
/// the caller solves the curve at the reported η once.
pub(crate) fn settle_eta(
    columns_m: &[f64],
    eta_constant: f64,
    mut profile: AmplitudeProfile,
    mut eta_at: impl FnMut(&[f64]) -> Result<Option<f64>, PipelineError>,
    mut stall_profile: impl FnMut(f64, &AmplitudeProfile) -> Result<AmplitudeProfile, PipelineError>,
) -> Result<LocalAmplitudeEta, PipelineError> {
    let mut eta = eta_constant;
    for pass in 1..=MAX_PASSES {
        let scale: Vec<f64> = columns_m.iter().map(|&x| profile.at(x)).collect();
        let next = eta_at(&scale)?.ok_or_else(|| {
            unsupported(format!(
                "η is not identifiable on the attenuated wave of the stall profile \
                 (A/A₀ from {:.3} to {:.3})",
                scale.first().copied().unwrap_or(1.0),
                scale.last().copied().unwrap_or(1.0)
            ))
        })?;
        let change = (next - eta).abs() / eta;
        if change < ETA_TOLERANCE {
            return Ok(LocalAmplitudeEta {
                effective_contact_ratio: eta,
                constant_wave_effective_contact_ratio: eta_constant,
                passes: pass,
                last_change: change,
                stall_profile: profile,
            });
        }
        eta = next;
        profile = stall_profile(eta, &profile)?;
    }
    Err(unsupported(format!(
        "the whole slider's η at the local amplitude did not settle to {ETA_TOLERANCE:e} in \
         {MAX_PASSES} static–dynamic passes (last η {eta:.6})"
    )))
}

/// The error of a curve at η on which `auto` turned the energy-conserving wave off.
pub(crate) fn attenuation_off(eta: f64, reason: &str) -> PipelineError {
    unsupported(format!(
        "at the whole slider's η = {eta:.6} on the attenuated wave the energy-conserving \
         wave turned off ({reason}); set wave.attenuation = \"on\" or \"off\""
    ))
}

fn unsupported(message: String) -> PipelineError {
    PipelineError::Unsupported {
        stage: "static (whole slider at the local amplitude)",
        message,
    }
}
