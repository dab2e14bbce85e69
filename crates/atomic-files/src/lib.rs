//! The one atomic file writer of the workspace.
//!
//! * [`write_atomically`], [`write_atomically_with`], [`write_atomically_via`]: one file is
//!   written to a temporary sibling (`.<name>.tmp-<pid>-<n>`), flushed to disk and renamed over
//!   the target. A failed or killed write never leaves a partial file under the target name.
//! * [`StagedDir`]: a results folder written into a hidden staging folder beside its destination
//!   and swapped in by [`StagedDir::commit`]. The swap is two renames (destination aside to
//!   `.<name>.previous-<pid>`, staging to destination); a process killed between them leaves the
//!   earlier results in the `.previous` folder, and the next [`StagedDir::create`] (or
//!   [`recover`]) for that destination moves them back and reports it ([`Recovery`]).
//!
//! Every error names the verb and the path ([`FileError`]).
//!
//! Range of validity: renames are atomic only within one file system, so temporary files and
//! staging folders are always siblings of their target. Orphans are recognised through `/proc`
//! (Linux); where there is no `/proc`, nothing is recovered or removed automatically.

mod error;
mod process;
mod staged;
mod write;

pub use error::FileError;
pub use staged::{Recovery, StagedDir, recover};
pub use write::{write_atomically, write_atomically_via, write_atomically_with};
