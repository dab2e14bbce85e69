//! Command-line arguments.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

/// Friction-drive simulator of a surface-acoustic-wave motor: contact springs, static FEM contact
/// (effective contact ratio η) and stick/slip dynamics.
#[derive(Debug, Parser)]
#[command(name = "sawdrive", version, about, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Print the embedded default scene (the paper's motor) as TOML, to start a scene from;
    /// with --resolve, print a scene resolved to SI units after --set overrides.
    Scene(SceneArgs),
    /// The four Johnson springs of one post and their series values.
    Springs(SpringsArgs),
    /// Mesh tools.
    #[command(subcommand)]
    Mesh(MeshCommand),
}

#[derive(Debug, Subcommand)]
pub enum MeshCommand {
    /// Node/element counts, physical groups, volume and element quality of an MSH 4.1 file.
    Info(MeshInfoArgs),
}

#[derive(Debug, Args)]
pub struct MeshInfoArgs {
    /// Gmsh MSH 4.1 file (ASCII or binary).
    pub file: PathBuf,
    /// Print JSON (SI units).
    #[arg(long)]
    pub json: bool,
}

/// A scene and its overrides, shared by every command that reads a scene.
#[derive(Debug, Args)]
pub struct SceneInput {
    /// Scene file (TOML); keys it omits come from the embedded default scene.
    pub scene: Option<PathBuf>,
    /// Override a scene key, e.g. --set preload=20N --set posts.count=50x50
    /// (short names: preload, load, friction, effective_ratio, mass).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub overrides: Vec<String>,
}

#[derive(Debug, Args)]
pub struct SceneArgs {
    /// Resolve the scene (default, SCENE file, --set) and print it in SI units.
    #[arg(long)]
    pub resolve: bool,
    #[command(flatten)]
    pub input: SceneInput,
    /// With --resolve: print JSON instead of TOML.
    #[arg(long, requires = "resolve")]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct SpringsArgs {
    /// Post diameter with its unit, e.g. 20um.
    #[arg(long, allow_hyphen_values = true)]
    pub diameter: String,
    /// Slider material: si or linbo3.
    #[arg(long, default_value = "si")]
    pub slider: String,
    /// Stator material: si or linbo3.
    #[arg(long, default_value = "linbo3")]
    pub stator: String,
    /// Print JSON (SI units, unit in each key).
    #[arg(long)]
    pub json: bool,
}
