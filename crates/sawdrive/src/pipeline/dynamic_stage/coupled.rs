//! Dynamic stage with its model choice: the lumped model of N_eff = η·N independent
//! posts ([`run_dynamic`](super::run_dynamic)), the coupled model of the static strip's posts with their elastic
//! interaction (`coupled_dynamics`) — or of every post of the whole slider when the static
//! stage ran it (`static.model = "slider"`, [`super::whole_slider`]) — and `model.dynamics =
//! "auto"` between them by the criterion of validation/coupled-dynamics
//! (`coupled_dynamics::choose_model`, on the strip's or the whole slider's η fit misfit).
//!
//! The lumped model always runs: its no-load speed is the criterion's evidence, its scene the
//! base of η_dyn, and its estimated error ([`coupled_dynamics::lumped_error_estimate`]) goes
//! into every summary. The coupled model reuses the static stage's factorisation: the strip's
//! normal and tangential tip compliances come from the fresh analysis, or from the verified
//! cache `compliance-<geometry key>.json` beside the static report (no second FEM on a cached
//! run; one strip condensation when the entry is missing).

use std::path::{Path, PathBuf};

use charts::{Chart, Series, Style};

use coupled_dynamics::{
    CoupledModel, CoupledResult, CoupledScene, PostHistories, PostMode, PreloadBalance,
};
use nalgebra::DMatrix;
use serde::Serialize;
use stick_slip::{CurvePoint, DynamicResult, ModelKind, VerticalModel};

use super::attenuation::{self, WaveAttenuation, WaveBooks};
use super::lumped::{DynamicRun, write_history_charts};
use super::whole_slider;
pub use super::whole_slider::SliderCoupledFigures;
use crate::output::io;
use crate::pipeline::local_amplitude::LocalAmplitudeEta;
use crate::pipeline::{PipelineError, RunControl};
use crate::pipeline::{StaticOutcome, strip_tips};
use crate::scene::{DEFAULT_COUPLED_STEPS_PER_PERIOD, Scene};

/// What the dynamic stage produced.
#[derive(Debug, Clone)]
pub struct DynamicStage {
    /// The lumped run (always made: the criterion's evidence and η_dyn's base).
    pub lumped: DynamicRun,
    /// The coupled run, when that model was chosen.
    pub coupled: Option<CoupledResult>,
    /// Every strip post's forces and contact mode over one steady period of the coupled model,
    /// at half its no-load speed (with the coupled run).
    pub coupled_histories: Option<PostHistories>,
    /// Estimated relative error of the coupled run's time step (`step_error_estimate`).
    pub coupled_step_error_estimate: Option<f64>,
    /// Why this model runs (the `auto` decision, or the scene's choice).
    pub dynamics_reason: String,
    /// Estimated relative error of the lumped model at the static η against the coupled one
    /// (`None`: η was given, so there is no static fit to estimate it from).
    pub lumped_error_estimate: Option<f64>,
    /// The energy-conserving wave: on or off, why, and the wave power under the array.
    pub wave: WaveAttenuation,
    /// The wave's books of every point of [`Self::curve`], in its order.
    pub wave_books: Vec<WaveBooks>,
    /// The whole slider's η at the local amplitude of the energy-conserving wave, when the
    /// whole slider's static stage feeds a lumped model on it (the curve ran at its η).
    pub local_amplitude: Option<LocalAmplitudeEta>,
    /// The transducer's figures when the scene gives `wave.drive_voltage`.
    pub drive: Option<DriveFigures>,
    /// The whole slider's lattice and maps, when the coupled model ran on every post of it.
    pub coupled_slider: Option<SliderCoupledFigures>,
}

impl DynamicStage {
    /// Name of the model whose numbers are reported: `coupled`, `periodic-average` or
    /// `transient`.
    pub fn model_name(&self) -> &'static str {
        match (&self.coupled, self.lumped.result.model) {
            (Some(_), _) => "coupled",
            (None, ModelKind::PeriodicAverage) => "periodic-average",
            (None, ModelKind::Transient) => "transient",
        }
    }

    /// Stall thrust of the reported model (N).
    pub fn stall_thrust_n(&self) -> f64 {
        self.coupled
            .as_ref()
            .map_or(self.lumped.result.stall_thrust_n, |c| c.stall_thrust_n)
    }

    /// No-load speed of the reported model (m/s).
    pub fn no_load_speed_m_per_s(&self) -> f64 {
        self.coupled
            .as_ref()
            .map_or(self.lumped.result.no_load_speed_m_per_s, |c| {
                c.no_load_speed_m_per_s
            })
    }

    /// Largest efficiency of the reported model.
    pub fn efficiency(&self) -> f64 {
        self.coupled
            .as_ref()
            .map_or(self.lumped.result.efficiency, |c| c.efficiency)
    }

    /// Stick fraction at stall of the reported model.
    pub fn stick_fraction(&self) -> f64 {
        self.coupled
            .as_ref()
            .map_or(self.lumped.result.stick_fraction, |c| c.stick_fraction)
    }

    /// Speed–thrust curve of the reported model, in the lumped model's columns.
    pub fn curve(&self) -> Vec<CurvePoint> {
        match &self.coupled {
            None => self.lumped.result.curve.clone(),
            Some(c) => c
                .curve
                .iter()
                .map(|p| CurvePoint {
                    speed_m_per_s: p.speed_m_per_s,
                    thrust_n: p.thrust_n,
                    output_power_w: p.output_power_w,
                    efficiency: p.efficiency,
                    stick_fraction: p.stick_fraction,
                })
                .collect(),
        }
    }

    /// Why the reported model ran: the `auto` decision, then the lumped model's own choice.
    pub fn model_reason(&self) -> String {
        match &self.coupled {
            Some(_) => self.dynamics_reason.clone(),
            None => format!(
                "{}; {}",
                self.dynamics_reason, self.lumped.result.model_reason
            ),
        }
    }

    /// Estimated relative error of the model whose numbers are reported: the lumped model's
    /// against the coupled one, or the coupled run's time-step error.
    pub fn model_error_estimate(&self) -> Option<f64> {
        match &self.coupled {
            Some(_) => self.coupled_step_error_estimate,
            None => self.lumped_error_estimate,
        }
    }

    /// The JSON of `sawdrive dynamic --json`: the reported model's result with the choices,
    /// every curve point with its wave books (`stator_power_w`, `wave_power_in_w`,
    /// `wave_power_out_w`).
    pub fn json(&self) -> serde_json::Value {
        let mut value = serde_json::to_value(self.json_fields())
            .expect("the dynamic stage's JSON is plain numbers and text");
        if let Some(serde_json::Value::Array(points)) = value.get_mut("curve") {
            for (point, books) in points.iter_mut().zip(&self.wave_books) {
                if let serde_json::Value::Object(map) = point {
                    map.insert("stator_power_w".into(), books.stator_power_w.into());
                    map.insert("wave_power_in_w".into(), books.wave_power_in_w.into());
                    map.insert("wave_power_out_w".into(), books.wave_power_out_w.into());
                }
            }
        }
        value
    }

    /// The fields of [`Self::json`] before the curve's wave books.
    fn json_fields(&self) -> DynamicJson<'_> {
        DynamicJson {
            result: match &self.coupled {
                Some(c) => ResultRef::Coupled(c),
                None => ResultRef::Lumped(&self.lumped.result),
            },
            model_reason: self.coupled.as_ref().map(|_| self.dynamics_reason.as_str()),
            dynamics_reason: &self.dynamics_reason,
            lumped_error_estimate: self.lumped_error_estimate,
            model_error_estimate: self.model_error_estimate(),
            lumped: self
                .coupled
                .as_ref()
                .map(|_| LumpedFigures::of(&self.lumped.result)),
            wave_attenuation: self.wave.state,
            wave_attenuation_reason: &self.wave.reason,
            wave_power_in_w: self.wave.power_in_w,
            local_amplitude: self.local_amplitude.as_ref(),
            drive: self.drive,
            coupled_posts: self.coupled.as_ref().map(|c| c.posts),
            coupled_slider: self.coupled_slider.as_ref(),
        }
    }
}

/// From the electrical side (`wave.drive_voltage`): the normal amplitude the transducer
/// launches, its electrical input power and the motor's overall efficiency, the largest
/// mechanical output power along the speed–thrust curve over the electrical input. Books: the
/// output cannot exceed the acoustic power launched towards the slider (½ of the acoustic
/// power, ≤ ½P_in); a curve that does is refused, not reported.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DriveFigures {
    /// |u_z| the transducer launches (m): the scene's normal amplitude.
    pub normal_amplitude_m: f64,
    /// Electrical input power P_in = ½Re(V·I*) (W).
    pub electrical_power_w: f64,
    /// max over the curve of (thrust × speed) / P_in.
    pub overall_efficiency: f64,
}

impl DriveFigures {
    /// The figures of `scene` whose reported curve has the largest mechanical output
    /// `max_output_power_w` (W); `None` without a drive voltage.
    pub fn of(scene: &Scene, max_output_power_w: f64) -> Result<Option<Self>, PipelineError> {
        let Some(drive) = &scene.drive else {
            return Ok(None);
        };
        let launched_w = drive.acoustic_power_per_direction_w;
        if max_output_power_w > launched_w {
            return Err(PipelineError::Unsupported {
                stage: "dynamic",
                message: format!(
                    "the curve's mechanical output {max_output_power_w:.4e} W exceeds the \
                     {launched_w:.4e} W the transducer launches towards the slider: the \
                     constant-amplitude wave is asked for more power than it carries; set \
                     wave.attenuation = \"auto\" (nothing was written)"
                ),
            });
        }
        Ok(Some(Self {
            normal_amplitude_m: drive.normal_amplitude_m,
            electrical_power_w: drive.electrical_input_power_w,
            overall_efficiency: max_output_power_w / drive.electrical_input_power_w,
        }))
    }
}

/// `sawdrive dynamic --json`: the result of the model that ran (its own keys: `model`,
/// `stall_thrust_n`, `no_load_speed_m_per_s`, `curve`, …; the coupled model's
/// `energy_balance_residual`, `eta_dyn`), why it ran, and the lumped model's estimated error.
#[derive(Debug, Serialize)]
pub struct DynamicJson<'a> {
    #[serde(flatten)]
    result: ResultRef<'a>,
    /// A coupled run's reason (a lumped result carries its own `model_reason`).
    #[serde(skip_serializing_if = "Option::is_none")]
    model_reason: Option<&'a str>,
    dynamics_reason: &'a str,
    lumped_error_estimate: Option<f64>,
    /// [`DynamicStage::model_error_estimate`].
    model_error_estimate: Option<f64>,
    /// The lumped model's figures beside a coupled run (at the constant-amplitude wave).
    #[serde(skip_serializing_if = "Option::is_none")]
    lumped: Option<LumpedFigures>,
    /// `on` or `off`: whether the reported curve is the energy-conserving wave's.
    wave_attenuation: &'a str,
    /// Why (`wave.attenuation`, or the `auto` evidence).
    wave_attenuation_reason: &'a str,
    /// Wave power entering under the post array (W).
    wave_power_in_w: f64,
    /// The whole slider's η at the local amplitude (whole-slider static stage, lumped model,
    /// attenuation on).
    #[serde(skip_serializing_if = "Option::is_none")]
    local_amplitude: Option<&'a LocalAmplitudeEta>,
    /// `normal_amplitude_m`, `electrical_power_w`, `overall_efficiency` with a drive voltage.
    #[serde(flatten)]
    drive: Option<DriveFigures>,
    /// Posts the coupled model ran (the strip's row, or every post of the whole slider).
    #[serde(skip_serializing_if = "Option::is_none")]
    coupled_posts: Option<usize>,
    /// The whole slider's lattice (`posts_x`, `posts_y`), Dundurs' β and normal-grid time,
    /// when the coupled model ran on every post of it.
    #[serde(skip_serializing_if = "Option::is_none")]
    coupled_slider: Option<&'a SliderCoupledFigures>,
}

#[derive(Debug, Serialize)]
#[serde(untagged)]
enum ResultRef<'a> {
    Lumped(&'a DynamicResult),
    Coupled(&'a CoupledResult),
}

/// The lumped model's headline figures, reported beside a coupled run.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct LumpedFigures {
    pub model: ModelKind,
    pub stall_thrust_n: f64,
    pub no_load_speed_m_per_s: f64,
    pub efficiency: f64,
}

impl LumpedFigures {
    pub(crate) fn of(r: &DynamicResult) -> Self {
        Self {
            model: r.model,
            stall_thrust_n: r.stall_thrust_n,
            no_load_speed_m_per_s: r.no_load_speed_m_per_s,
            efficiency: r.efficiency,
        }
    }
}

/// Write the dynamic stage's files into `dir`, each once: `dynamic.json` ([`DynamicStage::json`])
/// and `curve.csv` of the model that ran, the speed–thrust chart (after a coupled run, the
/// coupled curve over the lumped one), the lumped run's history charts
/// ([`write_history_charts`]) and, after a coupled run, the coupled post histories.
pub fn write_dynamic_stage_files(
    title: &str,
    stage: &DynamicStage,
    dir: &Path,
) -> Result<Vec<PathBuf>, PipelineError> {
    let json = dir.join("dynamic.json");
    std::fs::write(&json, serde_json::to_vec_pretty(&stage.json())?).map_err(io("write", &json))?;
    let csv = dir.join("curve.csv");
    std::fs::write(&csv, stick_slip::curve_csv(&stage.curve())).map_err(io("write", &csv))?;
    let mut files = vec![json, csv];
    let stem = dir.join("speed_thrust");
    files.extend(match &stage.coupled {
        None => stick_slip::plots::write_speed_thrust_chart(&stage.lumped.result, &stem)?,
        Some(coupled) => charts::write_chart(
            &coupled_speed_thrust_chart(title, &stage.lumped.result, coupled),
            &stem,
        )?,
    });
    files.extend(write_history_charts(title, &stage.lumped, dir)?);
    if let Some(histories) = &stage.coupled_histories {
        let csv = dir.join("coupled_post_histories.csv");
        std::fs::write(&csv, histories_csv(histories)).map_err(io("write", &csv))?;
        files.push(csv);
        files.extend(charts::write_stacked(
            &histories_charts(title, histories),
            &dir.join("coupled_post_forces"),
        )?);
    }
    if let Some(slider) = &stage.coupled_slider {
        files.extend(whole_slider::write_maps(title, slider, dir)?);
    }
    Ok(files)
}

/// The speed–thrust chart after a coupled run: the coupled curve over the lumped one.
fn coupled_speed_thrust_chart(
    title: &str,
    lumped: &DynamicResult,
    coupled: &CoupledResult,
) -> Chart {
    let mut chart = stick_slip::plots::speed_thrust_chart(
        &format!("speed–thrust of {title}: coupled and lumped models"),
        &[("lumped, static η", lumped)],
    );
    let points = coupled
        .curve
        .iter()
        .map(|p| (p.speed_m_per_s, p.thrust_n))
        .collect();
    chart
        .series
        .insert(0, Series::new("coupled", points, Style::LineMarkers));
    chart
}

/// Posts drawn in the history charts: this many, spread along the strip.
const HISTORY_CHART_POSTS: usize = 4;

/// One row per sample and post: time, post index, forces (N), contact mode.
fn histories_csv(h: &PostHistories) -> String {
    let mut csv = String::from("time_s,post,normal_force_n,tangential_force_n,mode\n");
    for (k, t) in h.time_s.iter().enumerate() {
        for (i, (n, f)) in h.normal_force_n[k]
            .iter()
            .zip(&h.tangential_force_n[k])
            .enumerate()
        {
            let mode = match h.mode[k][i] {
                PostMode::Separated => "separated",
                PostMode::Stick => "stick",
                PostMode::Slip => "slip",
            };
            csv.push_str(&format!("{t:e},{i},{n:e},{f:e},{mode}\n"));
        }
    }
    csv
}

/// Normal (top) and tangential (bottom) force against time (ns) of a few posts along the strip.
fn histories_charts(title: &str, h: &PostHistories) -> [Chart; 2] {
    let posts = h.normal_force_n.first().map_or(0, Vec::len);
    let shown: Vec<usize> = (0..HISTORY_CHART_POSTS.min(posts))
        .map(|k| k * posts / HISTORY_CHART_POSTS.min(posts))
        .collect();
    let panel = |what: &str, values: &[Vec<f64>]| {
        let mut chart = Chart::new(
            format!(
                "{title}: coupled model, {what} at {:.3} m/s",
                h.speed_m_per_s
            ),
            "time (ns)",
            format!("{what} (N)"),
        );
        for &i in &shown {
            let points = h
                .time_s
                .iter()
                .zip(values)
                .map(|(t, v)| (t * 1e9, v[i]))
                .collect();
            chart
                .series
                .push(Series::new(format!("post {i}"), points, Style::Line));
        }
        chart
    };
    [
        panel("normal force", &h.normal_force_n),
        panel("tangential force", &h.tangential_force_n),
    ]
}

/// What the coupled branch of the dynamic stage hands on (empty after a lumped run).
pub(super) struct CoupledOutcome {
    pub(super) result: Option<CoupledResult>,
    pub(super) histories: Option<PostHistories>,
    pub(super) step_error: Option<f64>,
    pub(super) wave: WaveAttenuation,
    pub(super) books: Vec<WaveBooks>,
    pub(super) slider: Option<SliderCoupledFigures>,
}

impl CoupledOutcome {
    pub(super) fn lumped(wave: WaveAttenuation, books: Vec<WaveBooks>) -> Self {
        Self {
            result: None,
            histories: None,
            step_error: None,
            wave,
            books,
            slider: None,
        }
    }
}

/// The scene's own warnings lead the coupled model's, as they lead the lumped one's.
fn prepend_scene_warnings(scene: &Scene, result: &mut CoupledResult) {
    let scene_warnings = scene
        .warnings
        .iter()
        .map(|w| format!("{}: {}", w.parameter, w.message));
    result.warnings.splice(0..0, scene_warnings);
}

/// The wave's books of every point of a coupled curve: P_out as the energy-conserving wave gave
/// it (`out`), else P_in − the stator power the posts draw.
fn coupled_books(
    result: &CoupledResult,
    out: &[Option<f64>],
    wave: &WaveAttenuation,
) -> Vec<WaveBooks> {
    result
        .curve
        .iter()
        .zip(out)
        .map(|(p, out)| WaveBooks {
            stator_power_w: p.stator_power_w,
            wave_power_in_w: wave.power_in_w,
            wave_power_out_w: out.unwrap_or(wave.power_in_w - p.stator_power_w),
        })
        .collect()
}

/// The coupled model of the static strip's row (with the energy-conserving wave when it is on).
pub(super) fn strip_coupled(
    scene: &Scene,
    statics: &StaticOutcome,
    lumped: &DynamicRun,
    cache_dir: Option<&Path>,
    control: &RunControl,
) -> Result<CoupledOutcome, PipelineError> {
    let mut run = run_coupled_model(scene, statics, lumped, cache_dir)?;
    prepend_scene_warnings(scene, &mut run.result);
    let stall_draw_w = run.result.curve.first().map_or(0.0, |p| p.stator_power_w);
    let wave = attenuation::decide(scene, stall_draw_w)?;
    if wave.on() {
        PipelineError::check(control, "dynamic (energy-conserving wave)")?;
        attenuate_coupled(&mut run, wave.power_in_w)?;
    }
    let books = coupled_books(&run.result, &run.books, &wave);
    Ok(CoupledOutcome {
        result: Some(run.result),
        histories: Some(run.histories),
        step_error: run.step_error,
        wave,
        books,
        slider: None,
    })
}

/// The coupled model of every post of the whole slider (with the energy-conserving wave when
/// it is on).
pub(super) fn slider_coupled(
    scene: &Scene,
    stage: &crate::pipeline::SliderStage,
    lumped: &DynamicRun,
    control: &RunControl,
) -> Result<CoupledOutcome, PipelineError> {
    let whole_slider::SliderRun {
        result: run,
        wave,
        wave_power_out_w,
    } = whole_slider::run(scene, stage, lumped, control)?;
    let mut result = run.coupled;
    prepend_scene_warnings(scene, &mut result);
    let books = coupled_books(&result, &wave_power_out_w, &wave);
    Ok(CoupledOutcome {
        result: Some(result),
        histories: Some(run.histories),
        step_error: None,
        wave,
        books,
        slider: Some(SliderCoupledFigures {
            posts_x: run.posts_x,
            posts_y: run.posts_y,
            dundurs_beta: run.dundurs_beta,
            normal_grid_wall_s: run.normal_grid_wall_s,
            maps: run.maps,
        }),
    })
}

/// A coupled run: its result, post histories, step-error estimate, the coupled scene it ran
/// and, per curve point, the wave power leaving (with the energy-conserving wave).
struct CoupledRun {
    result: CoupledResult,
    histories: PostHistories,
    step_error: Option<f64>,
    scene: CoupledScene,
    books: Vec<Option<f64>>,
}

/// Replace a constant-amplitude coupled run by the energy-conserving wave's
/// (`coupled_dynamics::solve_attenuated_with_histories`, P_in `power_in_w`, the no-load search
/// from the constant wave's no-load speed): stall, no-load speed, curve, efficiency and stick
/// fraction at the self-consistent profiles, the post histories at the profile of their own
/// speed (started from the converged curve point nearest it). η_dyn (the lumped model's fit to
/// the coupled curve) and the time-step error estimate stay the constant wave's: they describe
/// the contact's mechanics, which the amplitude profile does not change, and say so in a
/// warning.
fn attenuate_coupled(run: &mut CoupledRun, power_in_w: f64) -> Result<(), PipelineError> {
    let started = std::time::Instant::now();
    let mut options = coupled_dynamics::AttenuationOptions::new(power_in_w);
    options.no_load_guess_m_per_s = Some(run.result.no_load_speed_m_per_s);
    let (curve, _, histories) = coupled_dynamics::solve_attenuated_with_histories(
        &run.scene,
        &options,
        HISTORY_SPEED_FRACTION,
    )?;
    run.books = super::attenuation::take_attenuated_curve(&mut run.result, &curve);
    let r = &mut run.result;
    r.wall_time_s += started.elapsed().as_secs_f64();
    r.warnings.push(format!(
        "energy-conserving wave: {} fixed-point iterations at most per point, books closed to \
         {:.1e} of P_in; eta_dyn and the step-error estimate are the constant-amplitude wave's",
        curve.max_iterations, curve.max_balance_residual
    ));
    run.histories = histories;
    Ok(())
}

/// Fraction of the coupled no-load speed at which the post histories are taken.
const HISTORY_SPEED_FRACTION: f64 = 0.5;

/// The coupled model on the static strip's compliance, with η_dyn against the lumped scene, and
/// the post histories at [`HISTORY_SPEED_FRACTION`] of its no-load speed.
fn run_coupled_model(
    scene: &Scene,
    statics: &StaticOutcome,
    lumped: &DynamicRun,
    cache_dir: Option<&Path>,
) -> Result<CoupledRun, PipelineError> {
    if let VerticalModel::Dynamic { .. } = scene.model.vertical {
        return Err(PipelineError::Unsupported {
            stage: "dynamic",
            message:
                "model.lumped.vertical = \"dynamic\": the coupled model balances the preload at \
                      every instant (a quasi-static slider); use vertical = \"quasi-static\""
                    .into(),
        });
    }
    let tips = strip_tips(scene, statics, cache_dir)?;
    let motor = &scene.motor;
    let mut coupled = CoupledScene::independent_posts(
        motor.wave.clone(),
        tips.post_x_m.clone(),
        1.0,
        1.0,
        motor.friction.mu_static,
        motor.friction.mu_kinetic,
        motor.load.preload_n,
    );
    let n = tips.post_x_m.len();
    coupled.normal_compliance_m_per_n = DMatrix::from_vec(n, n, tips.normal_m_per_n);
    coupled.tangential_compliance_m_per_n = DMatrix::from_vec(n, n, tips.tangential_m_per_n);
    coupled.strip_share = tips.strip_share;
    coupled.preload_balance = PreloadBalance::Instant;
    coupled.steps_per_period = scene
        .model
        .steps_per_period
        .unwrap_or(DEFAULT_COUPLED_STEPS_PER_PERIOD) as usize;
    if let Some(points) = scene.model.curve_points {
        coupled.curve_points = points as usize;
    }
    coupled.validate()?;
    let model = CoupledModel::new(&coupled)?;
    let result = coupled_dynamics::solve(&model, Some(&lumped.scene))?;
    let speed = HISTORY_SPEED_FRACTION * result.no_load_speed_m_per_s;
    // The histories' steady solve and the coarse-step solves are independent: run side by side.
    let (histories, coarse) = rayon::join(
        || model.post_histories(speed),
        || coarse_step_thrusts(&coupled, &result, speed),
    );
    let (fine_at_speed, histories) = histories?;
    let step_error = coarse?.map(|[stall_2h, at_speed_2h]| {
        step_error_estimate(
            [result.stall_thrust_n, fine_at_speed.thrust_n],
            [stall_2h, at_speed_2h],
            result.stall_thrust_n,
        )
    });
    Ok(CoupledRun {
        books: vec![None; result.curve.len()],
        result,
        histories,
        step_error,
        scene: coupled,
    })
}

/// Observed order p of the coupled model's step error (validation/coupled-dynamics,
/// work-precision: ≈ 1.8 from T/32 to T/512 on the default slider).
const COUPLED_STEP_ORDER: f64 = 1.8;

/// The thrust at stall and at `speed` with twice the step of `scene`; `None` when half the
/// steps would not resolve a contact arc or the slider is locked.
fn coarse_step_thrusts(
    scene: &CoupledScene,
    result: &CoupledResult,
    speed: f64,
) -> Result<Option<[f64; 2]>, PipelineError> {
    let half = scene.steps_per_period / 2;
    if half < coupled_dynamics::scene::MIN_STEPS_PER_PERIOD || result.stall_thrust_n <= 0.0 {
        return Ok(None);
    }
    let mut coarse_scene = scene.clone();
    coarse_scene.steps_per_period = half;
    let coarse = CoupledModel::new(&coarse_scene)?;
    let (stall, at_speed) = rayon::join(|| coarse.at_speed(0.0), || coarse.at_speed(speed));
    Ok(Some([stall?.thrust_n, at_speed?.thrust_n]))
}

/// Richardson estimate of the coupled run's relative step error from the thrusts at stall and at
/// half the no-load speed with the run's step h (`fine`) and with 2h (`coarse`):
/// |F_h − F_2h| / (2^p − 1), the larger of the two, relative to the stall thrust.
fn step_error_estimate(fine: [f64; 2], coarse: [f64; 2], stall_thrust_n: f64) -> f64 {
    let largest = (0..2)
        .map(|i| (fine[i] - coarse[i]).abs())
        .fold(0.0, f64::max);
    largest / (2f64.powf(COUPLED_STEP_ORDER) - 1.0) / stall_thrust_n
}
