//! The validation study of `validation/ball-slider/`: the default ball's curve, the wave
//! amplitude sweep (5–40 nm), a preload sweep and a ball-size sweep at 20 nm, and the step and
//! spring-bed refinement of stall thrust and no-load speed. The example `ball_study` writes it
//! as JSON and draws its figures; `StudySize::Smoke` is the same study on a coarse grid for tests.

use serde::Serialize;

use crate::dynamics::{BallModel, BallResult, solve};
use crate::error::Result;
use crate::scene::BallScene;

/// How much of the study to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StudySize {
    /// The committed study.
    Full,
    /// Two amplitudes, two preloads, coarse numerics (for tests).
    Smoke,
}

/// One row of a sweep: the varied value and the curve's headline numbers.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepRow {
    /// The swept value (m for amplitude and diameter, N for preload).
    pub value: f64,
    /// The solved scene's result.
    pub result: BallResult,
}

/// Stall thrust and no-load speed at one refinement level.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RefinementRow {
    /// Steps per period or springs.
    pub level: usize,
    /// No-load speed (m/s).
    pub no_load_speed_m_per_s: f64,
    /// Stall thrust (N).
    pub stall_thrust_n: f64,
}

/// The study's results.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Study {
    /// The default scene.
    pub scene: BallScene,
    /// Its result.
    pub default: BallResult,
    /// Normal amplitude swept, A_t/A_n kept (value in m).
    pub amplitude_sweep: Vec<SweepRow>,
    /// Preload swept at 20 nm (value in N).
    pub preload_sweep: Vec<SweepRow>,
    /// Ball diameter swept at 20 nm and the default preload (value in m).
    pub diameter_sweep: Vec<SweepRow>,
    /// Steps per period refined (springs at the default).
    pub step_refinement: Vec<RefinementRow>,
    /// Springs refined (steps at the default).
    pub spring_refinement: Vec<RefinementRow>,
}

fn refine(scene: &BallScene, levels: &[usize], steps: bool) -> Result<Vec<RefinementRow>> {
    levels
        .iter()
        .map(|&level| {
            let mut s = scene.clone();
            if steps {
                s.numerics.steps_per_period = level;
            } else {
                s.numerics.springs = level;
            }
            let m = BallModel::new(&s)?;
            Ok(RefinementRow {
                level,
                no_load_speed_m_per_s: m.no_load_speed_m_per_s()?.unwrap_or(0.0),
                stall_thrust_n: m.thrust_n(m.stall_speed_m_per_s())?.max(0.0),
            })
        })
        .collect()
}

fn sweep(values: &[f64], make: impl Fn(f64) -> BallScene) -> Result<Vec<SweepRow>> {
    values
        .iter()
        .map(|&value| {
            Ok(SweepRow {
                value,
                result: solve(&make(value))?,
            })
        })
        .collect()
}

/// The swept values of one study size.
struct Grid {
    amplitudes: Vec<f64>,
    preloads: Vec<f64>,
    diameters: Vec<f64>,
    steps: Vec<usize>,
    springs: Vec<usize>,
}

/// Run the study.
pub fn run(size: StudySize) -> Result<Study> {
    let mut scene = BallScene::default_ball();
    let grid = match size {
        StudySize::Full => Grid {
            amplitudes: (1..=8).map(|i| 5e-9 * i as f64).collect(),
            preloads: vec![0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0],
            diameters: vec![0.5e-3, 1e-3, 2e-3, 4e-3],
            steps: vec![32, 64, 128, 256, 512, 2048],
            springs: vec![50, 100, 200, 400, 800, 1600],
        },
        StudySize::Smoke => {
            scene.numerics.curve_points = 3;
            scene.numerics.free_periods = 4;
            scene.numerics.steps_per_period = 32;
            scene.numerics.springs = 50;
            Grid {
                amplitudes: vec![10e-9, 20e-9],
                preloads: vec![0.02, 1.0],
                diameters: vec![2e-3],
                steps: vec![32, 64],
                springs: vec![25, 50],
            }
        }
    };
    let Grid {
        amplitudes,
        preloads,
        diameters,
        steps,
        springs,
    } = grid;
    let with = |f: &dyn Fn(&mut BallScene)| {
        let mut s = scene.clone();
        f(&mut s);
        s
    };
    Ok(Study {
        default: solve(&scene)?,
        amplitude_sweep: sweep(&amplitudes, |a| scene.clone().with_normal_amplitude(a))?,
        preload_sweep: sweep(&preloads, |p| with(&|s| s.preload_n = p))?,
        diameter_sweep: sweep(&diameters, |d| with(&|s| s.ball.diameter_m = d))?,
        step_refinement: refine(&scene, &steps, true)?,
        spring_refinement: refine(&scene, &springs, false)?,
        scene,
    })
}
