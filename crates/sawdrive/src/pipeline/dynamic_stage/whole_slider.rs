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
//! The energy-conserving wave (`wave.attenuation = "on"`, or `auto` when the constant wave's
//! posts would draw more than the wave carries): the constant wave's stall point decides
//! `auto`; then, side by side, the constant-amplitude curve (η_dyn stays the constant wave's, as
//! on the strip) and every curve point, the maps and the histories at their self-consistent
//! profiles, each post at its local amplitude (`SliderDynamics::solve_attenuated`: one lane of
//! the wave's power per lattice row).
//!
//! Not modelled here, and refused or stated rather than ignored: the slider's vertical
//! dynamics (`model.lumped.vertical = "dynamic"` refused, as for the strip), the time-step
//! error estimate (not made: it would cost a second normal grid and two steady solves of every
//! post).
//!
//! The studies' curves ([`study_curve`]: stall, no-load speed and a few points of each
//! sample) follow the same wave decision, on each sample's own constant-wave stall draw, and
//! on the energy-conserving wave solve every speed's profile to self-consistency
//! (`coupled_dynamics::SliderProfiles`), started from the nominal sample's profiled states
//! with their secant differences ([`StudyWarmStart`]).

use std::path::{Path, PathBuf};

use coupled_dynamics::slider::{AMPLITUDE_FIELD, MAP_FIELDS};
use coupled_dynamics::{
    CoupledError, CoupledPoint, PeriodState, SliderDynamics, SliderDynamicsResult, SliderScene,
};
use serde::Serialize;
use slider_contact::{NearField, SliderModel};
use stick_slip::{AttenuationSetting, VerticalModel};

use super::attenuation::{self, WaveAttenuation};
use super::lumped::DynamicRun;
use crate::output::io;
use crate::pipeline::RunControl;
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
/// slider's vertical dynamics.
pub(crate) fn check_scene(scene: &Scene) -> Result<(), PipelineError> {
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

/// The whole slider's coupled run of the dynamic stage: its result, the wave's decision and,
/// per curve point, the wave power leaving (with the energy-conserving wave).
pub(super) struct SliderRun {
    pub(super) result: SliderDynamicsResult,
    pub(super) wave: WaveAttenuation,
    pub(super) wave_power_out_w: Vec<Option<f64>>,
}

/// Runs the whole slider's coupled model of `scene` on the static stage's slider `stage`, with
/// η_dyn against the lumped scene; on the energy-conserving wave when `wave.attenuation` asks
/// for it or `auto` finds the constant wave's stall draw above what the wave carries.
pub(super) fn run(
    scene: &Scene,
    stage: &SliderStage,
    lumped: &DynamicRun,
    control: &RunControl,
) -> Result<SliderRun, PipelineError> {
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
    // estimated error (a few per cent): both searches start there.
    let guess = Some(lumped.result.no_load_speed_m_per_s).filter(|v| *v > 0.0);
    // The constant wave's stall draw decides `auto` (the same steady period as the constant
    // curve's stall point, solved from rest); `off` needs no decision before the curve.
    let stall_draw_w = match scene.wave_attenuation {
        AttenuationSetting::Off => None,
        _ => Some(dynamics.model().at_speed_from(0.0, None)?.0.stator_power_w),
    };
    let wave = attenuation::decide(scene, stall_draw_w.unwrap_or(0.0))?;
    let constant = || dynamics.solve_from_guess(Some(&lumped.scene), guess);
    let (mut result, wave_power_out_w) = if wave.on() {
        PipelineError::check(control, "dynamic (whole slider, energy-conserving wave)")?;
        let mut options = coupled_dynamics::AttenuationOptions::new(wave.power_in_w);
        options.no_load_guess_m_per_s = guess;
        // The constant curve (η_dyn) and the attenuated one are independent: side by side.
        let (constant, attenuated) = rayon::join(constant, || {
            dynamics.solve_attenuated(&static_model, &options)
        });
        let mut result = constant?;
        let out = attenuate(&mut result, attenuated?);
        (result, out)
    } else {
        let result = constant()?;
        let out = vec![None; result.coupled.curve.len()];
        (result, out)
    };
    result.coupled.wall_time_s = started.elapsed().as_secs_f64();
    result.coupled.warnings.push(
        "whole slider: the tangential near field is Johnson's 1/k_pt (the normal one is \
         calibrated on the strip FEM); no time-step error estimate is made"
            .into(),
    );
    Ok(SliderRun {
        result,
        wave,
        wave_power_out_w,
    })
}

/// Replaces the constant-amplitude run's curve, stall, no-load speed, efficiency, stick
/// fraction, maps and histories by the energy-conserving wave's; η_dyn stays the constant
/// wave's (the contact's mechanics, which the profile does not change) and a warning says so.
/// Returns each curve point's wave power leaving.
fn attenuate(
    result: &mut SliderDynamicsResult,
    attenuated: coupled_dynamics::AttenuatedSlider,
) -> Vec<Option<f64>> {
    let curve = attenuated.curve;
    let out = super::attenuation::take_attenuated_curve(&mut result.coupled, &curve);
    let r = &mut result.coupled;
    r.warnings.push(format!(
        "energy-conserving wave on the whole slider (one lane of the wave's power per lattice \
         row): {} fixed-point iterations at most per point, {} normal grids solved, books \
         closed to {:.1e} of P_in; eta_dyn is the constant-amplitude wave's",
        curve.max_iterations, attenuated.normal_grids, curve.max_balance_residual
    ));
    result.maps = attenuated.maps;
    result.history_posts = attenuated.history_posts;
    result.histories = attenuated.histories;
    out
}

/// Writes the maps of a whole-slider coupled run into `dir`: `coupled_map_<field>.svg` of the
/// time-mean normal force, slip fraction and friction power per post at half the no-load speed
/// (and of the local wave amplitude `amplitude_scale` when the energy-conserving wave is on),
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
    let attenuated = half.amplitude_scale.iter().any(|a| *a != 1.0);
    let drawn = MAP_FIELDS
        .iter()
        .chain(attenuated.then_some(&AMPLITUDE_FIELD));
    for &(name, unit) in drawn {
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

/// Fractions of the no-load speed v₀ at which a study's coupled curve is solved when
/// `model.curve_points = "auto"`, besides the stall (0) and v₀ itself: the largest output
/// power lies near 0.6 v₀ and the largest efficiency near 0.9–0.95 v₀ on the whole slider's
/// concave curve (validation/whole-slider/dynamics), so the three points sit around and
/// between them; the maxima are read off the interpolants through all five points
/// ([`curve_maxima`]).
pub const STUDY_SPEED_FRACTIONS: [f64; 3] = [0.55, 0.75, 0.92];
/// Tolerance of a study's no-load speed (of the crest speed): bands of several per cent need
/// far less than the dynamic stage's 1e-7, and every secant step costs a steady solve of every
/// post. Default 1e-5.
pub const STUDY_SPEED_TOLERANCE: f64 = 1e-5;
/// Speeds of the grid on which the interpolants' maxima are searched. Default 801.
const MAXIMA_GRID: usize = 801;

/// The tangential lattice operator of a study's slider (Cerruti terms of both bodies, the
/// bonded layer's correction, Johnson's tangential near field), built once per operator
/// (lattice, bodies, post diameter) and shared by the samples that keep it.
#[derive(Clone)]
pub struct StudyTangential {
    spec: slider_contact::OperatorSpec,
    operator: std::sync::Arc<dyn coupled_dynamics::ComplianceProduct>,
}

impl std::fmt::Debug for StudyTangential {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StudyTangential")
            .field("spec", &self.spec)
            .finish_non_exhaustive()
    }
}

impl StudyTangential {
    /// The operator of `static_model`'s lattice and bodies.
    pub fn build(static_model: &SliderModel) -> Result<Self, PipelineError> {
        let spec = static_model.params.operator_spec();
        let operator = slider_contact::LatticeOperator::tangential(&spec, NearField::Johnson)
            .map_err(CoupledError::from)?;
        Ok(Self {
            spec,
            operator: std::sync::Arc::new(operator),
        })
    }
}

/// The periodic states of one coupled study curve, the warm start of the next sample's (same
/// lattice): the stall's, the no-load speed's and each curve point's, with the no-load speeds
/// of the coupled and the lumped model that predict the next sample's.
#[derive(Debug, Clone)]
pub struct StudyWarmStart {
    posts: usize,
    stall: StudyState,
    no_load: Option<StudyState>,
    points: Vec<StudyState>,
    /// Coupled over lumped no-load speed of the run that left these states.
    no_load_ratio: f64,
    /// The run's stall thrust (N), no-load speed (m/s) and thrust slope −dF/dv at v₀ (N s/m,
    /// the chord from the point below v₀): the next sample's first no-load speed and, where
    /// its curve ([`similar_no_load`]) gives none, its Newton step.
    stall_thrust_n: f64,
    no_load_m_per_s: f64,
    no_load_slope_n_s_per_m: f64,
    /// The run's solved points as (speed m/s, thrust N), speed ascending, the stall first and
    /// v₀'s last: the curve the next sample's is a scaled copy of ([`similar_no_load`]).
    curve: Vec<(f64, f64)>,
}

/// Where one study curve's wall time went (s).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct StudyTimes {
    /// The contact solves of the normal grid (every step's phase).
    pub normal_grid_s: f64,
    /// The stall point.
    pub stall_s: f64,
    /// The no-load search (with the curve points it solves as nodes of its root:
    /// `lower_points`).
    pub no_load_s: f64,
    /// The other points (the curve points the search did not solve).
    pub points_s: f64,
}

/// One sample's coupled curve for a study: stall thrust, no-load speed, largest output power
/// and efficiency, the solved points, the periods stepped and the states it ended in.
#[derive(Debug, Clone)]
pub struct StudyCurve {
    /// Stall thrust (N).
    pub stall_thrust_n: f64,
    /// No-load speed (m/s).
    pub no_load_speed_m_per_s: f64,
    /// Largest thrust × speed (W).
    pub max_output_power_w: f64,
    /// Largest efficiency.
    pub efficiency: f64,
    /// The solved points, speed ascending: the stall first, v₀'s last (the solved speed nearest
    /// v₀, its thrust within [`NO_LOAD_THRUST_TOLERANCE`] of the stall's).
    pub curve: Vec<CoupledPoint>,
    /// Wave periods stepped at every solved speed (the stall, the no-load search's, the
    /// points).
    pub periods: usize,
    /// Wall time (s) of the normal grid's contact solves, the stall, the no-load search and the
    /// other points.
    pub times_s: StudyTimes,
    /// The wave the curve ran on: the energy-conserving wave when `wave.attenuation` asks for
    /// it or `auto` finds the constant wave's stall draw above what the wave carries.
    pub wave: WaveAttenuation,
    /// The states the curve ended in (the next sample's warm start).
    pub warm: StudyWarmStart,
}

/// The coupled curve a study needs of one sample whose whole-slider static model is
/// `static_model` (the sample's offsets, preload and diameter; Johnson's near fields, as the
/// study's static model; steps solved to [`STUDY_STEP_TOLERANCE`]): the normal grid, the
/// stall, the no-load speed from the lumped model's `lumped_no_load_m_per_s` (scaled by the
/// warm start's coupled/lumped ratio) to [`STUDY_SPEED_TOLERANCE`] ([`no_load_search`]), then
/// the curve points downwards, every speed started from `warm` (the nominal sample's states)
/// where given, else from its neighbour. The wave is the dynamic stage's decision
/// (`wave.attenuation`; `auto` on the constant wave's stall draw against the power the wave
/// carries under the model's rows): on the energy-conserving wave every speed is the
/// self-consistent point of its amplitude profile (the dynamic stage's lanes, one per row;
/// profile tolerance [`STUDY_AMPLITUDE_TOLERANCE`]), so no point draws more than the wave
/// carries. `model.curve_points` given: its evenly spaced speeds
/// and the largest power and efficiency among them (the dynamic stage's layout); `auto`:
/// [`STUDY_SPEED_FRACTIONS`] and [`curve_maxima`]. Every point must be a closed steady period
/// with output ≤ stator power and v₀'s thrust ≈ 0 ([`accept`], [`NO_LOAD_THRUST_TOLERANCE`]);
/// the first that is not ends the curve with the [`Unresolved`] reason (the inner error), the
/// model's own failures are the outer one.
pub fn study_curve(
    scene: &Scene,
    static_model: &SliderModel,
    tangential: &StudyTangential,
    lumped_no_load_m_per_s: f64,
    warm: Option<&StudyWarmStart>,
) -> Result<Result<StudyCurve, Unresolved>, PipelineError> {
    check_scene(scene)?;
    let dynamics = study_dynamics(scene, static_model, tangential)?;
    let posts = dynamics.model().scene().post_x_m.len();
    let warm = warm.filter(|w| w.posts == posts);
    let mut clock = std::time::Instant::now();
    let mut lap = || {
        let s = clock.elapsed().as_secs_f64();
        clock = std::time::Instant::now();
        s
    };
    let stall = match study_stall(scene, static_model, &dynamics, warm)? {
        Ok(stall) => stall,
        Err(unresolved) => return Ok(Err(unresolved)),
    };
    let StudyStall {
        solver: model,
        point: stall,
        state: stall_state,
        wave,
    } = stall;
    let model = &model;
    let stall_s = lap();
    let fractions = study_fractions(scene);
    let guess = lumped_no_load_m_per_s * warm.map_or(1.0, |w| w.no_load_ratio);
    let exact = scene.model.curve_points.is_some();
    let search = no_load_search(model, &stall, &stall_state, guess, &fractions, exact, warm)?;
    let search = match search {
        Ok(search) => search,
        Err(unresolved) => return Ok(Err(unresolved)),
    };
    let no_load_s = lap();
    let NoLoad {
        solved: search,
        speed_m_per_s: no_load,
    } = search;
    let solved = match solve_points(model, no_load, &fractions, exact, &search, warm)? {
        Ok(solved) => solved,
        Err(unresolved) => return Ok(Err(unresolved)),
    };
    let times_s = StudyTimes {
        normal_grid_s: dynamics.normal_grid_wall_s(),
        stall_s,
        no_load_s,
        points_s: lap(),
    };
    let mut curve = vec![stall];
    curve.extend(solved.points);
    let (max_output_power_w, efficiency) = match scene.model.curve_points {
        Some(_) => sampled_maxima(&curve),
        None => curve_maxima(&curve),
    };
    let search_periods: usize = search.iter().map(|s| s.0.periods).sum();
    let warm = StudyWarmStart {
        posts,
        no_load: search.last().map(|s| s.1.clone()),
        no_load_ratio: no_load / lumped_no_load_m_per_s,
        ..StudyWarmStart::of_curve(&curve, stall_state, solved.states, no_load)
    };
    Ok(Ok(StudyCurve {
        stall_thrust_n: stall.thrust_n.max(0.0),
        no_load_speed_m_per_s: no_load,
        max_output_power_w,
        efficiency,
        curve,
        periods: stall.periods + search_periods + solved.periods,
        times_s,
        wave,
        warm,
    }))
}

impl StudyWarmStart {
    /// The figures of a solved `curve` (stall first, v₀'s point last, v₀ = `no_load` m/s) with
    /// the stall's and the points' states; no posts, no-load state or lumped ratio yet.
    fn of_curve(
        curve: &[CoupledPoint],
        stall: StudyState,
        points: Vec<StudyState>,
        no_load: f64,
    ) -> Self {
        Self {
            posts: 0,
            stall,
            no_load: None,
            points,
            no_load_ratio: f64::NAN,
            stall_thrust_n: curve.first().map_or(0.0, |p| p.thrust_n),
            no_load_m_per_s: no_load,
            no_load_slope_n_s_per_m: chord_slope(curve),
            curve: curve
                .iter()
                .map(|p| (p.speed_m_per_s, p.thrust_n))
                .collect(),
        }
    }
}

/// The whole slider's coupled model of a study's sample on `static_model`: steps solved to
/// [`STUDY_STEP_TOLERANCE`], the shared tangential operator where the sample keeps its lattice
/// and bodies (else its own), on every post.
fn study_dynamics(
    scene: &Scene,
    static_model: &SliderModel,
    tangential: &StudyTangential,
) -> Result<SliderDynamics, PipelineError> {
    let mut slider = slider_scene(scene, static_model);
    slider.tolerance = STUDY_STEP_TOLERANCE;
    let operator = match tangential.spec == static_model.params.operator_spec() {
        true => tangential.operator.clone(),
        false => StudyTangential::build(static_model)?.operator,
    };
    Ok(SliderDynamics::new(&slider, static_model, operator)?)
}

/// The stall of a study's curve, the model its other speeds run on and the wave's decision.
struct StudyStall<'a> {
    solver: StudySolver<'a>,
    point: CoupledPoint,
    state: StudyState,
    wave: WaveAttenuation,
}

/// The stall of a study's curve on `dynamics` (the sample's model of `static_model`): the
/// constant wave's, from `warm`'s stall; the wave's decision on its draw (a patch of the
/// lattice's rows draws, and is given, its rows' share of the wave); on the energy-conserving
/// wave the self-consistent stall, from `warm`'s stall or else the constant one's. A stall
/// that is no closed steady period is the [`Unresolved`] reason.
fn study_stall<'a>(
    scene: &Scene,
    static_model: &'a SliderModel,
    dynamics: &'a SliderDynamics,
    warm: Option<&StudyWarmStart>,
) -> Result<Result<StudyStall<'a>, Unresolved>, PipelineError> {
    let constant = StudySolver::Constant(dynamics.model());
    let (point, state) = match constant.accepted_at(0.0, warm.map(|w| &w.stall))? {
        Ok(solved) => solved,
        Err(unresolved) => return Ok(Err(unresolved)),
    };
    let rows = static_model.params.posts_y as f64 / f64::from(scene.motor.posts.count_y);
    let wave = attenuation::decide(scene, point.stator_power_w / rows)?;
    if !wave.on() {
        return Ok(Ok(StudyStall {
            solver: constant,
            point,
            state,
            wave,
        }));
    }
    let mut options = coupled_dynamics::AttenuationOptions::new(wave.power_in_w * rows);
    options.tolerance = STUDY_AMPLITUDE_TOLERANCE;
    let solver = StudySolver::Profiled(dynamics.profiles(static_model, &options)?);
    let from = warm.map_or(&state, |w| &w.stall);
    let (point, state) = match solver.accepted_at(0.0, Some(from))? {
        Ok(solved) => solved,
        Err(unresolved) => return Ok(Err(unresolved)),
    };
    Ok(Ok(StudyStall {
        solver,
        point,
        state,
        wave,
    }))
}

/// −dF/dv at the last point of `curve` from the chord to the one before (N s/m); NaN with
/// fewer than two points.
fn chord_slope(curve: &[CoupledPoint]) -> f64 {
    match curve {
        [.., a, b] => (a.thrust_n - b.thrust_n) / (b.speed_m_per_s - a.speed_m_per_s),
        _ => f64::NAN,
    }
}

/// Tolerance of a study's amplitude profile on the energy-conserving wave (max |Δα| of A₀;
/// the dynamic stage's is `coupled_dynamics::attenuation::DEFAULT_AMPLITUDE_TOLERANCE`, 1e-6).
/// Measured on the default slider with 5 nm height scatter (four samples) against 1e-6: the
/// P50 stall thrust, no-load speed, largest power and efficiency move by at most 1e-6
/// (relative), and the samples step 69 periods instead of 74; 1e-4 moves the stall thrust by
/// 2.4e-4, and 1e-3 leaves the nominal's no-load search without a root. Default 1e-5.
pub const STUDY_AMPLITUDE_TOLERANCE: f64 = 1e-5;

/// One solved speed's state, the start of a neighbouring speed's solve (or of the next
/// sample's at the same speed): the tips' periodic state on the constant wave, or with the
/// amplitude profile on the energy-conserving wave.
#[derive(Debug, Clone)]
pub enum StudyState {
    /// On the constant-amplitude wave.
    Constant(PeriodState),
    /// On the energy-conserving wave.
    Profiled(coupled_dynamics::ProfiledState),
}

/// The whole slider's coupled model of a study's curve, one speed at a time: on the constant
/// wave, or on the energy-conserving wave (every speed's amplitude profile self-consistent).
enum StudySolver<'a> {
    Constant(&'a coupled_dynamics::CoupledModel),
    Profiled(coupled_dynamics::SliderProfiles<'a>),
}

impl StudySolver<'_> {
    fn crest_speed_m_per_s(&self) -> f64 {
        match self {
            StudySolver::Constant(model) => model.crest_speed_m_per_s(),
            StudySolver::Profiled(profiles) => profiles.crest_speed_m_per_s(),
        }
    }

    /// [`Self::at_speed_from`], the point accepted ([`accept`]) or the reason it is not.
    fn accepted_at(
        &self,
        speed_m_per_s: f64,
        from: Option<&StudyState>,
    ) -> Result<Result<Solved, Unresolved>, PipelineError> {
        let (point, state) = self.at_speed_from(speed_m_per_s, from)?;
        Ok(accept(&point, self.crest_speed_m_per_s()).map(|()| (point, state)))
    }

    /// The steady point at `speed_m_per_s` from a neighbour's state: a constant-wave solve
    /// starts from a profiled state's tips, a profiled solve from a constant state at α = 1.
    fn at_speed_from(
        &self,
        speed_m_per_s: f64,
        from: Option<&StudyState>,
    ) -> Result<Solved, PipelineError> {
        match self {
            StudySolver::Constant(model) => {
                let start = from.map(|s| match s {
                    StudyState::Constant(state) => state,
                    StudyState::Profiled(profiled) => profiled.period_state(),
                });
                let (point, state) = model.at_speed_from(speed_m_per_s, start)?;
                Ok((point, StudyState::Constant(state)))
            }
            StudySolver::Profiled(profiles) => {
                let constant;
                let start = match from {
                    Some(StudyState::Profiled(profiled)) => Some(profiled),
                    Some(StudyState::Constant(state)) => {
                        constant = profiles.constant_state(state);
                        Some(&constant)
                    }
                    None => None,
                };
                let (point, state) = profiles.at_speed_from(speed_m_per_s, start)?;
                Ok((point.point, StudyState::Profiled(state)))
            }
        }
    }
}

/// Natural-residual tolerance of a study's step solves (relative to the friction scale); the
/// periodicity rule is 100× it. The dynamic stage's 1e-10 resolves a curve to ≈ 1e-8; a band
/// of several per cent needs far less, and every decade costs CG products in every step and
/// periods to periodicity. Measured on the default slider (100 × 100 posts, 40 N, 5 nm
/// scatter): 1e-6 against 1e-10 moved the nominal's and a sample's stall thrust, no-load
/// speed, largest power and efficiency by at most 8e-7 (relative), periods per sample 88 → 58;
/// 1e-5 against 1e-6 moves four samples' by at most 2e-6 (stall thrust; the others by less than
/// 1e-6), for 10 % less time per sample (fewer CG products per step; the periods are set by
/// the amplitude profile's tolerance, [`STUDY_AMPLITUDE_TOLERANCE`]). Default 1e-5.
pub const STUDY_STEP_TOLERANCE: f64 = 1e-5;
/// Evaluations of a study's no-load search at most, besides its two first speeds. Default 6.
const NO_LOAD_EVALUATIONS: usize = 6;

/// One solved speed: the steady point and the periodic state it started from.
type Solved = (CoupledPoint, StudyState);

/// The no-load search of a study's curve: every solved speed, the one nearest v₀ last, and v₀.
struct NoLoad {
    /// The solved speeds; the last is v₀'s point (|F| ≤ [`NO_LOAD_THRUST_TOLERANCE`] F(0⁺)).
    solved: Vec<Solved>,
    /// v₀ (m/s): the last point's speed, or the root interpolated through the solved speeds
    /// ([`interpolated_root`]) when its error estimate is below the tolerance.
    speed_m_per_s: f64,
}

/// The no-load speed v₀ of a study's curve: with the nominal run `warm`, its v₀ scaled by the
/// stall thrusts, at the layout's last fraction below v₀, then on the nominal's curve scaled
/// through it ([`similar_start`]); else from the predicted `guess`, the
/// thrust at [`STUDY_SPEED_FRACTIONS`]' last fraction (0.92) of the guess and at the guess
/// (each started from the stall's `stall_state`); then inverse
/// interpolation F ↦ v through the last three solved speeds (a secant with two), kept inside
/// the bracket once one is found, until v₀ is known to [`STUDY_SPEED_TOLERANCE`] of the crest
/// speed: the next step is below it, or the root interpolated through the solved speeds is
/// ([`interpolated_root`]: its error estimate below it, the nearest solved speed's thrust
/// ≈ 0); each solve starts from the nearest solved speed's state. Returns every solved speed,
/// v₀'s point last (its thrust ≈ 0: [`NO_LOAD_THRUST_TOLERANCE`]); none if F(0⁺) ≤ 0.
fn no_load_search(
    model: &StudySolver<'_>,
    stall: &CoupledPoint,
    stall_state: &StudyState,
    guess: f64,
    fractions: &[f64],
    exact: bool,
    warm: Option<&StudyWarmStart>,
) -> Result<Result<NoLoad, Unresolved>, PipelineError> {
    if stall.thrust_n <= 0.0 {
        return Ok(Ok(NoLoad {
            solved: Vec::new(),
            speed_m_per_s: 0.0,
        }));
    }
    let crest = model.crest_speed_m_per_s();
    let guess = match guess.is_finite() && guess > 0.0 {
        true => guess.min(11.0 * crest),
        false => 0.5 * crest,
    };
    let mut solved = match first_speeds(model, stall, stall_state, guess, fractions, exact, warm)? {
        Ok(solved) => solved,
        Err(unresolved) => return Ok(Err(unresolved)),
    };
    // The curve's points below the search's first speed, solved before a speed that refines a
    // root already near zero (warm start, `auto` layout): nodes of the root's interpolation.
    let mut lower: Option<Vec<Solved>> = None;
    for _ in 0..=NO_LOAD_EVALUATIONS + 1 {
        let best = nearest_root(&solved);
        let next = next_speed(&solved, stall.thrust_n);
        let near_zero = solved[best].0.thrust_n.abs() <= NO_LOAD_THRUST_TOLERANCE * stall.thrust_n;
        let nodes = solved.iter().chain(lower.iter().flatten()).map(|s| &s.0);
        let estimate = interpolated_root(nodes, stall.thrust_n);
        let interpolated =
            estimate.filter(|&(_, error)| near_zero && error <= STUDY_SPEED_TOLERANCE * crest);
        let stepped = (next - solved[best].0.speed_m_per_s).abs() <= STUDY_SPEED_TOLERANCE * crest;
        if stepped || interpolated.is_some() {
            let root = solved.remove(best);
            if !near_zero {
                return Ok(Err(no_root(&root.0, crest, stall)));
            }
            let speed_m_per_s = match interpolated {
                Some((speed, _)) if !stepped => speed,
                _ => root.0.speed_m_per_s,
            };
            solved.extend(lower.into_iter().flatten());
            solved.push(root);
            return Ok(Ok(NoLoad {
                solved,
                speed_m_per_s,
            }));
        }
        if near_zero && lower.is_none() && warm.is_some() && !exact {
            // No lower points yet: `estimate` is the search speeds' own.
            let speed = estimate.map_or(next, |r| r.0);
            lower = match lower_points(model, speed, fractions, &solved, warm)? {
                Ok(points) => Some(points),
                Err(unresolved) => return Ok(Err(unresolved)),
            };
            continue;
        }
        let from = nearest_speed(&solved, next);
        match model.accepted_at(next, Some(&solved[from].1))? {
            Ok(point) => solved.push(point),
            Err(unresolved) => return Ok(Err(unresolved)),
        }
    }
    let best = nearest_root(&solved);
    Ok(Err(no_root(&solved[best].0, crest, stall)))
}

/// The no-load search's first speeds: from the nominal run `warm` by [`similar_start`]; else
/// [`STUDY_SPEED_FRACTIONS`]' last fraction of the predicted `guess` and the guess, each
/// started from the nominal's state at that fraction, else from the stall's.
#[allow(clippy::type_complexity)]
fn first_speeds(
    model: &StudySolver<'_>,
    stall: &CoupledPoint,
    stall_state: &StudyState,
    guess: f64,
    fractions: &[f64],
    exact: bool,
    warm: Option<&StudyWarmStart>,
) -> Result<Result<Vec<Solved>, Unresolved>, PipelineError> {
    let below = match !exact && fractions.len() >= 2 {
        true => Some(fractions.len() - 2),
        false => None,
    };
    if let Some(first) =
        warm.and_then(|w| similar_start(model, stall, w, fractions, below).transpose())
    {
        return first;
    }
    let low = STUDY_SPEED_FRACTIONS[STUDY_SPEED_FRACTIONS.len() - 1];
    let low_start = warm.and_then(|w| w.points.get(fractions.len().saturating_sub(2)));
    let high_start = warm.and_then(|w| w.no_load.as_ref());
    let mut solved = Vec::with_capacity(NO_LOAD_EVALUATIONS + 4);
    for (v, start) in [(low * guess, low_start), (guess, high_start)] {
        match model.accepted_at(v, Some(start.unwrap_or(stall_state)))? {
            Ok(point) => solved.push(point),
            Err(unresolved) => return Ok(Err(unresolved)),
        }
    }
    Ok(Ok(solved))
}

/// The curve's points at `fractions` of the estimated no-load speed `no_load` below the
/// search's first speed (which stands for the last fraction below v₀), each from `warm`'s
/// state at the same fraction, else from the nearest solved speed's, and accepted
/// ([`accept`]). Solved before the search refines a root that is already near zero, they are
/// nodes of the interpolated root ([`interpolated_root`]: the three solved speeds with the
/// least thrust) nearer than the stall, whose error estimate then often meets the tolerance
/// without a further speed; [`solve_points`] takes them as its points at those fractions.
fn lower_points(
    model: &StudySolver<'_>,
    no_load: f64,
    fractions: &[f64],
    solved: &[Solved],
    warm: Option<&StudyWarmStart>,
) -> Result<Result<Vec<Solved>, Unresolved>, PipelineError> {
    let mut points: Vec<Solved> = Vec::new();
    for (k, f) in fractions
        .iter()
        .enumerate()
        .take(fractions.len().saturating_sub(2))
        .rev()
    {
        let v = f * no_load;
        let from = match warm.and_then(|w| w.points.get(k)) {
            Some(state) => state,
            None => &solved[nearest_speed(solved, v)].1,
        };
        match model.accepted_at(v, Some(from))? {
            Ok(point) => points.push(point),
            Err(unresolved) => return Ok(Err(unresolved)),
        }
    }
    Ok(Ok(points))
}

/// The first two speeds of a sample's no-load search from the nominal run `warm`, whose
/// curve the sample's is taken to be a scaled copy of, F(v) = a·F_n(v/b): a is the stall
/// thrusts' ratio (the curve's thrust scale) and b ≈ a first (the lumped model's v₀ is no
/// predictor under scatter: it rises with σ while the coupled one falls,
/// validation/whole-slider/bands). The first speed is the fraction `fractions[below]` of a·v₀ₙ
/// (the layout's last point below v₀, so that it stands for that point: [`REUSE_WINDOW`];
/// v₀ itself with no such point), started from the nominal's state at that fraction; its
/// thrust then fixes b ([`similar_no_load`]) and the second speed is b·v₀ₙ, started from the
/// first's state (the Newton step with the nominal's slope at v₀ where the nominal's curve
/// does not bracket it). `None` without a usable nominal slope.
#[allow(clippy::type_complexity)]
fn similar_start(
    model: &StudySolver<'_>,
    stall: &CoupledPoint,
    warm: &StudyWarmStart,
    fractions: &[f64],
    below: Option<usize>,
) -> Result<Option<Result<Vec<Solved>, Unresolved>>, PipelineError> {
    let slope = warm.no_load_slope_n_s_per_m;
    let (Some(no_load_start), true) = (
        warm.no_load.as_ref(),
        slope > 0.0 && warm.stall_thrust_n > 0.0 && warm.no_load_m_per_s > 0.0,
    ) else {
        return Ok(None);
    };
    let ratio = stall.thrust_n / warm.stall_thrust_n;
    let below = below.and_then(|k| Some((*fractions.get(k)?, warm.points.get(k)?)));
    let (fraction, start) = below.unwrap_or((1.0, no_load_start));
    let crest = model.crest_speed_m_per_s();
    let first = fraction * warm.no_load_m_per_s * ratio;
    let (point, state) = match model.accepted_at(first.min(11.0 * crest), Some(start))? {
        Ok(solved) => solved,
        Err(unresolved) => return Ok(Some(Err(unresolved))),
    };
    let second = similar_no_load(&warm.curve, warm.no_load_m_per_s, ratio, &point)
        .unwrap_or(point.speed_m_per_s + point.thrust_n / slope);
    let mut solved = vec![(point, state)];
    if second > 0.0 && second.is_finite() {
        match model.accepted_at(second.min(11.0 * crest), Some(&solved[0].1))? {
            Ok(point) => solved.push(point),
            Err(unresolved) => return Ok(Some(Err(unresolved))),
        }
    }
    Ok(Some(Ok(solved)))
}

/// The no-load speed b·v₀ₙ of a curve F(v) = `ratio`·F_n(v/b) through `point`, F_n the
/// nominal `curve` ((speed, thrust), speed ascending, v₀'s point last) and v₀ₙ its
/// `no_load` (m/s): u = v/b solves
/// F_n(u) = F(v)/`ratio` on the quadratic through the nominal points around the bracket of
/// that thrust (bisection), b = v/u. The quadratic's curvature carries the curve's bend
/// between the point and v₀ that a Newton step with the slope at v₀ misses (default slider,
/// 5 nm: first speed 0.90 v₀, the Newton step 2.0e-3 m/s short of v₀). `None` where the
/// nominal curve does not bracket the thrust.
fn similar_no_load(
    curve: &[(f64, f64)],
    no_load: f64,
    ratio: f64,
    point: &CoupledPoint,
) -> Option<f64> {
    let target = point.thrust_n / ratio;
    let k = (1..curve.len()).find(|&k| (curve[k - 1].1 - target) * (curve[k].1 - target) <= 0.0)?;
    let nodes = match k + 1 < curve.len() {
        true => &curve[k - 1..=k + 1],
        false => &curve[k.checked_sub(2)?..=k],
    };
    let (speeds, thrusts): (Vec<f64>, Vec<f64>) = nodes.iter().copied().unzip();
    let excess = |u: f64| lagrange(&speeds, &thrusts, u) - target;
    let (mut lo, mut hi) = (curve[k - 1].0, curve[k].0);
    let short_at_lo = excess(lo) < 0.0;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        match (excess(mid) < 0.0) == short_at_lo {
            true => lo = mid,
            false => hi = mid,
        }
    }
    let u = 0.5 * (lo + hi);
    (u > 0.0 && ratio > 0.0).then(|| point.speed_m_per_s * no_load / u)
}

/// The refusal of a no-load search that ended on `point`.
fn no_root(point: &CoupledPoint, crest: f64, stall: &CoupledPoint) -> Unresolved {
    Unresolved::NoRoot {
        speed_m_per_s: point.speed_m_per_s,
        crest_speed_m_per_s: crest,
        thrust_n: point.thrust_n,
        stall_thrust_n: stall.thrust_n,
    }
}

/// Index of the solved speed with the smallest |thrust|.
fn nearest_root(solved: &[Solved]) -> usize {
    (0..solved.len())
        .min_by(|&a, &b| {
            solved[a]
                .0
                .thrust_n
                .abs()
                .total_cmp(&solved[b].0.thrust_n.abs())
        })
        .unwrap_or(0)
}

/// Index of the solved speed nearest `speed` (its state starts the next solve).
fn nearest_speed(solved: &[Solved], speed: f64) -> usize {
    let distance = |k: usize| (solved[k].0.speed_m_per_s - speed).abs();
    (0..solved.len())
        .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
        .unwrap_or(0)
}

/// The next speed of the no-load search: inverse interpolation v(F) at F = 0 through the last
/// three solved speeds (two: the secant), or the middle of the bracket (the stall at v = 0 with
/// `stall_n` its lower end) where that leaves it or is not finite.
fn next_speed(solved: &[Solved], stall_n: f64) -> f64 {
    let (mut lo, mut hi) = ((0.0, stall_n), None::<(f64, f64)>);
    for (p, _) in solved {
        let at = (p.speed_m_per_s, p.thrust_n);
        if p.thrust_n > 0.0 && at.0 > lo.0 {
            lo = at;
        } else if p.thrust_n <= 0.0 && hi.is_none_or(|h: (f64, f64)| at.0 < h.0) {
            hi = Some(at);
        }
    }
    let mut last: Vec<(f64, f64)> = solved
        .iter()
        .rev()
        .take(3)
        .map(|(p, _)| (p.speed_m_per_s, p.thrust_n))
        .collect();
    if last.len() < 2 {
        last.push((0.0, stall_n));
    }
    let forces: Vec<f64> = last.iter().map(|x| x.1).collect();
    let speeds: Vec<f64> = last.iter().map(|x| x.0).collect();
    let predicted = match all_distinct(&forces) {
        true => lagrange(&forces, &speeds, 0.0),
        false => f64::NAN,
    };
    let upper = hi.map_or(f64::INFINITY, |h| h.0);
    match predicted.is_finite() && predicted > lo.0 && predicted < upper {
        true => predicted,
        false => match hi {
            Some(h) => 0.5 * (lo.0 + h.0),
            None => 1.5 * lo.0.max(speeds[0]),
        },
    }
}

/// Whether no two of `values` are equal (the nodes of an inverse interpolation in F).
fn all_distinct(values: &[f64]) -> bool {
    values
        .iter()
        .enumerate()
        .all(|(i, a)| values[..i].iter().all(|b| b != a))
}

/// v₀ interpolated through the solved points and its error estimate (m/s): the secant through
/// the two whose thrusts are nearest zero, and its difference from the inverse quadratic
/// F ↦ v through those two and the next nearest (the stall, F(0) = `stall_n`, with only two
/// solved), which is the secant's second-order term. `None` with fewer than two solved speeds
/// or a root that is not finite and positive.
fn interpolated_root<'a>(
    solved: impl Iterator<Item = &'a CoupledPoint>,
    stall_n: f64,
) -> Option<(f64, f64)> {
    let mut order: Vec<(f64, f64)> = solved.map(|p| (p.thrust_n, p.speed_m_per_s)).collect();
    order.sort_by(|a, b| a.0.abs().total_cmp(&b.0.abs()));
    if order.len() < 2 {
        return None;
    }
    if order.len() == 2 {
        order.push((stall_n, 0.0));
    }
    let (forces, speeds): (Vec<f64>, Vec<f64>) = order[..3].iter().copied().unzip();
    if !all_distinct(&forces) {
        return None;
    }
    let secant = lagrange(&forces[..2], &speeds[..2], 0.0);
    let quadratic = lagrange(&forces, &speeds, 0.0);
    let error = (quadratic - secant).abs();
    (secant.is_finite() && secant > 0.0 && error.is_finite()).then_some((secant, error))
}

/// The points of a study curve above the stall, speed ascending, their periodic states and the
/// periods stepped beyond the no-load search's.
struct SolvedPoints {
    points: Vec<CoupledPoint>,
    states: Vec<StudyState>,
    periods: usize,
}

/// The points at `fractions` of the no-load speed `no_load` (the last, v₀'s, is the no-load
/// search's last point, its thrust ≈ 0; unless `exact` (`model.curve_points` given), a search
/// speed within [`REUSE_WINDOW`] of a fraction stands for it, the interpolants need no exact
/// fractions), the others solved from the top down, each from `warm`'s state of the same point,
/// else from its faster neighbour's, and accepted ([`accept`]).
fn solve_points(
    model: &StudySolver<'_>,
    no_load: f64,
    fractions: &[f64],
    exact: bool,
    search: &[Solved],
    warm: Option<&StudyWarmStart>,
) -> Result<Result<SolvedPoints, Unresolved>, PipelineError> {
    let mut solved = SolvedPoints {
        points: Vec::with_capacity(fractions.len()),
        states: Vec::with_capacity(fractions.len()),
        periods: 0,
    };
    let mut previous: Option<StudyState> = None;
    for (k, f) in fractions.iter().enumerate().rev() {
        let v = f * no_load;
        let near = search.iter().enumerate().find(|(j, s)| {
            let last = j + 1 == search.len();
            let close = (s.0.speed_m_per_s - v).abs() <= REUSE_WINDOW * no_load;
            (last && k + 1 == fractions.len())
                || (!exact && !last && close && k + 1 < fractions.len())
        });
        let (point, state) = match near {
            Some((_, s)) => s.clone(),
            None => {
                let from = warm.and_then(|w| w.points.get(k)).or(previous.as_ref());
                let (point, state) = match model.accepted_at(v, from)? {
                    Ok(solved) => solved,
                    Err(unresolved) => return Ok(Err(unresolved)),
                };
                solved.periods += point.periods;
                (point, state)
            }
        };
        solved.points.push(point);
        previous = Some(state.clone());
        solved.states.push(state);
    }
    solved.points.reverse();
    solved.states.reverse();
    Ok(Ok(solved))
}

/// How far (of v₀) a no-load search speed may lie from a curve fraction to stand for it in the
/// `auto` layout: the search's first speed, 0.92 of the predicted v₀, lands within a few per
/// cent of 0.92 v₀ when the prediction is good. Default 0.05.
const REUSE_WINDOW: f64 = 0.05;

/// Largest |F(v₀)| over the stall thrust that a study's no-load speed may leave. The search
/// stops on a speed step of [`STUDY_SPEED_TOLERANCE`] of the crest speed, which leaves ≈ 1e-5
/// of the stall thrust on a moving slider; a nearly locked slider's v₀ lies below that step, so
/// the search stops on a speed whose thrust is still the stall's. Default 1e-3.
pub const NO_LOAD_THRUST_TOLERANCE: f64 = 1e-3;
/// Largest excess of a solved point's output power over the power its stator delivers,
/// relative to the larger of the two: the books of a closed steady period balance to round-off
/// (≈ 1e-15 of the power flow), so output ≤ stator power, efficiency ≤ 1. Default 1e-9.
pub const BOOKS_TOLERANCE: f64 = 1e-9;

/// Why a sample's coupled study curve is refused: its figures would not be the coupled
/// model's steady ones. A study's `auto` then keeps the lumped model and says why; an explicit
/// `model.dynamics = "coupled"` fails naming the sample.
#[derive(Debug, Clone, PartialEq)]
pub enum Unresolved {
    /// The steady period at a speed did not close within the model's period budget: its books
    /// hold a change of stored energy, so output over stator power is no efficiency. A nearly
    /// locked slider is the usual case: moving µm/s or less, its stuck posts wind up over far
    /// more periods than the budget before they slip.
    OpenPeriod {
        /// Speed of the point (m/s).
        speed_m_per_s: f64,
        /// Crest speed of the wave (m/s).
        crest_speed_m_per_s: f64,
        /// Periods stepped.
        periods: usize,
    },
    /// The no-load search ended on a speed whose thrust is not ≈ 0
    /// ([`NO_LOAD_THRUST_TOLERANCE`] of the stall thrust).
    NoRoot {
        /// Speed the search ended on (m/s).
        speed_m_per_s: f64,
        /// Crest speed of the wave (m/s).
        crest_speed_m_per_s: f64,
        /// Thrust there (N).
        thrust_n: f64,
        /// Stall thrust (N).
        stall_thrust_n: f64,
    },
    /// A point's output power exceeds its stator power ([`BOOKS_TOLERANCE`]).
    Books {
        /// Speed of the point (m/s).
        speed_m_per_s: f64,
        /// Output power (W).
        output_power_w: f64,
        /// Power the stator delivers (W).
        stator_power_w: f64,
    },
}

impl std::fmt::Display for Unresolved {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Unresolved::OpenPeriod {
                speed_m_per_s: v,
                crest_speed_m_per_s: c,
                periods,
            } => write!(
                f,
                "the whole slider's coupled steady period at {v:.3e} m/s ({:.1e} of the crest \
                 speed) did not close within {periods} periods (a nearly locked slider)",
                v / c
            ),
            Unresolved::NoRoot {
                speed_m_per_s: v,
                crest_speed_m_per_s: c,
                thrust_n,
                stall_thrust_n,
            } => write!(
                f,
                "the whole slider's coupled no-load search ended at {v:.3e} m/s ({:.1e} of the \
                 crest speed) with the thrust {thrust_n:.4e} N of the stall's {stall_thrust_n:.4e} \
                 N (no root within the speed tolerance {STUDY_SPEED_TOLERANCE:e} of the crest \
                 speed: a nearly locked slider)",
                v / c
            ),
            Unresolved::Books {
                speed_m_per_s: v,
                output_power_w,
                stator_power_w,
            } => write!(
                f,
                "the whole slider's coupled point at {v:.3e} m/s puts out {output_power_w:.6e} W, \
                 more than the {stator_power_w:.6e} W its stator delivers"
            ),
        }
    }
}

/// Whether a solved point's figures are a steady cycle's with balanced books: its period
/// closed and its output power is at most the stator's ([`BOOKS_TOLERANCE`]).
fn accept(point: &CoupledPoint, crest_speed_m_per_s: f64) -> Result<(), Unresolved> {
    if !point.converged {
        return Err(Unresolved::OpenPeriod {
            speed_m_per_s: point.speed_m_per_s,
            crest_speed_m_per_s,
            periods: point.periods,
        });
    }
    let (output, stator) = (point.output_power_w, point.stator_power_w);
    let scale = output.abs().max(stator.abs());
    if output > 0.0 && !(output - stator <= BOOKS_TOLERANCE * scale) {
        return Err(Unresolved::Books {
            speed_m_per_s: point.speed_m_per_s,
            output_power_w: output,
            stator_power_w: stator,
        });
    }
    Ok(())
}

/// The fractions of v₀ a study solves besides the stall: v₀ itself last, after
/// [`STUDY_SPEED_FRACTIONS`] or `model.curve_points`' evenly spaced speeds.
fn study_fractions(scene: &Scene) -> Vec<f64> {
    match scene.model.curve_points {
        Some(n) => (1..n).map(|k| f64::from(k) / f64::from(n - 1)).collect(),
        None => STUDY_SPEED_FRACTIONS.iter().copied().chain([1.0]).collect(),
    }
}

/// The largest output power and efficiency among the solved points.
fn sampled_maxima(curve: &[CoupledPoint]) -> (f64, f64) {
    let max = |f: fn(&CoupledPoint) -> f64| curve.iter().map(f).fold(0.0, f64::max);
    (max(|p| p.output_power_w), max(|p| p.efficiency))
}

/// The largest output power P(v) = F(v)·v and efficiency P(v)/(P(v) + D(v)) on [0, v₀] of the
/// polynomial interpolants of the thrust F and the loss D = P_stator − P (friction and the
/// stepping's numerical dissipation, ≥ 0 on every accepted point) through the solved points
/// (stall, [`STUDY_SPEED_FRACTIONS`] of v₀, v₀; degree 4, Lagrange form), each at least the
/// largest solved value. The loss interpolant is floored at 0 between the points, so the
/// efficiency is at most 1 and the output power at most the stator power P + D by
/// construction, whatever the interpolants do. Both are smooth in v between stall and no load
/// (the curve's stick/slip fractions change continuously), so the interpolants' error is that
/// of five-node interpolation; measured against the 8-point curve in
/// validation/whole-slider/bands.
pub fn curve_maxima(curve: &[CoupledPoint]) -> (f64, f64) {
    let (mut power, mut efficiency) = sampled_maxima(curve);
    let v0 = curve.last().map_or(0.0, |p| p.speed_m_per_s);
    if curve.len() < 3 || v0 <= 0.0 {
        return (power, efficiency);
    }
    let speeds: Vec<f64> = curve.iter().map(|p| p.speed_m_per_s).collect();
    let thrust: Vec<f64> = curve.iter().map(|p| p.thrust_n).collect();
    let loss: Vec<f64> = curve
        .iter()
        .map(|p| (p.stator_power_w - p.output_power_w).max(0.0))
        .collect();
    for k in 1..MAXIMA_GRID {
        let v = v0 * k as f64 / MAXIMA_GRID as f64;
        let output = lagrange(&speeds, &thrust, v) * v;
        power = power.max(output);
        let lost = lagrange(&speeds, &loss, v).max(0.0);
        if output > 0.0 {
            efficiency = efficiency.max(output / (output + lost));
        }
    }
    (power, efficiency)
}

/// The interpolating polynomial through (`xs`, `ys`) at `x` (Lagrange form).
fn lagrange(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    xs.iter()
        .zip(ys)
        .enumerate()
        .map(|(i, (xi, yi))| {
            let basis = xs
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, xj)| (x - xj) / (xi - xj))
                .product::<f64>();
            yi * basis
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point of the curve F(v) = F₀(1 − (v/v₀)²) drawing the stator power P₀(1 + v/v₀).
    fn point(v: f64) -> CoupledPoint {
        let (f0, v0, p0) = (2.0, 0.8, 3.0);
        let thrust_n = f0 * (1.0 - (v / v0).powi(2));
        let stator_power_w = p0 * (1.0 + v / v0);
        CoupledPoint {
            speed_m_per_s: v,
            thrust_n,
            output_power_w: thrust_n * v,
            stator_power_w,
            friction_dissipation_w: stator_power_w - thrust_n * v,
            numerical_dissipation_w: 0.0,
            efficiency: thrust_n * v / stator_power_w,
            stick_fraction: 0.0,
            contact_fraction: 0.0,
            energy_balance_residual: 0.0,
            right_endpoint_balance_residual: 0.0,
            energy_identity_residual: 0.0,
            converged: true,
            periods: 2,
            max_solver_residual: 0.0,
            solver_iterations: 0,
            fallback_steps: 0,
        }
    }

    #[test]
    fn the_interpolants_find_the_maxima_between_the_solved_points_of_a_smooth_curve() {
        let v0 = 0.8;
        let curve: Vec<CoupledPoint> = [0.0]
            .iter()
            .chain(&STUDY_SPEED_FRACTIONS)
            .chain(&[1.0])
            .map(|f| point(f * v0))
            .collect();
        // Exact: P = F₀ v (1 − v²/v₀²) peaks at v₀/√3 with 2F₀v₀/(3√3); the efficiency
        // F v / P_stator on a fine grid.
        let exact_power = 2.0 * 2.0 * v0 / (3.0 * 3f64.sqrt());
        let exact_efficiency = (1..100_000)
            .map(|k| point(v0 * k as f64 / 100_000.0).efficiency)
            .fold(0.0, f64::max);
        let (power, efficiency) = curve_maxima(&curve);
        let (sampled_power, sampled_efficiency) = sampled_maxima(&curve);
        assert!(
            (power / exact_power - 1.0).abs() < 1e-5,
            "largest output power {power} against {exact_power}"
        );
        assert!(
            (efficiency / exact_efficiency - 1.0).abs() < 1e-4,
            "largest efficiency {efficiency} against {exact_efficiency}"
        );
        assert!(
            sampled_power < power && sampled_efficiency < efficiency,
            "the solved points alone fall short of the maxima: {sampled_power}, {sampled_efficiency}"
        );
    }

    #[test]
    fn the_interpolated_no_load_speed_of_a_smooth_curve_lies_within_its_error_estimate() {
        // F = F₀(1 − (v/v₀)²), solved at 0.99 v₀ and 0.9998 v₀ (v₀ = 0.8 m/s).
        let near = [point(0.99 * 0.8), point(0.9998 * 0.8)];
        let (root, error) = interpolated_root(near.iter(), point(0.0).thrust_n).unwrap();
        assert!(
            (root - 0.8).abs() <= error,
            "root {root}, error estimate {error}"
        );
        assert!(
            error < 1e-5 * 0.8,
            "error estimate {error} of two points close to v₀"
        );
        // Two points far from v₀: the estimate grows with the distance (no false confidence).
        let far = [point(0.5 * 0.8), point(0.7 * 0.8)];
        let (root, error) = interpolated_root(far.iter(), point(0.0).thrust_n).unwrap();
        assert!(
            (root - 0.8).abs() <= error,
            "root {root}, error estimate {error}"
        );
        assert!(
            error > 1e-2 * 0.8,
            "error estimate {error} of two points far from v₀"
        );
        assert!(
            interpolated_root(near[..1].iter(), 10.0).is_none(),
            "one point"
        );
    }

    #[test]
    fn the_no_load_speed_of_a_scaled_copy_of_the_nominal_curve_follows_from_one_point() {
        // Nominal F_n = F₀(1 − (v/v₀)²) at the `auto` layout; the sample's F = a·F_n(v/b).
        let v0 = 0.8;
        let nominal: Vec<(f64, f64)> = [0.0]
            .iter()
            .chain(&STUDY_SPEED_FRACTIONS)
            .chain(&[1.0])
            .map(|f| (f * v0, point(f * v0).thrust_n))
            .collect();
        let (a, b) = (0.9, 0.93);
        for v in [0.6 * b * v0, 0.9 * b * v0, 0.99 * b * v0] {
            let mut sample = point(v / b);
            sample.speed_m_per_s = v;
            sample.thrust_n *= a;
            let found = similar_no_load(&nominal, v0, a, &sample).unwrap();
            assert!(
                (found - b * v0).abs() < 1e-12,
                "from {v} m/s: v₀ {found} against {}",
                b * v0
            );
        }
        let mut beyond = point(0.5);
        beyond.thrust_n = 3.0;
        assert!(
            similar_no_load(&nominal, v0, a, &beyond).is_none(),
            "a thrust above the nominal's stall over a has no bracket"
        );
    }

    /// The nearly locked slider's points whose periods did not close (a degenerate design of
    /// the design golden): thrust ≈ constant, efficiency 0.98–0.996 at the points and the
    /// stall's stator power a round-off below 0. Interpolating the stator power and dividing
    /// gave an efficiency of 1.06 between the points.
    #[test]
    fn the_interpolated_efficiency_of_a_degenerate_curve_stays_at_most_one() {
        let at = |v: f64, thrust_n: f64, stator_power_w: f64| CoupledPoint {
            speed_m_per_s: v,
            thrust_n,
            output_power_w: thrust_n * v,
            stator_power_w,
            efficiency: if v > 0.0 {
                thrust_n * v / stator_power_w
            } else {
                0.0
            },
            ..point(0.0)
        };
        let curve = [
            at(0.0, 7.158464777582371e-2, -8.453473708672885e-12),
            at(
                8.988465646565014e-7,
                7.044346757734055e-2,
                6.433516130955116e-8,
            ),
            at(
                1.225699860895229e-6,
                7.066235379670369e-2,
                8.77328392684223e-8,
            ),
            at(
                1.5035251626981477e-6,
                7.095147020778521e-2,
                1.0762086573899793e-7,
            ),
            at(
                1.6342664811936387e-6,
                7.129440234959188e-2,
                1.1697993705581368e-7,
            ),
        ];
        let (power, efficiency) = curve_maxima(&curve);
        assert!(efficiency <= 1.0, "efficiency {efficiency}");
        let stator = curve.iter().map(|p| p.stator_power_w).fold(0.0, f64::max);
        assert!(
            power <= stator,
            "output {power} W above the stator's {stator} W"
        );
    }

    #[test]
    fn a_point_with_an_open_period_or_more_output_than_stator_power_is_refused() {
        let crest = 1.1;
        assert_eq!(accept(&point(0.4), crest), Ok(()));
        let open = CoupledPoint {
            converged: false,
            periods: 64,
            ..point(0.4)
        };
        assert!(matches!(
            accept(&open, crest),
            Err(Unresolved::OpenPeriod { periods: 64, .. })
        ));
        let over = CoupledPoint {
            stator_power_w: 0.5 * point(0.4).output_power_w,
            ..point(0.4)
        };
        let e = accept(&over, crest).unwrap_err();
        assert!(matches!(e, Unresolved::Books { .. }), "{e}");
        assert!(e.to_string().contains("more than"), "{e}");
    }

    /// A 12 × 12 slider (the studies' small scene) with `sets`: its scene, static model and
    /// tangential operator, with 5 nm height scatter when `scattered`.
    fn small_study(sets: &[&str], scattered: bool) -> (Scene, SliderModel, StudyTangential) {
        let mut all = vec![
            "posts.count=12x12",
            "posts.array=0.48mm",
            "slider.length=0.5mm",
            "slider.width=0.5mm",
            "load.preload=0.576N",
            "static.model=slider",
            "model.dynamics=coupled",
            "model.coupled.steps_per_period=32",
        ];
        all.extend(sets);
        let all: Vec<String> = all.iter().map(|s| s.to_string()).collect();
        let scene = crate::scene::load_scene(None, &all).unwrap();
        let mut imperfections = slider_contact::Imperfections::default();
        if scattered {
            imperfections.height_scatter_m = 5e-9;
            imperfections.scatter_seed = 11;
        }
        let params = crate::pipeline::evaluate::slider_params(&scene, imperfections);
        let slider = SliderModel::build(&params).unwrap();
        let tangential = StudyTangential::build(&slider).unwrap();
        (scene, slider, tangential)
    }

    fn curve_of(scene: &Scene, slider: &SliderModel, t: &StudyTangential) -> StudyCurve {
        study_curve(scene, slider, t, 0.5, None).unwrap().unwrap()
    }

    #[test]
    fn a_study_curve_on_the_energy_conserving_wave_never_draws_more_than_the_wave_carries() {
        let (scene, slider, t) = small_study(&[], true);
        let attenuated = curve_of(&scene, &slider, &t);
        assert!(attenuated.wave.on(), "auto: {}", attenuated.wave.reason);
        let (off, ..) = small_study(&["wave.attenuation=off"], true);
        let constant = curve_of(&off, &slider, &t);
        assert!(!constant.wave.on(), "off: {}", constant.wave.reason);
        let p_in = attenuated.wave.power_in_w;
        let constant_draw = constant.curve[0].stator_power_w;
        assert!(
            constant_draw > 0.01 * p_in,
            "the constant wave's stall draw {constant_draw} W is what turns auto on (P_in {p_in} W)"
        );
        for p in &attenuated.curve {
            assert!(
                p.stator_power_w <= p_in,
                "at {} m/s the posts draw {} W of the {p_in} W the wave carries",
                p.speed_m_per_s,
                p.stator_power_w
            );
        }
        let (a, c) = (&attenuated.curve[0], &constant.curve[0]);
        assert!(
            a.stator_power_w < c.stator_power_w && a.thrust_n < c.thrust_n,
            "the attenuated stall draws {} W and pushes {} N, the constant one {} W and {} N",
            a.stator_power_w,
            a.thrust_n,
            c.stator_power_w,
            c.thrust_n
        );
    }

    #[test]
    fn a_sample_started_from_the_nominal_in_the_auto_layout_gives_its_cold_figures() {
        // The warm search starts at the layout's last fraction below v₀ and solves the lower
        // points before it refines the root: other speeds than the cold curve's, the same
        // stall and v₀ to the tolerances, and maxima from interpolants through nearby nodes.
        let (scene, nominal, t) = small_study(&[], false);
        let warm = curve_of(&scene, &nominal, &t).warm;
        let (_, sample, _) = small_study(&[], true);
        let cold = curve_of(&scene, &sample, &t);
        let started = study_curve(&scene, &sample, &t, 0.5, Some(&warm))
            .unwrap()
            .unwrap();
        let close = |a: f64, b: f64, tolerance: f64, what: &str| {
            assert!(
                (a - b).abs() <= tolerance * b.abs(),
                "{what}: warm {a}, cold {b}"
            );
        };
        close(started.stall_thrust_n, cold.stall_thrust_n, 1e-4, "stall");
        let v0 = (started.no_load_speed_m_per_s, cold.no_load_speed_m_per_s);
        close(v0.0, v0.1, 1e-4, "no-load speed");
        close(
            started.max_output_power_w,
            cold.max_output_power_w,
            1e-3,
            "power",
        );
        close(started.efficiency, cold.efficiency, 1e-3, "efficiency");
        assert_eq!(started.curve.len(), cold.curve.len(), "the same layout");
    }

    #[test]
    fn a_sample_started_from_the_nominals_profiled_states_gives_its_cold_curve() {
        // Evenly spaced speeds: the `auto` layout lets a no-load search speed stand for a
        // curve fraction, so warm and cold curves would sit on different speeds.
        let exact = ["model.curve_points=5"];
        let (scene, nominal, t) = small_study(&exact, false);
        let warm = curve_of(&scene, &nominal, &t).warm;
        let (_, sample, _) = small_study(&exact, true);
        let cold = curve_of(&scene, &sample, &t);
        let started = study_curve(&scene, &sample, &t, 0.5, Some(&warm))
            .unwrap()
            .unwrap();
        assert!(started.wave.on() && cold.wave.on());
        let close = |a: f64, b: f64, what: &str| {
            assert!(
                (a - b).abs() <= 1e-4 * b.abs(),
                "{what}: warm {a}, cold {b}"
            );
        };
        close(started.stall_thrust_n, cold.stall_thrust_n, "stall thrust");
        close(
            started.no_load_speed_m_per_s,
            cold.no_load_speed_m_per_s,
            "no-load speed",
        );
        close(
            started.max_output_power_w,
            cold.max_output_power_w,
            "largest output power",
        );
        close(started.efficiency, cold.efficiency, "efficiency");
    }
}
