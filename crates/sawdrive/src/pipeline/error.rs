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
    /// Coupled dynamic model (issue 14).
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
}
