//! Design under fabrication scatter (issue 15): the model-independent half.
//!
//! * [`distribution`]: stated input distributions (fixed, normal, uniform, truncated normal),
//!   drawn from the workspace's one seeded generator (`slider_contact::rng::SplitMix64`), one
//!   generator per sample so results are bitwise reproducible and independent of thread count.
//! * [`stats`]: mean, percentiles (Hyndman–Fan type 7) with distribution-free order-statistic
//!   confidence intervals, histograms; a [`stats::Band`] per output.
//! * [`sensitivity`]: Spearman rank correlation of each input with each output, ranked.
//! * [`optimise`]: bounded variables, named constraints, Latin-hypercube pre-search and
//!   Nelder–Mead in the unit box; [`optimise::multi_fidelity`] searches with a cheap model and
//!   confirms finalists with the full one, tagging every number with its fidelity.
//! * [`pareto`]: the non-dominated set of (thrust, speed)-like pairs.
//!
//! The motor model itself (scene → η → speed–thrust curve) is plugged in by the caller
//! (`sawdrive::design`), so everything here is tested on closed-form toy models.

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
