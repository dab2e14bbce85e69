/// Why a pipeline stage failed; each names the stage.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The scene cannot be mapped onto a stage's model.
    #[error("{stage} stage: {message}")]
    Unsupported {
        /// Stage name.
        stage: &'static str,
        /// What is not supported and what to do.
        message: String,
    },
    /// Johnson springs.
    #[error("springs: {0}")]
    Springs(#[from] contact_springs::SpringError),
    /// Static FEM contact.
    #[error("static stage: {0}")]
    Static(#[from] static_contact::ContactError),
    /// The contact solver stopped within the scene's limits.
    #[error(
        "static stage: {source}; the limits are static.max_iterations = {max_iterations} and \
         static.tolerance = {tolerance:e} (raise the one or loosen the other)"
    )]
    StaticNotConverged {
        /// The solver's error.
        #[source]
        source: static_contact::ContactError,
        /// `static.max_iterations`.
        max_iterations: usize,
        /// `static.tolerance`.
        tolerance: f64,
    },
    /// Dynamic model.
    #[error("dynamic stage: {0}")]
    Dynamic(#[from] stick_slip::StickSlipError),
    /// Coupled dynamic model.
    #[error("dynamic stage (coupled model): {0}")]
    Coupled(#[from] coupled_dynamics::CoupledError),
    /// Writing results.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    /// Charts.
    #[error("chart: {0}")]
    Chart(#[from] charts::ChartError),
    /// JSON.
    #[error("json: {0}")]
    Json(#[from] serde_json::Error),
    /// The caller asked the run to stop (its `should_stop` hook) before the stage started.
    #[error("{stage} stage: cancelled")]
    Cancelled {
        /// The stage that did not start.
        stage: &'static str,
    },
}

impl PipelineError {
    /// Whether the run stopped because its caller asked it to (between stages, or inside the
    /// static contact solves or the dynamic curve), not because of bad input or a failure.
    pub fn is_cancelled(&self) -> bool {
        matches!(
            self,
            PipelineError::Cancelled { .. }
                | PipelineError::Static(static_contact::ContactError::Cancelled { .. })
                | PipelineError::Dynamic(stick_slip::StickSlipError::Cancelled { .. })
        )
    }

    /// `Err(Cancelled { stage })` if `should_stop()` says so.
    pub(crate) fn check(should_stop: ShouldStop<'_>, stage: &'static str) -> Result<(), Self> {
        match should_stop() {
            true => Err(PipelineError::Cancelled { stage }),
            false => Ok(()),
        }
    }
}

/// The caller's stop request, asked between the stages and inside them (before each static
/// contact solve, each dynamic curve point): the library crates' hook
/// ([`stick_slip::ShouldStop`], [`static_contact::ShouldStop`]).
pub type ShouldStop<'a> = &'a (dyn Fn() -> bool + Sync);
