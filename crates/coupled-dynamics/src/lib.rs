#![doc = include_str!("../README.md")]

mod anderson;
pub mod attenuation;
pub mod boxqp;
pub mod criterion;
mod error;
pub mod model;
pub mod result;
pub mod scene;
pub mod slider;

pub use attenuation::{
    AttenuatedCurve, AttenuatedPoint, AttenuationOptions, attenuated_at_speed, solve_attenuated,
    solve_attenuated_with_histories,
};
pub use criterion::{
    DEFAULT_AUTO_TOLERANCE, DynamicsChoice, LUMPED_ERROR_FACTOR, LumpedEvidence, ModelDecision,
    choose_model, lumped_error_estimate,
};
pub use error::{CoupledError, Result};
pub use model::{
    ComplianceProduct, CoupledModel, CoupledPoint, PeriodState, PostHistories, PostMeans, PostMode,
};
pub use result::{CoupledResult, fit_eta_dyn, lumped_misfit, solve};
pub use scene::{CoupledScene, PreloadBalance, WaveDirection};
pub use slider::{
    AttenuatedSlider, NormalContact, ProfiledState, RigidBackContact, SliderDynamics,
    SliderDynamicsResult, SliderMaps, SliderProfiles, SliderScene,
};
