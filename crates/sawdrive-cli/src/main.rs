//! The `sawdrive` command line.

use sawdrive_cli::{cli, commands};

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    if let Some(dir) = &cli.cache {
        gmsh_mesh::cache::set_cache_dir(dir.clone());
    }
    quiet_on_broken_pipe_panics();
    match catch_unwind(AssertUnwindSafe(|| commands::run(cli))) {
        Ok(Ok(())) => ExitCode::SUCCESS,
        // The reader of stdout went away (`sawdrive mesh info FILE | head -1`): nothing left
        // to tell, and the results folder is complete.
        Ok(Err(error)) if is_broken_pipe(&error) => ExitCode::SUCCESS,
        Ok(Err(error)) => {
            eprintln!("error: {}", error_chain(&error));
            ExitCode::FAILURE
        }
        Err(payload) if is_broken_pipe_panic(payload.as_ref()) => ExitCode::SUCCESS,
        Err(payload) => resume_unwind(payload),
    }
}

/// Whether `error` comes from writing to a closed pipe (EPIPE).
fn is_broken_pipe(error: &anyhow::Error) -> bool {
    error.chain().any(|cause| {
        cause
            .downcast_ref::<std::io::Error>()
            .is_some_and(|e| e.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Whether a panic is `println!` failing on a closed stdout (commands that print with
/// `println!` rather than `writeln!`).
fn is_broken_pipe_panic(payload: &(dyn Any + Send)) -> bool {
    let message = payload
        .downcast_ref::<String>()
        .map(String::as_str)
        .or_else(|| payload.downcast_ref::<&str>().copied())
        .unwrap_or_default();
    message.contains("failed printing to stdout") && message.contains("Broken pipe")
}

/// Keep the default panic message for every panic but a closed stdout's.
fn quiet_on_broken_pipe_panics() {
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if !is_broken_pipe_panic(info.payload()) {
            default_hook(info);
        }
    }));
}

/// One line: the error and its causes, joined by ": ", control bytes escaped. A cause whose
/// text its parent's message already contains (errors that print their source) is not repeated.
fn error_chain(error: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in error.chain().map(ToString::to_string) {
        if line.contains(&cause) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&cause);
    }
    // Messages may quote bytes of input files: never pass terminal escapes through.
    gmsh_mesh::escape_control(&line.replace('\n', " "))
}
