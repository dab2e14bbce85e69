#![doc = include_str!("../README.md")]

pub mod distribution;
mod error;
pub mod optimise;
pub mod pareto;
pub mod sensitivity;
pub mod stats;

pub use distribution::{Distribution, ScatterInput, draw_inputs, sample_seed};
pub use error::{DesignError, Result, invalid};
pub use optimise::{
    Evaluation, Fidelity, Objective, OptimiserSettings, Outcome, SearchResult, Sense, Variable,
    VariableSensitivity, local_sensitivity, multi_fidelity, optimise,
};
pub use pareto::pareto_front;
pub use sensitivity::{Sensitivity, rank_inputs, spearman};
pub use stats::{Band, Histogram, band, histogram, percentile};
