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
    /// Cache folder for generated meshes and gmsh scripts (default: $SAWDRIVE_CACHE, else
    /// $XDG_CACHE_HOME/sawdrive, else $HOME/.cache/sawdrive). The FEM result cache of a run
    /// stays in OUT/.cache.
    #[arg(long, global = true, value_name = "DIR")]
    pub cache: Option<PathBuf>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Print the embedded default scene (the paper's motor) as TOML, to start a scene from;
    /// with --resolve, print a scene resolved to SI units after --set overrides.
    Scene(SceneArgs),
    /// The four Johnson springs of one post and their series values.
    Springs(SpringsArgs),
    /// The Rayleigh wave of the stator's crystal cut: velocities (free, metallized), coupling
    /// K², |u_x/u_z|, and the power it carries at the scene's amplitude and frequency.
    Wave(WaveArgs),
    /// Mesh tools.
    #[command(subcommand)]
    Mesh(MeshCommand),
    /// Static FEM contact of the slider on the stator: post forces and the effective contact
    /// ratio η. Writes OUT/<scene>/static/.
    Static(StageArgs),
    /// Dynamic stick/slip model: speed–thrust curve, stall thrust, no-load speed, efficiency.
    /// Uses the scene's η, or runs the static stage when effective_ratio = "fem".
    /// Writes OUT/<scene>/dynamic/.
    Dynamic(StageArgs),
    /// The whole pipeline (springs → static → η → dynamic) into OUT/<scene>/.
    Run(StageArgs),
    /// Run a sweep file: a grid of scene overrides, in parallel, resumable.
    Sweep(SweepArgs),
    /// Validation studies: `validate <case> --level smoke|quick|full`, `validate all`,
    /// `validate --list`. A failing check exits non-zero naming it.
    Validate(ValidateArgs),
    /// Monte Carlo bands of η, speed, thrust and power under the scene's [scatter] section.
    /// Writes OUT/<scene>-uq/.
    Uq(UqArgs),
    /// Optimise a texture (DESIGN.toml: variables, constraints, objective). Writes OUT/<name>/.
    Design(DesignArgs),
}

#[derive(Debug, Args)]
pub struct UqArgs {
    #[command(flatten)]
    pub input: SceneInput,
    /// Monte Carlo samples (≥ 1).
    #[arg(long)]
    pub samples: usize,
    /// Seed (same seed: bitwise-identical results).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Results folder; writes OUT/<scene>-uq/ (samples kept in OUT/.uq-samples/ for resume).
    #[arg(long = "out", default_value = "out", value_name = "DIR")]
    pub out: PathBuf,
    /// Static model: 8-row patch of the lattice instead of the whole slider (≈ 10× cheaper).
    #[arg(long)]
    pub patch: bool,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct DesignArgs {
    /// Design file (TOML).
    pub design: PathBuf,
    /// Results folder; writes OUT/<name>/.
    #[arg(long = "out", default_value = "out", value_name = "DIR")]
    pub out: PathBuf,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Options of the commands that run a stage on a scene.
#[derive(Debug, Args)]
pub struct StageArgs {
    #[command(flatten)]
    pub input: SceneInput,
    /// Results folder; each scene writes OUT/<scene name>/.
    #[arg(long = "out", default_value = "out", value_name = "DIR")]
    pub out: PathBuf,
    /// Print the result as JSON on stdout (no progress display).
    #[arg(long)]
    pub json: bool,
    /// Do not read or write the FEM result cache (OUT/.cache).
    #[arg(long)]
    pub no_cache: bool,
}

#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Sweep file (TOML).
    pub sweep: PathBuf,
    /// Results folder; the sweep writes OUT/<sweep name>/.
    #[arg(long = "out", default_value = "out", value_name = "DIR")]
    pub out: PathBuf,
    /// Parallel jobs, 1 to 256 (default: all cores).
    #[arg(long, conflicts_with = "merge")]
    pub jobs: Option<usize>,
    /// Print the results table as JSON on stdout (with --shard: this shard's rows).
    #[arg(long)]
    pub json: bool,
    /// Run only shard K of N (1-based): points K, K+N, K+2N, … in sweep order. The shard that
    /// saves the last point writes results.csv and the charts. For job arrays on a cluster.
    #[arg(long, value_name = "K/N", conflicts_with = "merge")]
    pub shard: Option<sawdrive::sweep::Shard>,
    /// Run no point: collect the points saved by all shards into results.csv and the charts
    /// (refused, naming the missing points, until every point is saved).
    #[arg(long)]
    pub merge: bool,
}

#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// The case to run (`--list` names them), or `all`.
    #[arg(required_unless_present = "list", value_name = "CASE")]
    pub case: Option<String>,
    /// Study size: smoke (seconds; all cases ≤ 3 min), quick (every code path of full on smaller
    /// meshes, ≤ 5 min per case on 2 cores), full (the committed study).
    #[arg(long, default_value = "full", value_parser = ["smoke", "quick", "full"])]
    pub level: String,
    /// Output folder of one case's charts and results; with `all`, each case writes OUT/<case>/
    /// [default: out/validation/<case>].
    #[arg(long = "out", value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print the checks as JSON: {"checks": [{"case", "quantity", "value", "reference",
    /// "tolerance", "pass", "source", "rule"}, …], "skipped": […]}.
    #[arg(long)]
    pub json: bool,
    /// Name every case and what it validates.
    #[arg(long)]
    pub list: bool,
    /// Write the Markdown table of every check of the run into FILE, keeping the sections of
    /// the cases not run [default: validation/SUMMARY.md].
    #[arg(long, value_name = "FILE", num_args = 0..=1, default_missing_value = "validation/SUMMARY.md")]
    pub summary: Option<PathBuf>,
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
pub struct WaveArgs {
    #[command(flatten)]
    pub input: SceneInput,
    /// Crystal cut, instead of the scene's stator.cut: 128yx-linbo3, yz-linbo3 or st-x-quartz.
    #[arg(long, value_name = "CUT")]
    pub cut: Option<String>,
    /// Print JSON (SI units, unit in each key).
    #[arg(long)]
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
