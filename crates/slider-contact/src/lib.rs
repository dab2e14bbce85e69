//! Whole-slider static contact on the post lattice (issue 13). The physics — the two-scale split
//! and the scale each part resolves, the preload mechanisms, the imperfections, the constrained CG
//! and its stopping rule, the checks — is docs/physics.md §9.
//!
//! All N posts of the slider, frictionless and unilateral, under load control by the preload P:
//! a two-scale compliance operator ([`lattice`]: each post's near field + the lattice far field
//! through the stator half-space and the slider body bonded to a rigid back, applied by FFT,
//! [`layer`] for the body's Fourier-space influence function) and a constrained
//! conjugate-gradient solver ([`solver`], Polonsky & Keer 1999) → post forces and gaps per phase
//! of the frozen wave → η (docs/physics.md §6), load sharing, contact fraction ([`slider`]).
//! Imperfections of a real slider (height scatter, height map, tilt, bow): [`heights`].
//! Preload mechanisms ([`Mechanism`]): a rigid back, or a free back under a pressure or a ball,
//! whose bending is a Kirchhoff plate of the slider outline ([`plate`]) and whose post forces
//! balance the preload and its moments ([`balanced`]).
//!
//! ```
//! use slider_contact::{CgOptions, SliderParams, run};
//! // A 12 × 12 post corner of the default slider, 2 phases, 0.5 N, solved to 1e-9.
//! let params = SliderParams {
//!     posts_x: 12,
//!     posts_y: 12,
//!     slider_length_m: 12.0 * 40e-6,
//!     slider_width_m: 12.0 * 40e-6,
//!     preload_n: 0.5,
//!     phases: 2,
//!     solver: CgOptions { tolerance: 1e-9, ..CgOptions::default() },
//!     ..SliderParams::default()
//! };
//! let report = run(&params).unwrap();
//! assert_eq!(report.model, "slider");
//! assert!((report.post_forces_n.iter().sum::<f64>() - 0.5).abs() < 1e-9);
//! assert!(report.complementarity_residual < 1e-8);
//! ```

pub mod balanced;
pub mod bessel;
pub mod calibration;
mod error;
pub mod heights;
pub mod lattice;
pub mod layer;
pub mod plate;
pub mod precondition;
pub mod rng;
pub mod slider;
pub mod solver;

pub use balanced::BalancedCg;
pub use calibration::{NearFieldCalibration, calibrate_near_field};
pub use error::{Result, SliderError};
pub use heights::{HeightMap, HeightMapCsv, Imperfections, ImperfectionsExt};
pub use lattice::{
    ComplianceOperator, DiagonalParts, LatticeGeometry, LatticeKernel, LatticeOperator, NearField,
    OperatorSpec,
};
pub use plate::FreePlate;
pub use precondition::{ContactPreconditioner, PlatePreconditioner};
pub use slider::{
    FreeBack, Mechanism, MechanismExt, SliderModel, SliderParams, SliderReport, SliderSnapshot, run,
};
pub use solver::{CgOptions, CgSolution, ConstrainedCg, DEFAULT_TOLERANCE};
