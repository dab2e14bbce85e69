#![doc = include_str!("../README.md")]

pub mod distribution;
mod error;
pub mod evaluator;
mod files;
pub mod optimise;
pub mod pareto;
pub mod scatter;
pub mod sensitivity;
pub mod stats;
pub mod study;
pub mod uq;

pub use distribution::{Distribution, ScatterInput, draw_inputs, sample_seed};
pub use error::{DesignError, Result, StudyError, invalid};
pub use evaluator::{
    CoupledCost, CurvePoint, EvaluationCost, Evaluator, Fidelity as ModelFidelity, ModelError,
    MotorOutputs, MotorSample, OUTPUT_NAMES, SceneFacts, VariableKind,
};
pub use optimise::{
    Evaluation, Fidelity, Objective, OptimiserSettings, Outcome, SearchResult, Sense, Variable,
    VariableSensitivity, local_sensitivity, multi_fidelity, optimise,
};
pub use pareto::pareto_front;
pub use sensitivity::{Sensitivity, rank_inputs, spearman};
pub use stats::{Band, Histogram, band, histogram, percentile};
