//! The dynamic stage: the lumped model ([`lumped`]: stick-slip's period average or transient on
//! N_eff = η·N posts), the coupled model of every post of the strip row ([`coupled`]) or of the
//! whole slider ([`whole_slider`], with `static.model = "slider"`), run when `model.dynamics`
//! asks for it or `auto` finds the lumped model's estimated error above
//! `model.lumped_tolerance` (the decision, [`run_dynamic_stage`], is this file's), and the ball
//! slider ([`ball`]); the energy-conserving wave's decision and solves for every dynamic model
//! ([`attenuation`]).
//!
//! One-way: the stage reads the static stage only through its typed outcome
//! ([`crate::pipeline::StaticOutcome`]) and tip compliances ([`crate::pipeline::strip_tips`]).

pub(crate) mod attenuation;
pub(crate) mod ball;
pub(crate) mod coupled;
pub(crate) mod lumped;
pub(crate) mod whole_slider;

/// The pipeline's error, as `attenuation` names it (`super::PipelineError`).
use crate::pipeline::PipelineError;

use std::path::Path;

use contact_springs::PostSprings;
use coupled_dynamics::{
    DEFAULT_AUTO_TOLERANCE, DynamicsChoice, LumpedEvidence, choose_model, lumped_error_estimate,
};

use self::coupled::{CoupledOutcome, DriveFigures, DynamicStage, slider_coupled, strip_coupled};
use self::lumped::run_dynamic;
use crate::pipeline::RunControl;
use crate::pipeline::{StaticDetails, StaticOutcome};
use crate::scene::{Dynamics, Scene, StaticModel};

/// Run the dynamic stage of `scene` at η = `effective_ratio`: the lumped model, and the coupled
/// one when `model.dynamics` asks for it or `auto` finds the lumped model's estimated error above
/// `model.lumped_tolerance`. `statics` is the static stage's outcome (`None`: η was given);
/// `cache_dir` holds the strip's tip compliances between runs. `control` is asked before each
/// point of the lumped curve and before the coupled model (which itself is not interrupted).
pub fn run_dynamic_stage(
    scene: &Scene,
    springs: &PostSprings,
    effective_ratio: f64,
    statics: Option<&StaticOutcome>,
    cache_dir: Option<&Path>,
    control: &RunControl,
) -> Result<DynamicStage, PipelineError> {
    let lumped = run_dynamic(scene, springs, effective_ratio, control)?;
    let evidence = statics.and_then(|s| {
        evidence(
            s,
            lumped.result.no_load_speed_m_per_s,
            scene.motor.wave.crest_speed_m_per_s(),
        )
    });
    let estimate = evidence.as_ref().map(lumped_error_estimate);
    let (run_coupled, reason) = decide(scene, statics, evidence.as_ref())?;
    let mut lumped = lumped;
    let mut local_amplitude = None;
    let outcome = match (run_coupled, statics) {
        (true, Some(statics)) => {
            PipelineError::check(control, "dynamic (coupled model)")?;
            match &statics.report.details {
                StaticDetails::Slider(stage) => slider_coupled(scene, stage, &lumped, control)?,
                StaticDetails::Strip(_) => {
                    strip_coupled(scene, statics, &lumped, cache_dir, control)?
                }
            }
        }
        _ => {
            let mut attenuated =
                attenuation::attenuate_lumped(scene, &lumped.scene, &mut lumped.result)?;
            if let Some(statics) = statics {
                local_amplitude = crate::pipeline::local_amplitude::settle(
                    scene,
                    springs,
                    statics,
                    cache_dir,
                    control,
                    &mut lumped,
                    &mut attenuated,
                )?;
            }
            CoupledOutcome::lumped(attenuated.wave, attenuated.books)
        }
    };
    let mut stage = DynamicStage {
        lumped,
        coupled: outcome.result,
        coupled_histories: outcome.histories,
        coupled_step_error_estimate: outcome.step_error,
        dynamics_reason: reason,
        lumped_error_estimate: estimate,
        wave: outcome.wave,
        wave_books: outcome.books,
        local_amplitude,
        drive: None,
        coupled_slider: outcome.slider,
    };
    let max_output_w = stage
        .curve()
        .iter()
        .map(|p| p.output_power_w)
        .fold(0.0, f64::max);
    stage.drive = DriveFigures::of(scene, max_output_w)?;
    Ok(stage)
}

/// The criterion's evidence from the static stage of either model: its η fit's misfit (the
/// strip's main preload, or the whole slider's fit), with the lumped no-load speed.
fn evidence(
    statics: &StaticOutcome,
    lumped_no_load_speed_m_per_s: f64,
    crest_speed_m_per_s: f64,
) -> Option<LumpedEvidence> {
    match &statics.report.details {
        StaticDetails::Strip(report) => {
            LumpedEvidence::from_report(report, lumped_no_load_speed_m_per_s, crest_speed_m_per_s)
        }
        StaticDetails::Slider(slider) => {
            let fit = &slider.report.eta_fit;
            fit.eta.map(|_| LumpedEvidence {
                eta_fit_misfit: fit.relative_rms_residual,
                lumped_no_load_speed_m_per_s,
                crest_speed_m_per_s,
            })
        }
    }
}

/// Whether the coupled model runs, and why.
fn decide(
    scene: &Scene,
    statics: Option<&StaticOutcome>,
    evidence: Option<&LumpedEvidence>,
) -> Result<(bool, String), PipelineError> {
    match (scene.model.dynamics, statics, evidence) {
        (Dynamics::Lumped(_), _, _) => Ok((false, "model.dynamics names a lumped model".into())),
        (Dynamics::Coupled, None, _) => Err(PipelineError::Unsupported {
            stage: "dynamic",
            message: "model.dynamics = \"coupled\" needs the static stage's strip compliance, \
                      but contact.effective_ratio is given: set it to \"fem\""
                .into(),
        }),
        (Dynamics::Coupled, Some(s), _) if s.report.model == StaticModel::Slider => {
            whole_slider::check_scene(scene)?;
            Ok((
                true,
                "model.dynamics = \"coupled\" asks for it: every post of the whole slider \
                 (static.model = \"slider\") on its own static state"
                    .into(),
            ))
        }
        (Dynamics::Coupled, Some(_), _) => {
            Ok((true, "model.dynamics = \"coupled\" asks for it".into()))
        }
        (Dynamics::Auto, None, _) => Ok((
            false,
            "lumped: η is given (contact.effective_ratio), so no static fit estimates the \
             lumped model's error and the coupled model has no strip compliance"
                .into(),
        )),
        (Dynamics::Auto, Some(_), None) => Ok((
            false,
            "lumped: the static stage fitted no η, so the lumped model's error cannot be \
             estimated"
                .into(),
        )),
        (Dynamics::Auto, Some(s), Some(evidence)) => {
            let tolerance = scene
                .model
                .lumped_tolerance
                .unwrap_or(DEFAULT_AUTO_TOLERANCE);
            let decision = choose_model(evidence, tolerance)?;
            let coupled = decision.model == DynamicsChoice::Coupled;
            if s.report.model != StaticModel::Slider {
                return Ok((coupled, decision.reason));
            }
            let reason = format!(
                "whole slider (every post, static.model = \"slider\"): {}; the estimate uses \
                 the whole slider's η fit misfit with the strips' envelope factor",
                decision.reason
            );
            if coupled {
                whole_slider::check_scene(scene)?;
            }
            Ok((coupled, reason))
        }
    }
}
