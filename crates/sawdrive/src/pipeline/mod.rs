//! The static → dynamic pipeline: a resolved [`Scene`](crate::scene::Scene) to springs, the
//! static FEM contact (η), the dynamic stick/slip model, and the files a run writes.
//!
//! Each stage is a function of the scene (and the previous stage's output), so a user can stop
//! after any stage or feed a hand-chosen η to the dynamics (`effective_ratio = 0.36`).

mod dynamic_stage;
mod error;
pub mod evaluate;
mod local_amplitude;
mod run;
mod stages;
mod static_stage;

pub use dynamic_stage::attenuation::{
    AmplitudeProfile, LumpedAttenuation, WaveAttenuation, WaveBooks, wave_power_under_array_w,
};
pub use dynamic_stage::ball::{
    BALL_DRAW_WARNING_FRACTION, BallStage, ball_scene, run_ball_stage, write_ball_stage_files,
};
pub use dynamic_stage::coupled::{
    DriveFigures, DynamicJson, DynamicStage, LumpedFigures, SliderCoupledFigures,
    write_dynamic_stage_files,
};
pub use dynamic_stage::lumped::{DynamicRun, dynamic_scene, run_dynamic, write_history_charts};
pub use dynamic_stage::run_dynamic_stage;
pub use error::PipelineError;
pub use local_amplitude::LocalAmplitudeEta;
pub use run::{RunOptions, RunSummary, StageTimings, check_dynamic_figures, run_pipeline};
/// The caller's stop request and progress sink, passed to every stage that can be stopped
/// ([`RunControl::none()`]: never stops, reports nothing).
pub use run_control::{Progress, RunControl};
pub use stages::{EffectiveRatio, effective_ratio};
pub use static_stage::fill::fill_static_cache;
pub use static_stage::keys::{geometry_key, static_params};
pub use static_stage::slider::{
    SliderStage, run_slider_static, slider_content_hash, slider_params, write_slider_maps,
};
pub use static_stage::springs::scene_springs;
pub use static_stage::strip::{
    StaticDetails, StaticOutcome, StaticStageReport, write_static_files,
};

pub use static_stage::run_static;
pub use static_stage::tips::{StripTips, strip_tips};
