//! The static stage: which model identifies η (the strip of one post row or the whole slider,
//! chosen by `static.model`), the strip ([`strip`]: the condensed strip FEM, its verified report
//! cache and the sweep's cache fill), the whole slider ([`slider`]: the lattice model with the
//! near field calibrated on the strip FEM), the post springs both use ([`springs`]) and the
//! strip's tip compliances handed to the coupled dynamics ([`tips`]); the keys they share
//! ([`keys`]), the one verified cache every cached artefact of the stage goes through
//! ([`cache`]) and the sweep's cache fill ([`fill`]).
//!
//! One-way: nothing here imports the dynamic stage; what leaves the stage is its typed outcome
//! ([`StaticOutcome`]) and the tip compliances ([`tips::StripTips`]), re-exported by the pipeline.

pub(crate) mod cache;
pub(crate) mod fill;
pub(crate) mod keys;
pub(crate) mod slider;
pub(crate) mod springs;
pub(crate) mod strip;
pub(crate) mod tips;

use std::path::Path;

use contact_springs::PostSprings;

pub use strip::StaticOutcome;

use crate::pipeline::{PipelineError, RunControl};
use crate::scene::Scene;

/// The static stage (`strip::run_static`: the strip or the whole slider, as `static.model`
/// chooses), asking `control` before each contact solve. A ball slider has none: refused naming
/// `slider.shape`.
pub fn run_static(
    scene: &Scene,
    springs: &PostSprings,
    cache_dir: Option<&Path>,
    with_fields: bool,
    control: &RunControl,
) -> Result<StaticOutcome, PipelineError> {
    if scene.ball.is_some() {
        return Err(PipelineError::Unsupported {
            stage: "static",
            message: "slider.shape = \"ball\" has no post array and no static stage (one Hertz \
                      contact, solved in closed form by the dynamic stage): run `sawdrive \
                      dynamic` or `sawdrive run`"
                .into(),
        });
    }
    strip::run_static(scene, springs, cache_dir, with_fields, control)
}
