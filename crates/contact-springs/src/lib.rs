#![doc = include_str!("../README.md")]

pub mod effective_ratio;
mod error;
mod material;
mod springs;

pub use error::SpringError;
pub use material::Material;
pub use springs::{PostSprings, k_pn, k_pt, k_sn, k_st, post_springs, series};
