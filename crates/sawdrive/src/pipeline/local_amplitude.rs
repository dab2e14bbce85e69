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
//! 60 N; a secant on g(η) − η saved none: g is not smooth at 1e-3). Where the plain passes stop
//! contracting (a pass that does not halve |g(η) − η|: on 160 × 160 posts of 14.7 µm at 48.7 N
//! they cycle between η = 0.3043 and 0.3073, |g′| ≈ 1), the passes go on by false position
//! (Illinois) inside the bracket of the passes so far, which holds the fixed point; where g
//! jumps across the diagonal (a row switching between stick and slip) there is no η with
//! |g(η) − η| below the tolerance, and η is settled once the bracket is narrower than
//! [`ETA_TOLERANCE`] η (the reported `last_change` then says how far g jumps). A pass needs only the stall
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
/// Static–dynamic passes at most. Default 12 (plain passes settle in 4–5; the false position
/// after a cycle needs 3–4 more).
pub const MAX_PASSES: usize = 12;

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
    let mut bracket = Bracket::default();
    let mut last_residual = f64::INFINITY;
    let mut false_position = false;
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
        let residual = next - eta;
        let change = residual.abs() / eta;
        bracket.record(eta, residual);
        if change < ETA_TOLERANCE || bracket.width() < ETA_TOLERANCE * eta {
            return Ok(LocalAmplitudeEta {
                effective_contact_ratio: eta,
                constant_wave_effective_contact_ratio: eta_constant,
                passes: pass,
                last_change: change,
                stall_profile: profile,
            });
        }
        false_position |= residual.abs() > 0.5 * last_residual;
        last_residual = residual.abs();
        eta = match bracket.false_position() {
            Some(inside) if false_position => inside,
            _ => next,
        };
        profile = stall_profile(eta, &profile)?;
    }
    Err(unsupported(format!(
        "the whole slider's η at the local amplitude did not settle to {ETA_TOLERANCE:e} in \
         {MAX_PASSES} static–dynamic passes (last η {eta:.6})"
    )))
}

/// The passes' bracket of the fixed point: the latest η with g(η) > η (`low`, the fixed point
/// above it) and with g(η) < η (`high`), each with its residual g(η) − η.
#[derive(Debug, Default)]
struct Bracket {
    low: Option<(f64, f64)>,
    high: Option<(f64, f64)>,
    /// Which end the last pass replaced (`true`: `low`).
    last_replaced_low: Option<bool>,
}

impl Bracket {
    /// Record a pass; an end kept twice in a row has its residual halved (Illinois), so the
    /// false position cannot stall at one end.
    fn record(&mut self, eta: f64, residual: f64) {
        let low = residual > 0.0;
        if self.last_replaced_low == Some(low) {
            let kept = if low { &mut self.high } else { &mut self.low };
            if let Some(end) = kept {
                end.1 *= 0.5;
            }
        }
        *(if low { &mut self.low } else { &mut self.high }) = Some((eta, residual));
        self.last_replaced_low = Some(low);
    }

    /// The zero of the secant through the two ends, once both are known.
    fn false_position(&self) -> Option<f64> {
        let ((a, ra), (b, rb)) = (self.low?, self.high?);
        Some(a - ra * (b - a) / (rb - ra))
    }

    /// |high − low| (infinite until both ends are known).
    fn width(&self) -> f64 {
        match (self.low, self.high) {
            (Some((a, _)), Some((b, _))) => (b - a).abs(),
            _ => f64::INFINITY,
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `settle_eta` on a scalar map g: the "profile" carries η itself (one column at x = 0), so
    /// the static solve at a profile is g(η).
    fn settle_on(g: impl Fn(f64) -> f64, eta0: f64) -> Result<LocalAmplitudeEta, PipelineError> {
        settle_eta(
            &[0.0],
            eta0,
            AmplitudeProfile::of(&[0.0], &[eta0]),
            |scale| Ok(Some(g(scale[0]))),
            |eta, _| Ok(AmplitudeProfile::of(&[0.0], &[eta])),
        )
    }

    #[test]
    fn contracting_passes_settle_by_plain_iteration() {
        let g = |eta: f64| 0.3 + 0.2 * (eta - 0.3);
        let s = settle_on(g, 0.45).unwrap();
        assert!((s.effective_contact_ratio - 0.3).abs() < ETA_TOLERANCE * 0.3);
        // 0.15 · 0.2^k below 3e-4 after 4 passes: plain iteration, no bracketing detour.
        assert_eq!(s.passes, 5);
    }

    #[test]
    fn a_two_cycle_of_the_plain_passes_settles_by_false_position() {
        // g′ = −0.98: the plain passes alternate about 0.3 and shrink by 2 % per pass (the
        // 0.3043/0.3073 cycle of 160 × 160 posts at 48.7 N), far beyond the pass limit.
        let g = |eta: f64| 0.3 - 0.98 * (eta - 0.3);
        let s = settle_on(g, 0.45).unwrap();
        assert!((s.effective_contact_ratio - 0.3).abs() < ETA_TOLERANCE * 0.3);
        assert!(s.passes <= MAX_PASSES);
    }

    #[test]
    fn a_map_that_jumps_across_the_diagonal_settles_at_the_jump_within_the_tolerance() {
        let g = |eta: f64| if eta < 0.305 { 0.31 } else { 0.30 };
        let s = settle_on(g, 0.45).unwrap();
        assert!((s.effective_contact_ratio - 0.305).abs() < ETA_TOLERANCE * 0.305);
        // No η has |g(η) − η| below the tolerance: the report says how far g jumps.
        assert!(s.last_change > ETA_TOLERANCE);
    }

    #[test]
    fn a_map_without_a_fixed_point_in_reach_is_a_named_error() {
        let g = |eta: f64| 1.05 * eta;
        let e = settle_on(g, 0.3).unwrap_err().to_string();
        assert!(e.contains("did not settle"), "{e}");
    }
}
