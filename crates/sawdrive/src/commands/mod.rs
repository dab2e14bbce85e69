//! One module per subcommand.

mod mesh;
mod scene;
mod springs;

use crate::cli::{Cli, Command, MeshCommand};

/// Run the parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Scene(args) => scene::run(&args),
        Command::Springs(args) => springs::run(&args),
        Command::Mesh(MeshCommand::Info(args)) => mesh::info(&args),
    }
}
