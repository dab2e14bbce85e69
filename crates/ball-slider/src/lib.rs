#![doc = include_str!("../README.md")]

pub mod dynamics;
mod error;
pub mod hertz;
pub mod iwan;
pub mod mindlin;
pub mod quadrature;
mod scene;
pub mod study;

pub use dynamics::{
    BallModel, BallResult, CurvePoint, FreeCheck, MAX_RESONANCE_STEP, SpeedPoint, StaticSummary,
    WaveShare, solve,
};
pub use error::{BallError, Result};
pub use hertz::HertzContact;
pub use iwan::{BedStep, SpringBed};
pub use mindlin::MindlinContact;
pub use scene::{
    BallScene, BallSlider, DEFAULT_BALL_DIAMETER_M, DEFAULT_PRELOAD_N, Numerics,
    STEEL_DENSITY_KG_PER_M3, STEEL_POISSON_RATIO, STEEL_YOUNGS_MODULUS_PA, bearing_steel,
};
