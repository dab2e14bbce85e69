//! One module per subcommand.

mod design;
mod dynamic;
mod mesh;
mod run;
mod scene;
mod springs;
mod statics;
mod sweep;
mod uq;
mod validate;
mod wave;

use crate::cli::{Cli, Command, MeshCommand};

/// Run the parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Scene(args) => scene::run(&args),
        Command::Springs(args) => springs::run(&args),
        Command::Wave(args) => wave::run(&args),
        Command::Mesh(MeshCommand::Info(args)) => mesh::info(&args),
        Command::Static(args) => statics::run(&args),
        Command::Dynamic(args) => dynamic::run(&args),
        Command::Run(args) => run::run(&args),
        Command::Sweep(args) => sweep::run(&args),
        Command::Validate(args) => validate::run(&args),
        Command::Uq(args) => uq::run(&args),
        Command::Design(args) => design::run(&args),
    }
}
