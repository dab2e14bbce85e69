//! Design under scatter: the motor model the `design` crate's Monte Carlo and
//! optimiser run on ([`motor`]), the `[scatter]` section ([`scatter`]), `sawdrive uq` ([`uq`])
//! and `sawdrive design` ([`study`]).

pub mod motor;
pub mod scatter;
pub mod study;
pub mod uq;
