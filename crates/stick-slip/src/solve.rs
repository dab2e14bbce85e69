//! The one-call entry point: run the model the scene needs.

use crate::error::Result;
use crate::periodic::PeriodicAverageModel;
use crate::result::DynamicResult;
use crate::scene::{DynamicScene, ModelKind};
use crate::transient::TransientModel;

/// Validate the scene, choose the model (`auto`: the period average unless the scene needs the
/// transient, reason in `model_reason`) and run it.
pub fn solve(scene: &DynamicScene) -> Result<DynamicResult> {
    match scene.resolve_model()?.0 {
        ModelKind::PeriodicAverage => PeriodicAverageModel::new(scene)?.solve(),
        ModelKind::Transient => TransientModel::new(scene)?.solve(),
    }
}
