#![doc = include_str!("../README.md")]

/// The command line's arguments (clap), here so that tests and docs can parse command lines
/// (the README's examples are checked by `tests/readme_commands.rs`). Its doc comments are the
/// help text of the command line (`OUT/<scene>/`, `[scatter]`), plain text rather than Markdown.
#[allow(rustdoc::invalid_html_tags, rustdoc::broken_intra_doc_links)]
pub mod cli;
pub mod commands;
pub mod progress;
