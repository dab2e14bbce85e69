//! Coupled stick/slip dynamics of the slider's posts on the strip compliance (issue 14).
//!
//! The lumped model (`stick_slip`) replaces the elastic interaction of the posts through slider
//! and stator by N_eff = η·N independent Jenkins posts. This crate keeps the interaction: the
//! posts of the static stage's strip, with its condensed **normal and tangential** tip
//! compliances ([`static_contact::StripModel::tip_compliance`]: one FEM factorisation, the
//! half-space for the stator), unilateral contact and Coulomb friction (μ_s, μ_k) at every tip,
//! the travelling wave at each post's x, the rigid heavy slider at an imposed speed in its
//! periodic steady state, the preload balanced at every instant. See [`model`] for the
//! equations and the step, [`boxqp`] for the exact contact solver.
//!
//! **Cross terms dropped (Goodman's approximation).** The normal problem does not see the
//! tangential forces. Between the two elastic bodies the normal–tangential coupling is the
//! Dundurs mismatch β = 0.021 for Si (G = 66.5 GPa, ν = 0.22) on LiNbO3 (67 GPa, 0.25)
//! ([`static_contact::halfspace::dundurs_beta`]); the half-space cross terms between posts are
//! 2 % of the direct ones on the default strip. The slider FEM's own cross term is 0.035 of the direct
//! terms at its largest entry on the default 100-post Tet10 strip (0.33 on the short 10-post
//! test strip, whose body tilts under one post's tangential force against the clamped backing
//! 0.5 mm above the tips); it is dropped here, the main modelling limitation of this crate.
//!
//! **Quasi-static elasticity.** The posts' own resonances (20 µm post, 2 µm high: normal
//! ≈ 176 MHz, tangential ≈ 163 MHz, stick-slip README) are 17–18× the 9.61 MHz drive, so their
//! inertia changes the tip forces by ≈ (f/f_post)² ≈ 0.3 %. The slider body's collective
//! resonances (thickness shear of the 0.5 mm Si plate, c_s/4t ≈ 2.7 MHz) lie *below* the drive,
//! but the period-average net force on the body is constant and its fluctuating part is the
//! wave-scale pattern, which travels at c = 3979 m/s below the Si shear speed 5343 m/s, i.e.
//! an evanescent (subsonic) field whose quasi-static response is corrected by O((c/c_s)²):
//! the quasi-static body compliance is an approximation there, not an exact limit.

pub mod boxqp;
pub mod criterion;
mod error;
pub mod model;
pub mod result;
pub mod scene;

pub use criterion::{
    DEFAULT_AUTO_TOLERANCE, DynamicsChoice, LUMPED_ERROR_FACTOR, LumpedEvidence, ModelDecision,
    choose_model, lumped_error_estimate,
};
pub use error::{CoupledError, Result};
pub use model::{CoupledModel, CoupledPoint, PeriodState, PostHistories, PostMode};
pub use result::{CoupledResult, fit_eta_dyn, lumped_misfit, solve};
pub use scene::{CoupledScene, PreloadBalance, WaveDirection};
