#![doc = include_str!("../README.md")]

mod boundary;
mod cut;
mod error;
pub mod idt;
mod material;
pub mod materials;
mod mode;
pub mod rotation;
mod search;
mod stroh;
mod wave;

pub use cut::Cut;
pub use error::{Surface, WaveError};
pub use idt::{ElectrodeMetal, Idt, IdtResponse, IdtSubstrate, Metallisation};
pub use material::{Material, VACUUM_PERMITTIVITY_F_PER_M};
pub use mode::{DepthSample, Fields, PartialWave, PowerFlux, SurfaceMode};
pub use rotation::EulerAngles;
pub use stroh::C64;
pub use wave::RayleighWave;
