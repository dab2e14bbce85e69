#![doc = include_str!("../README.md")]

pub mod balanced;
pub mod bessel;
pub mod calibration;
mod error;
pub mod heights;
pub mod lattice;
pub mod layer;
pub mod plate;
pub mod precondition;
pub mod slider;
pub mod solver;
pub mod tangential;
pub mod tangential_mirror;

pub use balanced::BalancedCg;
pub use calibration::{
    NearFieldCalibration, calibrate_near_field, calibrate_tangential_near_field,
};
pub use error::{Result, SliderError};
pub use heights::{HeightMap, HeightMapCsv, Imperfections, ImperfectionsExt};
pub use lattice::{
    ComplianceOperator, DiagonalParts, LatticeGeometry, LatticeKernel, LatticeOperator, NearField,
    OperatorSpec, Precision,
};
pub use plate::FreePlate;
pub use precondition::{ContactPreconditioner, PlatePreconditioner};
pub use slider::{
    FreeBack, Mechanism, MechanismExt, SliderModel, SliderParams, SliderReport, SliderSnapshot, run,
};
pub use solver::{CgOptions, CgSolution, ConstrainedCg, DEFAULT_TOLERANCE};
pub use tangential::{
    NEGLIGIBLE_DUNDURS_BETA, TangentialKernel, coupling_negligible, dundurs_beta,
};
