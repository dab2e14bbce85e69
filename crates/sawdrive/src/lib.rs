#![doc = include_str!("../README.md")]

/// Version of the dynamic (stick/slip) numbers a run produces. Bump when the dynamic numbers
/// change (integrators, model selection, period average, defaults they depend on): resumed sweeps
/// then recompute their saved points instead of reusing stale ones. The static stage has its own
/// (`static_contact::params::MODEL_VERSION`, also part of the sweep point hash).
pub const DYNAMIC_MODEL_VERSION: u32 = 1;

pub mod output;
pub mod pipeline;
pub mod scene;
pub mod sweep;
pub mod units;
