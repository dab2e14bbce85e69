#![doc = include_str!("../README.md")]

mod error;
mod name;
mod process;
mod read;
mod staged;
mod write;

pub use error::{FileError, InputProblem};
pub use name::{MAX_NAME_BYTES, NameError, check_name};
pub use read::{MAX_SETTINGS_FILE_BYTES, read_input, read_input_text};
pub use staged::{RESULT_MARKER, Recovery, StagedDir, recover, result_kind};
pub use write::{write_atomically, write_atomically_via, write_atomically_with};
