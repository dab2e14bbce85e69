//! Which lumped model ran: a leaf type, so that the integrator (whose `auto` step depends on
//! it) and the scene (which holds the integrator setting) do not import each other.

use serde::{Deserialize, Serialize};

/// The model that actually ran.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    /// Period-average of one post at imposed speed.
    PeriodicAverage,
    /// Transient of all phase groups.
    Transient,
}
