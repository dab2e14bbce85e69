//! The pipeline through the library, stage by stage: scene → springs → η (static FEM) → speed–
//! thrust curve. Runs in seconds on the small committed-mesh scene (no gmsh needed); `cargo test
//! -p sawdrive --example pipeline` runs it as a test.
//!
//! ```sh
//! cargo run -p sawdrive --example pipeline [SCENE.toml]
//! ```
use sawdrive::pipeline::{RunControl, run_dynamic, run_static, scene_springs};
use sawdrive::scene::load_scene;
use stick_slip::CurvePoint;

const SMALL_SCENE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tests/scenes/small-strip.toml"
);

fn speed_thrust_curve(scene_file: &str) -> anyhow::Result<Vec<CurvePoint>> {
    let scene = load_scene(Some(scene_file.as_ref()), &[])?;
    let springs = scene_springs(&scene)?;
    println!(
        "k_n = {:.4e} N/m, k_t = {:.4e} N/m",
        springs.k_n_n_per_m, springs.k_t_n_per_m
    );
    // RunControl::none(): this caller never stops a stage and shows no progress.
    let eta = run_static(&scene, &springs, None, false, &RunControl::none())?
        .effective_ratio
        .ok_or_else(|| anyhow::anyhow!("η is not identifiable for scene {}", scene.name))?;
    println!("η = {eta:.4}");
    Ok(run_dynamic(&scene, &springs, eta, &RunControl::none())?
        .result
        .curve)
}

fn main() -> anyhow::Result<()> {
    let scene_file = std::env::args()
        .nth(1)
        .unwrap_or_else(|| SMALL_SCENE.to_owned());
    println!("speed_m_per_s,thrust_n");
    for point in speed_thrust_curve(&scene_file)? {
        println!("{},{}", point.speed_m_per_s, point.thrust_n);
    }
    Ok(())
}

#[test]
fn pipeline_example_gives_a_falling_speed_thrust_curve_for_the_small_scene() {
    let curve = speed_thrust_curve(SMALL_SCENE).unwrap();
    let (first, last) = (curve.first().unwrap(), curve.last().unwrap());
    assert!(
        first.thrust_n > 0.0,
        "stall thrust positive: {} N",
        first.thrust_n
    );
    assert!(
        last.speed_m_per_s > first.speed_m_per_s && last.thrust_n < first.thrust_n,
        "thrust falls with speed"
    );
}
