//! The dynamic stage: the lumped model ([`lumped`]: stick-slip's period average or transient on
//! N_eff = η·N posts), the coupled model of every post of the strip row ([`coupled`]) or of the
//! whole slider ([`whole_slider`], with `static.model = "slider"`), run when `model.dynamics`
//! asks for it or `auto` finds the lumped model's estimated error above
//! `model.lumped_tolerance` (the decision is `coupled::run_dynamic_stage`'s), and the ball
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
