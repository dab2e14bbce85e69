//! Design under scatter: the motor model the `design` crate's Monte Carlo and
//! optimiser run on ([`motor`](crate::design::motor)), the `[scatter]` section
//! ([`scatter`](crate::design::scatter)), `sawdrive uq` ([`uq`](crate::design::uq)) and
//! `sawdrive design` ([`study`](crate::design::study)).

pub mod motor;
pub mod scatter;
pub mod study;
pub mod uq;
