//! The dynamic stage of a ball slider (`slider.shape = "ball"`): one steel ball on the stator's
//! wave through crate `ball-slider` — Hertz normal contact, Mindlin–Cattaneo partial slip with
//! the Mindlin–Deresiewicz memory (MDR/Iwan spring bed), the ball's dynamics on the Rayleigh wave
//! (docs/physics.md §4), its speed–thrust curve, stall thrust and no-load speed
//! (crates/ball-slider/README.md; Johnson 1985 §3.4, §7.2; Mindlin & Deresiewicz 1953; Popov &
//! Heß 2015). A ball has no post array and no static stage: `sawdrive static` refuses it, and
//! `sawdrive dynamic`/`run` write `dynamic.json` (the ball's result), `curve.csv` and the
//! speed–thrust chart.
//!
//! Energy balance: per curve point the crate's books close (power from the wave = friction +
//! mechanical output + change of stored energy; `max_energy_residual`). The wave's side
//! (`wave.attenuation`): the power the wave carries across the contact's width 2a is the ball's
//! P_in; with the energy-conserving wave on, every curve point is solved at the amplitude the
//! ball sees after drawing its power (`ball_slider::dynamics::attenuation`: midpoint rule,
//! P_out = P_in − stator power, so the books close exactly); `auto` turns it on when the
//! constant-amplitude ball draws more than 1 % of P_in at stall, as for the post array. The
//! 2a strip is the narrowest share of the beam (diffraction refills it behind a contact this
//! small), so the drop is an upper bound; the reason also gives the draw against the whole
//! beam, the lower bound. With the constant wave and a draw above 1 % a warning names
//! `wave.attenuation`. With a drive voltage the mechanical output is held against the power the
//! transducer launches ([`DriveFigures`]). Range of validity: the crate's (a point contact,
//! k·a ≪ 1; a continuous wave; one μ).

use std::path::{Path, PathBuf};
use std::time::Instant;

use ball_slider::{BallError, BallModel, BallResult, BallScene, WaveShare};
use charts::{Chart, Series, Style};
use serde::Serialize;
use stick_slip::{AttenuationSetting, Warning};

use super::attenuation::{WaveAttenuation, WaveBooks};
use super::coupled::DriveFigures;
use crate::output::io;
use crate::pipeline::PipelineError;
use crate::scene::Scene;

/// Fraction of the wave power across the contact's width above which the ball's draw makes the
/// constant amplitude doubtful (a warning when `wave.attenuation = "off"`): the 1 % of `auto`.
pub const BALL_DRAW_WARNING_FRACTION: f64 = 0.01;

/// What the ball's dynamic stage produced.
#[derive(Debug, Clone)]
pub struct BallStage {
    /// The ball model's input, built from the scene.
    pub scene: BallScene,
    /// Its result: curve, stall thrust, no-load speed, static contact, books.
    pub result: BallResult,
    /// The wave's side: the energy-conserving wave at the contact `on` or `off`, and why.
    pub wave: WaveAttenuation,
    /// The transducer's figures with a drive voltage.
    pub drive: Option<DriveFigures>,
    /// The scene's warnings, then the ball's.
    pub warnings: Vec<Warning>,
    /// Wall time of the ball model (s).
    pub wall_time_s: f64,
}

/// `dynamic.json` of a ball: `model = "ball"`, the ball's result, the wave's side, the drive.
#[derive(Debug, Serialize)]
struct BallJson<'a> {
    model: &'static str,
    model_reason: String,
    #[serde(flatten)]
    result: &'a BallResult,
    wave_attenuation: &'a str,
    wave_attenuation_reason: &'a str,
    /// Wave power across the contact's width (W).
    wave_power_in_w: f64,
    #[serde(flatten)]
    drive: Option<DriveFigures>,
    warnings: &'a [Warning],
    wall_time_s: f64,
}

/// Why the ball model runs.
pub(crate) const BALL_REASON: &str = "slider.shape = \"ball\": one Hertz contact with Mindlin–Cattaneo \
                           partial slip (crate ball-slider)";

impl BallStage {
    /// The JSON of `sawdrive dynamic --json` and `dynamic.json`; every curve point carries its
    /// wave books (`wave_power_in_w`, `wave_power_out_w`) beside its `stator_power_w`.
    pub fn json(&self) -> serde_json::Value {
        let mut value = serde_json::to_value(BallJson {
            model: "ball",
            model_reason: BALL_REASON.into(),
            result: &self.result,
            wave_attenuation: self.wave.state,
            wave_attenuation_reason: &self.wave.reason,
            wave_power_in_w: self.wave.power_in_w,
            drive: self.drive,
            warnings: &self.warnings,
            wall_time_s: self.wall_time_s,
        })
        .expect("the ball's JSON is plain numbers and text");
        if let Some(serde_json::Value::Array(points)) = value.get_mut("curve") {
            for (point, p) in points.iter_mut().zip(&self.result.curve) {
                let books = WaveBooks::of(self.wave.power_in_w, p.stator_power_w);
                if let serde_json::Value::Object(map) = point {
                    map.insert("wave_power_in_w".into(), books.wave_power_in_w.into());
                    map.insert("wave_power_out_w".into(), books.wave_power_out_w.into());
                }
            }
        }
        value
    }

    /// The curve in the post array's columns (`summary.json`, sweeps): output power = the
    /// ball's mechanical power, stick fraction = the fraction of the period in contact without
    /// gross slip.
    pub fn curve(&self) -> Vec<stick_slip::CurvePoint> {
        self.result
            .curve
            .iter()
            .map(|p| stick_slip::CurvePoint {
                speed_m_per_s: p.speed_m_per_s,
                thrust_n: p.thrust_n,
                output_power_w: p.mechanical_power_w,
                efficiency: p.efficiency,
                stick_fraction: stick_fraction(p),
            })
            .collect()
    }

    /// Stick fraction at stall (the first curve point); 0 when the ball is not driven.
    pub fn stick_fraction(&self) -> f64 {
        self.result.curve.first().map_or(0.0, stick_fraction)
    }
}

fn stick_fraction(p: &ball_slider::CurvePoint) -> f64 {
    (p.contact_fraction - p.gross_slip_fraction).max(0.0)
}

/// The scene key behind a field of the ball model's input.
fn scene_key(field: &str) -> &str {
    match field {
        "ball.diameter_m" => "slider.ball_diameter",
        "ball.material" => "slider.material",
        "ball.moving_mass_kg" => "slider.mass",
        "stator" => "stator.material",
        "friction_coefficient" => "friction.static",
        "friction.mu_kinetic" => "friction.kinetic",
        "preload_n" => "load.preload",
        "external_load_n" => "load.external",
        "numerics.steps_per_period" => "model.ball.steps_per_period",
        "numerics.curve_points" => "model.curve_points",
        "wave.decay_length_m" => "wave.decay_length",
        "wave.burst_periods" => "wave.burst_periods",
        other => other.strip_suffix("_m").unwrap_or(other),
    }
}

/// A ball-model error in the pipeline's form, naming the scene key of the field at fault.
fn ball_error(e: BallError) -> PipelineError {
    let key = match &e {
        BallError::InvalidParameter { field, .. }
        | BallError::Material { field, .. }
        | BallError::UnsupportedWave { field, .. } => Some(scene_key(field).to_owned()),
        _ => None,
    };
    PipelineError::Unsupported {
        stage: "dynamic (ball)",
        message: match key {
            Some(key) => format!("{key}: {e}"),
            None => {
                format!(
                    "{e} [scene: model.ball.steps_per_period, slider.ball_diameter, load.preload]"
                )
            }
        },
    }
}

/// The ball model's input for a ball `scene`: the motor's wave, stator, friction and load
/// (`BallScene::for_motor`), the scene's ball, and `model.ball.steps_per_period`,
/// `model.curve_points` as its numerics (absent: the crate's 128 and 21).
pub fn ball_scene(scene: &Scene) -> Result<BallScene, PipelineError> {
    let ball = scene
        .ball
        .clone()
        .ok_or_else(|| PipelineError::Unsupported {
            stage: "dynamic (ball)",
            message: "the scene's slider is the post array, not a ball (slider.shape)".into(),
        })?;
    let mut ball_scene = BallScene::for_motor(&scene.motor, ball).map_err(ball_error)?;
    let m = &scene.model;
    if let Some(steps) = m.steps_per_period {
        ball_scene.numerics.steps_per_period = steps as usize;
    }
    if let Some(points) = m.curve_points {
        ball_scene.numerics.curve_points = points as usize;
    }
    ball_scene.validate().map_err(ball_error)?;
    Ok(ball_scene)
}

/// Wave power across the contact's width 2a (W): the cut's power per beam width at the scene's
/// amplitude and frequency times min(2a, aperture).
fn wave_power_across_contact_w(scene: &Scene, contact_radius_m: f64) -> f64 {
    let wave = &scene.motor.wave;
    scene
        .crystal_wave
        .power_per_width_w_per_m(wave.normal_amplitude_m, wave.frequency_hz)
        * (2.0 * contact_radius_m).min(wave.aperture_m)
}

/// The wave's side of a ball run: the decision on the energy-conserving wave at the contact
/// and, when on, the ball scene's wave share. `auto` weighs the constant-amplitude ball's draw
/// at stall against the power across its contact, as the post array's `auto` does against the
/// power under the array; the reason also states the draw against the whole beam (the lower
/// bound of the effect, module docs).
fn wave_side(
    scene: &Scene,
    ball_scene: &BallScene,
) -> Result<(WaveAttenuation, Option<WaveShare>), PipelineError> {
    let model = BallModel::new(ball_scene).map_err(ball_error)?;
    let a = model
        .static_summary()
        .map_err(ball_error)?
        .hertz
        .contact_radius_m;
    let power_in_w = wave_power_across_contact_w(scene, a);
    let stall_draw_w = model
        .at_speed(model.stall_speed_m_per_s())
        .map_err(ball_error)?
        .stator_power_w;
    let (on, _) = scene.wave_attenuation.resolve(stall_draw_w, power_in_w);
    let beam_w = wave_power_across_contact_w(scene, f64::INFINITY);
    let setting = match scene.wave_attenuation {
        AttenuationSetting::Auto => format!(
            "auto ({} > {} of the power across the contact: {})",
            if on { "draw" } else { "no draw" },
            stick_slip::attenuation::AUTO_DRAW_FRACTION,
            if on { "on" } else { "off" }
        ),
        AttenuationSetting::On => "wave.attenuation = on".into(),
        AttenuationSetting::Off => "wave.attenuation = off".into(),
    };
    let reason = format!(
        "{setting}: the constant-amplitude ball draws {stall_draw_w:.4e} W at stall, {:.3e} of \
         the {power_in_w:.4e} W the wave carries across the contact's width 2a = {:.4e} m \
         ({:.3e} of the whole beam's {beam_w:.4e} W)",
        stall_draw_w / power_in_w,
        2.0 * a,
        stall_draw_w / beam_w
    );
    let wave = WaveAttenuation {
        state: if on { "on" } else { "off" },
        reason,
        power_in_w,
    };
    let share = on
        .then(|| WaveShare::new(power_in_w))
        .transpose()
        .map_err(ball_error)?;
    Ok((wave, share))
}

/// With the constant wave (`wave.attenuation = "off"`), the warning when the ball draws more
/// than [`BALL_DRAW_WARNING_FRACTION`] of the power across its contact along the curve.
fn constant_wave_warning(wave: &WaveAttenuation, result: &BallResult) -> Option<Warning> {
    let draw_w = result
        .curve
        .iter()
        .map(|p| p.stator_power_w)
        .fold(0.0, f64::max);
    let fraction = draw_w / wave.power_in_w;
    (!wave.on() && fraction > BALL_DRAW_WARNING_FRACTION).then(|| {
        Warning::new(
            "wave.attenuation",
            format!(
                "the ball draws {:.1} % of the wave power across its contact (more than {} %) \
                 with the constant amplitude: set wave.attenuation = \"auto\" or \"on\"",
                100.0 * fraction,
                100.0 * BALL_DRAW_WARNING_FRACTION
            ),
        )
    })
}

/// Run the ball model of a ball `scene`.
pub fn run_ball_stage(scene: &Scene) -> Result<BallStage, PipelineError> {
    let started = Instant::now();
    let mut ball_scene = ball_scene(scene)?;
    let (wave, share) = wave_side(scene, &ball_scene)?;
    ball_scene.wave_share = share;
    let result = ball_slider::solve(&ball_scene).map_err(ball_error)?;
    let mut warnings = scene.warnings.clone();
    warnings.extend(constant_wave_warning(&wave, &result));
    if !result.drives {
        warnings.push(Warning::new(
            "load.preload",
            format!(
                "the wave does not drive the ball (thrust at 0⁺ {:.4e} N): its static approach \
                 is {:.1} wave amplitudes; lower the preload or raise the amplitude",
                result.zero_speed_thrust_n, result.static_contact.approach_over_amplitude
            ),
        ));
    }
    if !result.all_steady {
        warnings.push(Warning::new(
            "model.ball.steps_per_period",
            "a free-ball check of the curve did not reach a steady speed",
        ));
    }
    let max_output_w = result.max_mechanical_power_w;
    let drive = DriveFigures::of(scene, max_output_w)?;
    Ok(BallStage {
        scene: ball_scene,
        result,
        wave,
        drive,
        warnings,
        wall_time_s: started.elapsed().as_secs_f64(),
    })
}

/// `curve.csv` of a ball: one row per curve point with its power books.
fn ball_curve_csv(result: &BallResult) -> String {
    let mut text = String::from(
        "speed_m_per_s,thrust_n,stator_power_w,friction_power_w,mechanical_power_w,efficiency,\
         contact_fraction,gross_slip_fraction,energy_residual\n",
    );
    for p in &result.curve {
        text.push_str(&format!(
            "{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}\n",
            p.speed_m_per_s,
            p.thrust_n,
            p.stator_power_w,
            p.friction_power_w,
            p.mechanical_power_w,
            p.efficiency,
            p.contact_fraction,
            p.gross_slip_fraction,
            p.energy_residual
        ));
    }
    text
}

/// Write `dynamic.json`, `curve.csv` and the speed–thrust chart of a ball run into `dir` (no
/// chart when the wave does not drive the ball: its curve is empty).
pub fn write_ball_stage_files(
    title: &str,
    stage: &BallStage,
    dir: &Path,
) -> Result<Vec<PathBuf>, PipelineError> {
    let json = dir.join("dynamic.json");
    std::fs::write(&json, serde_json::to_vec_pretty(&stage.json())?).map_err(io("write", &json))?;
    let csv = dir.join("curve.csv");
    std::fs::write(&csv, ball_curve_csv(&stage.result)).map_err(io("write", &csv))?;
    let mut files = vec![json, csv];
    if stage.result.curve.is_empty() {
        // The wave does not drive the ball (a warning says so): no curve to draw.
        return Ok(files);
    }
    let mut chart = Chart::new(
        format!("speed–thrust of {title}: ball slider"),
        "speed (m/s)",
        "thrust (N)",
    );
    let points = stage
        .result
        .curve
        .iter()
        .map(|p| (p.speed_m_per_s, p.thrust_n))
        .collect();
    chart
        .series
        .push(Series::new("ball", points, Style::LineMarkers));
    files.extend(charts::write_chart(&chart, &dir.join("speed_thrust"))?);
    Ok(files)
}
