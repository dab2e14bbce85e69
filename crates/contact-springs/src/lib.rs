//! Materials and the contact springs of one post of a SAW-motor slider.
//!
//! A post is a rigid flat punch of radius `a`, bonded to the silicon slider it is etched from and
//! touching the LiNbO3 stator through a frictional interface. Its compliance is four half-space
//! springs (K. L. Johnson, *Contact Mechanics*, CUP 1985; the SAW-motor model of Shigematsu &
//! Kurosawa, eqs (1)–(4)); see `docs/physics.md` §3 for the binding definitions.
//!
//! | spring | formula | boundary condition on r < a |
//! |---|---|---|
//! | [`k_pn`] | 4 G a · ln(3−4ν)/(1−2ν) | bonded normal |
//! | [`k_pt`] | G a / (1/8 + (1−2ν)/(8πκ)), κ = ln(3−4ν)/π | bonded tangential |
//! | [`k_sn`] | 4 G a/(1−ν) = 2E*a | frictionless normal |
//! | [`k_st`] | 8 G a/(2−ν) | tangential, normal displacement free |
//!
//! ```
//! use contact_springs::{post_springs, Material};
//! let springs = post_springs(&Material::silicon(), &Material::lithium_niobate(), 10e-6).unwrap();
//! assert!((springs.k_n_n_per_m / 1.8e6 - 1.0).abs() < 0.05); // ≈ 1.8·10⁶ N/m for d = 20 µm
//! ```

pub mod effective_ratio;
mod error;
mod material;
mod springs;

pub use error::SpringError;
pub use material::Material;
pub use springs::{PostSprings, k_pn, k_pt, k_sn, k_st, post_springs, series};
