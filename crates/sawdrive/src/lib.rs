//! sawdrive: the SAW-motor friction-drive simulator's scene files, pipeline and command line.
//!
//! The physics lives in the member crates: `contact-springs` (Johnson springs), `gmsh-mesh`,
//! `elastic-fem`, `static-contact` (η) and `stick-slip` (dynamics). This crate reads scenes
//! ([`scene`]), converts human units ([`units`]) and drives the stages.

pub mod output;
pub mod pipeline;
pub mod scene;
pub mod sweep;
pub mod units;
