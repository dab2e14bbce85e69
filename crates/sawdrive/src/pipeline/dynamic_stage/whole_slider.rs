//! The coupled model of every post of the whole slider in the dynamic stage
//! (`static.model = "slider"` with `model.dynamics = "coupled"`, or `auto` when the lumped
//! model's estimated error exceeds its tolerance): `coupled_dynamics::SliderDynamics` on the
//! static stage's own slider — the same parameters ([`slider_params`]: lattice, imperfections,
//! preload mechanism, the near field calibrated on the strip FEM, the scene's static
//! tolerance), so the normal contact of every grid phase is the static stage's solve — with the
//! tangential lattice operator (Cerruti half-space terms of both bodies, the bonded layer's
//! correction) on Johnson's tangential near field 1/k_pt (not calibrated on the strip FEM).
//!
//! Outputs beyond the strip's coupled run: the 2D maps of time-mean normal force, slip fraction
//! and friction power per post at half the no-load speed (SVG, and every post's means at
//! stall and at half the no-load speed as CSV); the post histories are the middle row's.
//!
//! Not modelled here, and refused or stated rather than ignored: the energy-conserving wave
//! (`wave.attenuation = "on"` is refused; `auto` keeps the constant-amplitude wave and says
//! so), the slider's vertical dynamics (`model.lumped.vertical = "dynamic"` refused, as for the
//! strip), the time-step error estimate (not made: it would cost a second normal grid and two
//! steady solves of every post).

use std::path::{Path, PathBuf};

use coupled_dynamics::slider::MAP_FIELDS;
use coupled_dynamics::{CoupledError, SliderDynamics, SliderDynamicsResult, SliderScene};
use serde::Serialize;
use slider_contact::{NearField, SliderModel};
use stick_slip::{AttenuationSetting, VerticalModel};

use super::attenuation::{self, WaveAttenuation};
use super::lumped::DynamicRun;
use crate::output::io;
use crate::pipeline::{PipelineError, SliderStage, slider_params};
use crate::scene::{DEFAULT_COUPLED_STEPS_PER_PERIOD, Scene};

/// The whole slider's figures beside its coupled result: lattice, maps, normal grid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SliderCoupledFigures {
    /// Posts along x.
    pub posts_x: usize,
    /// Posts along y.
    pub posts_y: usize,
    /// Dundurs' β of the bodies (the normal–tangential coupling dropped).
    pub dundurs_beta: Option<f64>,
    /// Wall time of the normal solves on the phase grid (s).
    pub normal_grid_wall_s: f64,
    /// Maps at stall and at half the no-load speed.
    #[serde(skip)]
    pub maps: Vec<coupled_dynamics::SliderMaps>,
}

/// Refuses, before anything runs, what the whole slider's coupled model cannot honour: the
/// energy-conserving wave asked for by `wave.attenuation = "on"` and the slider's vertical
/// dynamics.
pub(super) fn check_scene(scene: &Scene) -> Result<(), PipelineError> {
    if scene.wave_attenuation == AttenuationSetting::On {
        return Err(PipelineError::Unsupported {
            stage: "dynamic",
            message: "wave.attenuation = \"on\": the whole slider's coupled model \
                      (static.model = \"slider\") runs on the constant-amplitude wave (the local \
                      amplitude of every post is not modelled for it); set wave.attenuation = \
                      \"off\" or \"auto\", static.model = \"strip\", or a lumped model.dynamics"
                .into(),
        });
    }
    if let VerticalModel::Dynamic { .. } = scene.model.vertical {
        return Err(PipelineError::Unsupported {
            stage: "dynamic",
            message: "model.lumped.vertical = \"dynamic\": the coupled model balances the preload \
                      at every instant (a quasi-static slider); use vertical = \"quasi-static\""
                .into(),
        });
    }
    Ok(())
}

/// The whole slider's scene of `scene` on `static_model`: the motor's wave and friction, the
/// scene's `model.coupled.steps_per_period` (auto 64) and `model.curve_points` (auto
/// [`coupled_dynamics::slider::DEFAULT_SLIDER_CURVE_POINTS`]).
fn slider_scene(scene: &Scene, static_model: &SliderModel) -> SliderScene {
    let motor = &scene.motor;
    let mut s = SliderScene::for_static(
        static_model,
        motor.wave.clone(),
        motor.friction.mu_static,
        motor.friction.mu_kinetic,
    );
    s.steps_per_period = scene
        .model
        .steps_per_period
        .unwrap_or(DEFAULT_COUPLED_STEPS_PER_PERIOD) as usize;
    if let Some(points) = scene.model.curve_points {
        s.curve_points = points as usize;
    }
    s
}

/// Runs the whole slider's coupled model of `scene` on the static stage's slider `stage`, with
/// η_dyn against the lumped scene.
pub(super) fn run(
    scene: &Scene,
    stage: &SliderStage,
    lumped: &DynamicRun,
) -> Result<SliderDynamicsResult, PipelineError> {
    check_scene(scene)?;
    let started = std::time::Instant::now();
    let params = slider_params(scene, &stage.near_field);
    let static_model = SliderModel::build(&params).map_err(CoupledError::from)?;
    let dynamics = SliderDynamics::for_slider(
        &slider_scene(scene, &static_model),
        &static_model,
        NearField::Johnson,
    )?;
    // The lumped model's no-load speed at the static η predicts the coupled one within its
    // estimated error (a few per cent): the search starts there.
    let guess = Some(lumped.result.no_load_speed_m_per_s).filter(|v| *v > 0.0);
    let mut result = dynamics.solve_from_guess(Some(&lumped.scene), guess)?;
    result.coupled.wall_time_s = started.elapsed().as_secs_f64();
    result.coupled.warnings.push(
        "whole slider: the tangential near field is Johnson's 1/k_pt (the normal one is \
         calibrated on the strip FEM); no time-step error estimate is made"
            .into(),
    );
    Ok(result)
}

/// The energy-conserving wave's decision for the whole slider's coupled run drawing
/// `stall_draw_w` (W) at stall: `off` as the setting says; `auto` keeps the constant-amplitude
/// wave and says so when the draw would have turned it on (`on` was refused by
/// [`check_scene`]).
pub(super) fn wave_decision(
    scene: &Scene,
    stall_draw_w: f64,
) -> Result<WaveAttenuation, PipelineError> {
    let decided = attenuation::decide(scene, stall_draw_w)?;
    if !decided.on() {
        return Ok(decided);
    }
    Ok(WaveAttenuation {
        state: "off",
        reason: format!(
            "{}; but the whole slider's coupled model keeps the constant-amplitude wave (the \
             local amplitude of every post is not modelled for it): the curve is the constant \
             wave's",
            decided.reason
        ),
        power_in_w: decided.power_in_w,
    })
}

/// Writes the maps of a whole-slider coupled run into `dir`: `coupled_map_<field>.svg` of the
/// time-mean normal force, slip fraction and friction power per post at half the no-load speed,
/// and `coupled_post_means_stall.csv`, `coupled_post_means_half_no_load.csv` (every post's
/// time means).
pub(super) fn write_maps(
    title: &str,
    figures: &SliderCoupledFigures,
    dir: &Path,
) -> Result<Vec<PathBuf>, PipelineError> {
    let mut files = Vec::new();
    for (maps, tag) in figures.maps.iter().zip(["stall", "half_no_load"]) {
        let csv = dir.join(format!("coupled_post_means_{tag}.csv"));
        std::fs::write(&csv, maps.csv()).map_err(io("write", &csv))?;
        files.push(csv);
    }
    let Some(half) = figures.maps.get(1) else {
        return Ok(files);
    };
    for (name, unit) in MAP_FIELDS {
        let field = half.field(name).unwrap_or_default();
        let caption = format!(
            "{title}: {} per post at {:.3} m/s (half the no-load speed)",
            name.replace('_', " "),
            half.means.speed_m_per_s
        );
        let svg = dir.join(format!("coupled_map_{name}.svg"));
        std::fs::write(&svg, half.svg(field, &caption, unit)).map_err(io("write", &svg))?;
        files.push(svg);
    }
    Ok(files)
}
