//! End-to-end tests of the `sawdrive` command line live in `tests/e2e_*.rs` of this package.
