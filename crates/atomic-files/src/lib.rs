#![doc = include_str!("../README.md")]

mod error;
mod process;
mod staged;
mod write;

pub use error::FileError;
pub use staged::{Recovery, StagedDir, recover};
pub use write::{write_atomically, write_atomically_via, write_atomically_with};
