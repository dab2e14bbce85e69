//! The one-call entry points: run the model the scene needs.

use run_control::RunControl;

use crate::error::{Result, stop_check};
use crate::history::{PostHistory, SliderHistory};
use crate::periodic::PeriodicAverageModel;
use crate::result::DynamicResult;
use crate::scene::{DynamicScene, ModelKind};
use crate::transient::TransientModel;

/// Validate the scene, choose the model (`auto`: the period average unless the scene needs the
/// transient, reason in `model_reason`) and run it.
pub fn solve(scene: &DynamicScene) -> Result<DynamicResult> {
    match scene.resolve_model()?.0 {
        ModelKind::PeriodicAverage => PeriodicAverageModel::new(scene)?.solve(&RunControl::none()),
        ModelKind::Transient => TransientModel::new(scene)?.solve(),
    }
}

/// Histories for the charts of a run: one post over `options.history.periods` wave periods at
/// the operating point (at half the no-load speed if the load exceeds the stall thrust), and
/// the slider's motion for the transient model.
#[derive(Debug, Clone, PartialEq)]
pub struct RunHistories {
    /// One post (Fig. 6).
    pub post: PostHistory,
    /// The slider (transient only).
    pub slider: Option<SliderHistory>,
}

/// [`solve`] plus the histories the charts need (`plots::write_post_history_chart`,
/// `plots::write_slider_history_chart`); `control` is asked before each curve point or
/// transient run (a stopped run ends within one point with
/// [`crate::StickSlipError::Cancelled`]). [`RunControl::none()`]: never stops.
pub fn solve_with_histories(
    scene: &DynamicScene,
    control: &RunControl,
) -> Result<(DynamicResult, RunHistories)> {
    match scene.resolve_model()?.0 {
        ModelKind::PeriodicAverage => {
            let model = PeriodicAverageModel::new(scene)?;
            let result = model.solve(control)?;
            stop_check(control, || "the post history".into())?;
            let speed = result
                .operating_point
                .map_or(0.5 * result.no_load_speed_m_per_s, |op| op.speed_m_per_s);
            let h = &scene.options.history;
            let post = model.post_history(speed, h.periods, h.samples_per_period)?;
            Ok((result, RunHistories { post, slider: None }))
        }
        ModelKind::Transient => {
            let (result, run) = TransientModel::new(scene)?.solve_with_runs(control)?;
            let post = run.post_history.unwrap_or_default();
            Ok((
                result,
                RunHistories {
                    post,
                    slider: run.slider_history,
                },
            ))
        }
    }
}
