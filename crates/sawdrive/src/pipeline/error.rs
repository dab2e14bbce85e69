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
    #[error("dynamic stage: {error}{hint}", error = .0, hint = dynamic_hint(matches!(.0, stick_slip::StickSlipError::NotConverged { .. })))]
    Dynamic(#[from] stick_slip::StickSlipError),
    /// Coupled dynamic model.
    #[error("dynamic stage (coupled model): {error}{hint}", error = .0, hint = coupled_hint(matches!(.0, coupled_dynamics::CoupledError::NotConverged { .. })))]
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
    /// The caller asked the run to stop (its [`RunControl`](run_control::RunControl)) before the stage started.
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

    /// `Err(Cancelled { stage })` if the caller asked `control` to stop.
    pub(crate) fn check(
        control: &run_control::RunControl,
        stage: &'static str,
    ) -> Result<(), Self> {
        match control.should_stop() {
            true => Err(PipelineError::Cancelled { stage }),
            false => Ok(()),
        }
    }
}

/// The scene keys that set a lumped model's iterations, named when one did not converge.
fn dynamic_hint(not_converged: bool) -> &'static str {
    if not_converged {
        "; the scene keys that set it: model.lumped.integrator, model.lumped.time_step, model.transient.periods, model.dynamics (e.g. \"periodic-average\")"
    } else {
        ""
    }
}

/// The scene keys that set the coupled model's contact solves, named when one did not converge.
fn coupled_hint(not_converged: bool) -> &'static str {
    if not_converged {
        "; the scene keys that set it: model.coupled.steps_per_period, static.tolerance, model.dynamics (a lumped model)"
    } else {
        ""
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dynamic_model_that_did_not_converge_names_the_scene_keys_that_set_it() {
        let lumped = PipelineError::Dynamic(stick_slip::StickSlipError::NotConverged {
            model: "transient",
            what: "periodic steady state",
            iterations: 50,
            residual: 1e-3,
        });
        assert!(
            lumped.to_string().contains("model.lumped.time_step"),
            "{lumped}"
        );
        let other = PipelineError::Dynamic(stick_slip::StickSlipError::ModelNotApplicable {
            model: "periodic-average",
            reason: "a burst".into(),
        });
        assert!(!other.to_string().contains("scene keys"), "{other}");
    }
}
