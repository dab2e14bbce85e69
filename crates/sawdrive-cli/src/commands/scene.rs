//! `sawdrive scene`: print the default scene, or a resolved one.

use anyhow::Context;
use sawdrive::scene::{DEFAULT_SCENE_TOML, load_scene};

use crate::cli::SceneArgs;

pub fn run(args: &SceneArgs) -> anyhow::Result<()> {
    if !args.resolve {
        print!("{DEFAULT_SCENE_TOML}");
        return Ok(());
    }
    let scene = load_scene(args.input.scene.as_deref(), &args.input.overrides)?;
    let text = if args.json {
        serde_json::to_string_pretty(&scene)?
    } else {
        toml::to_string_pretty(&scene).context("formatting the resolved scene")?
    };
    println!("{text}");
    Ok(())
}
