//! The static → dynamic pipeline: a resolved [`Scene`](crate::scene::Scene) to springs, the
//! static FEM contact (η), the dynamic stick/slip model, and the files a run writes.
//!
//! Each stage is a function of the scene (and the previous stage's output), so a user can stop
//! after any stage or feed a hand-chosen η to the dynamics (`effective_ratio = 0.36`).

mod attenuation;
mod ball;
mod coupled;
mod dynamics;
mod error;
mod local_amplitude;
pub mod evaluate;
mod run;
mod slider_static;
mod springs;
mod stages;
mod statics;

pub use attenuation::{
    AmplitudeProfile, LumpedAttenuation, WaveAttenuation, WaveBooks, wave_power_under_array_w,
};
pub use local_amplitude::LocalAmplitudeEta;
pub use ball::{
    BALL_DRAW_WARNING_FRACTION, BallStage, ball_scene, run_ball_stage, write_ball_stage_files,
};
pub use coupled::{
    DriveFigures, DynamicJson, DynamicStage, LumpedFigures, run_dynamic_stage,
    write_dynamic_stage_files,
};
pub use dynamics::{DynamicRun, dynamic_scene, run_dynamic, write_history_charts};
pub use error::PipelineError;
pub use run::{RunOptions, RunSummary, StageTimings, check_dynamic_figures, run_pipeline};
/// The caller's stop request and progress sink, passed to every stage that can be stopped
/// ([`RunControl::none()`]: never stops, reports nothing).
pub use run_control::{Progress, RunControl};
pub use slider_static::{
    SliderStage, run_slider_static, slider_content_hash, slider_params, write_slider_maps,
};
pub use springs::scene_springs;
pub use stages::{EffectiveRatio, effective_ratio};
pub use statics::{
    StaticDetails, StaticOutcome, StaticStageReport, fill_static_cache, geometry_key,
    static_params, write_static_files,
};

/// The static stage (`statics::run_static`), asking `control` before each contact solve; a
/// ball slider has none and is refused.
pub fn run_static(
    scene: &crate::scene::Scene,
    springs: &contact_springs::PostSprings,
    cache_dir: Option<&std::path::Path>,
    with_fields: bool,
    control: &RunControl,
) -> Result<StaticOutcome, PipelineError> {
    ball::refuse_static(scene)?;
    statics::run_static(scene, springs, cache_dir, with_fields, control)
}
