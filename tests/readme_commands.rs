//! The README's shell examples are real command lines: every `sawdrive …` line in a ```sh block
//! parses with the command line's own definition (`sawdrive_cli::cli::Cli`).

use clap::Parser;
use sawdrive_cli::cli::Cli;

const README: &str = include_str!("../README.md");

/// The `sawdrive` command lines of the README's ```sh blocks (comments after `#` dropped).
fn readme_command_lines() -> Vec<String> {
    let mut lines = Vec::new();
    let mut in_sh_block = false;
    for line in README.lines() {
        let trimmed = line.trim();
        if trimmed.starts_with("```") {
            in_sh_block = !in_sh_block && trimmed == "```sh";
            continue;
        }
        let command = trimmed.split(" #").next().unwrap_or_default().trim();
        if in_sh_block && command.starts_with("sawdrive ") {
            lines.push(command.to_owned());
        }
    }
    lines
}

/// Split a command line at spaces, honouring "double" and 'single' quotes.
fn shell_words(line: &str) -> Vec<String> {
    let (mut words, mut word, mut quote, mut started) = (Vec::new(), String::new(), None, false);
    for c in line.chars() {
        match (quote, c) {
            (None, '"' | '\'') => (quote, started) = (Some(c), true),
            (Some(q), c) if c == q => quote = None,
            (None, ' ') if started => {
                words.push(std::mem::take(&mut word));
                started = false;
            }
            (None, ' ') => {}
            (_, c) => {
                word.push(c);
                started = true;
            }
        }
    }
    if started {
        words.push(word);
    }
    words
}

#[test]
fn every_sawdrive_line_of_the_readme_parses() {
    let lines = readme_command_lines();
    assert!(lines.len() >= 4, "README shell examples found: {lines:?}");
    for line in &lines {
        if let Err(error) = Cli::try_parse_from(shell_words(line)) {
            panic!("README command `{line}` does not parse:\n{error}");
        }
    }
}

#[test]
fn a_misspelt_command_line_is_caught() {
    assert_eq!(
        shell_words("sawdrive run 'a b' --set x=\"1 N\""),
        ["sawdrive", "run", "a b", "--set", "x=1 N"]
    );
    assert!(Cli::try_parse_from(shell_words("sawdrive run --jbos 2")).is_err());
}
