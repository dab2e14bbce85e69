//! The transient with the energy-conserving wave: every column of posts its own phase group
//! (columns with equal x mod λ no longer merge: they see different amplitudes), the group's
//! amplitude multiplied by its column's α, and each group's draw the time mean of its stator
//! power Σ w F·Δu over the run's averaging window. The balance P_in − P_out = Σ draws = stator
//! power closes to round-off whichever way the profile is found:
//!
//! * [`ProfileIteration::PerRun`]: each fixed-point evaluation is one whole run at the load
//!   (Anderson, `crate::attenuation::solve_amplitude_profile`); runs after the first start from
//!   the previous run's mean speed. A run's window mean is exact for its profile, so the fixed
//!   point is that of a deterministic map. Costs 5–10 runs per load.
//! * [`ProfileIteration::InRun`] (default): one run that adjusts the profile as it goes. Every
//!   `IN_RUN_BLOCK_PERIODS` periods the groups' mean draws over the block give T(α) and the
//!   profile moves to α + β (T(α) − α) (under-relaxed, β = `IN_RUN_RELAXATION`); the wave's
//!   transit under the slider takes ≈ 10 periods and the posts follow a change of amplitude
//!   within a period, so the profile settles with the slider (whose speed relaxes over ≈ 20
//!   periods on the default motor). The profile is frozen at the first block end after the
//!   plain run's settling periods (`periods − average_periods`) whose change is below the
//!   tolerance or has stopped falling (the 4-period means' own fluctuation), or at half the
//!   longest run whatever the blocks say; an averaging window of
//!   `average_periods` then runs at it, so its means are exact for that profile and the
//!   window's max|T(α) − α| is the fixed point's residual. Below the tolerance the run ends
//!   (a profile converged during settling gives the plain run's span: the weak-load limit is
//!   the constant-amplitude run); else the next window runs at the Anderson update of the
//!   windows so far (the per-run step, without restarting the slider), doubled in length
//!   when the change stops halving — the window means fluctuate by ≈ 1e-6 at slow speeds
//!   (quasi-periodic stick/slip). If it stops halving again, or the run reaches
//!   `IN_RUN_MAX_RUN_FACTOR` × `periods`, the per-run iteration finishes from its profile and
//!   speed. The run's steady test is reported as the plain run reports it (the curve warns);
//!   a slider pushed backwards (load beyond stall) and not steady ends the iteration in both
//!   schemes: it has no steady state to be self-consistent with. Agrees with `PerRun` to the
//!   tolerance in fewer periods (tests/attenuation.rs; bench `attenuation`).
//!
//! Needs a stepper that keeps the stator work per group and can change the amplitude during a
//! run (return mapping — the transient's default — post-mass, regularized explicit); the
//! event-driven stepper is refused.

use serde::{Deserialize, Serialize};

use super::{
    AttenuationOptions, anderson_step, check_scene, profile_targets, solve_amplitude_profile,
};
use crate::error::{Result, StickSlipError};
use crate::result::DynamicResult;
use crate::scene::TransientStart;
use crate::transient::CurveRun;
use crate::transient::run::{PeriodHook, PeriodRecord, Span, is_steady, mean_speed};
use crate::transient::system::Stepper;
use crate::transient::{TransientModel, TransientRun};
use run_control::RunControl;

/// Periods per profile update inside a run. Default 4.
const IN_RUN_BLOCK_PERIODS: usize = 4;
/// Longest in-run run, in plain runs (`periods`): the per-run fixed point's typical cost.
/// Default 3.
const IN_RUN_MAX_RUN_FACTOR: usize = 3;
/// Blocks without the change falling by a tenth after which the blocks have reached the
/// fluctuation of their 4-period means: the profile is frozen for a window. Default 4.
const IN_RUN_STALLED_BLOCKS: usize = 4;
/// Under-relaxation of the in-run profile updates. Default 0.7.
const IN_RUN_RELAXATION: f64 = 0.7;

/// How the transient finds the self-consistent profile (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ProfileIteration {
    /// One run that adjusts the profile every few periods, then verifies it over its window.
    #[default]
    InRun,
    /// One whole run per fixed-point evaluation.
    PerRun,
}

/// One self-consistent transient run with the energy-conserving wave.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttenuatedRun {
    /// The run at the converged profile (`stator_power_w` = Σ group draws).
    pub run: TransientRun,
    /// Wave power entering under the array (W).
    pub wave_power_in_w: f64,
    /// Wave power leaving at the trailing edge (W): P_in − Σ draws.
    pub wave_power_out_w: f64,
    /// x of each column relative to the slider centre (m), ascending.
    pub x_m: Vec<f64>,
    /// A/A₀ of each column.
    pub amplitude_scale: Vec<f64>,
    /// Mean stator power each column draws over the averaging window (W, whole slider).
    pub group_power_w: Vec<f64>,
    /// Fixed-point evaluations: runs (per run), or averaging windows (in run).
    pub iterations: usize,
    /// Profile updates inside the run before the first window (0 per run).
    pub in_run_updates: usize,
    /// Wave periods simulated in all (the cost measure).
    pub periods_simulated: usize,
    /// max |T(α) − α| at the reported profile.
    pub last_change: f64,
    /// |P_in − P_out − stator power| / P_in.
    pub balance_residual: f64,
}

impl CurveRun for AttenuatedRun {
    fn run(&self) -> &TransientRun {
        &self.run
    }

    fn periods_simulated(&self) -> usize {
        self.periods_simulated
    }
}

/// The transient's speed–thrust curve with the energy-conserving wave.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttenuatedTransientResult {
    /// Stall, no-load speed, curve, operating point, efficiency: all attenuated.
    pub result: DynamicResult,
    /// Wave power under the array (W).
    pub power_in_w: f64,
    /// The run behind each point of `result.curve`, in its order; the stall point (v → 0⁺) is
    /// backed by the slowest moving run (its books and profile).
    pub points: Vec<AttenuatedRun>,
    /// The run at the external load, with histories (also when the load exceeds the stall
    /// thrust and `result.operating_point` is `None`).
    pub operating: AttenuatedRun,
    /// Largest balance residual over the points and the operating run.
    pub max_balance_residual: f64,
    /// Most fixed-point evaluations of a run.
    pub max_iterations: usize,
    /// Loads run (operating point, curve loads, stall search).
    pub runs: usize,
    /// Wave periods simulated in all runs (the cost measure).
    pub periods_simulated: usize,
}

impl AttenuatedRun {
    fn new(
        run: TransientRun,
        options: &AttenuationOptions,
        x_m: Vec<f64>,
        alpha: Vec<f64>,
        draw_w: Vec<f64>,
        last_change: f64,
    ) -> Self {
        let p_in = options.power_in_w;
        let out = p_in - draw_w.iter().sum::<f64>();
        Self {
            wave_power_in_w: p_in,
            wave_power_out_w: out,
            balance_residual: (p_in - out - run.stator_power_w).abs() / p_in,
            periods_simulated: run.periods,
            run,
            x_m,
            amplitude_scale: alpha,
            group_power_w: draw_w,
            iterations: 1,
            in_run_updates: 0,
            last_change,
        }
    }
}

/// The profile fixed point did not converge.
fn not_converged(iterations: usize, residual: f64) -> StickSlipError {
    StickSlipError::NotConverged {
        model: "transient with the energy-conserving wave",
        what: "amplitude profile (fixed point of the wave's power balance)",
        iterations,
        residual,
    }
}

/// The stepper keeps no per-group work or cannot retune.
fn stepper_refused(name: &str) -> StickSlipError {
    StickSlipError::ModelNotApplicable {
        model: "transient with the energy-conserving wave",
        reason: format!(
            "the {name} stepper keeps no stator power per group: use return-mapping, post-mass or regularized-explicit"
        ),
    }
}

impl TransientModel {
    /// The self-consistent run at external load `load_n` (N) with the energy-conserving wave of
    /// `options` (by `options.transient_iteration`), from `start`, the profile from `warm` (one
    /// α per column, e.g. the previous load's or the period average's at the same load,
    /// [`crate::AttenuatedPeriodicModel`] without `bins`) or α = 1; `record` keeps the histories
    /// as [`TransientModel::run`]. Errors: bad options, a scene the attenuation cannot describe,
    /// the event-driven stepper, a failed run, or no convergence within `max_iterations`.
    pub fn run_attenuated(
        &self,
        load_n: f64,
        start: TransientStart,
        options: &AttenuationOptions,
        warm: Option<&[f64]>,
    ) -> Result<AttenuatedRun> {
        self.run_attenuated_recorded(load_n, start, options, warm, false)
    }

    /// [`run_attenuated`](Self::run_attenuated) with histories if `record`.
    pub fn run_attenuated_recorded(
        &self,
        load_n: f64,
        start: TransientStart,
        options: &AttenuationOptions,
        warm: Option<&[f64]>,
        record: bool,
    ) -> Result<AttenuatedRun> {
        let speed = self.initial_speed(load_n, start)?;
        self.run_attenuated_from(load_n, speed, options, warm, record)
    }

    /// The self-consistent run from `initial_speed` (m/s, drive direction).
    fn run_attenuated_from(
        &self,
        load_n: f64,
        speed: f64,
        options: &AttenuationOptions,
        warm: Option<&[f64]>,
        record: bool,
    ) -> Result<AttenuatedRun> {
        options.validate()?;
        check_scene(self.scene(), "transient with the energy-conserving wave")?;
        let x_m: Vec<f64> = crate::transient::groups::columns(self.scene())
            .iter()
            .map(|c| c.0)
            .collect();
        let alpha = match warm {
            Some(w) if w.len() == x_m.len() => w.to_vec(),
            Some(w) => {
                return Err(StickSlipError::InvalidParameter {
                    parameter: "warm amplitude profile",
                    value: w.len() as f64,
                    requirement: format!("needs one entry per column ({})", x_m.len()),
                });
            }
            None => vec![1.0; x_m.len()],
        };
        match options.transient_iteration {
            ProfileIteration::PerRun => self.per_run(load_n, speed, options, x_m, alpha, record),
            ProfileIteration::InRun => self.in_run(load_n, speed, options, x_m, alpha, record),
        }
    }

    /// The transient's whole speed–thrust curve with the energy-conserving wave of `options`:
    /// the constant-amplitude curve's loads, stall search and operating point
    /// ([`TransientModel::solve`]), every run self-consistent, its profile warm-started from
    /// the previous run's (its speed as the constant curve's). Errors: as
    /// [`run_attenuated`](Self::run_attenuated).
    pub fn solve_attenuated(
        &self,
        options: &AttenuationOptions,
    ) -> Result<AttenuatedTransientResult> {
        self.solve_attenuated_until(options, &RunControl::none())
    }

    /// [`solve_attenuated`](Self::solve_attenuated) that asks `control` before each run.
    fn solve_attenuated_until(
        &self,
        options: &AttenuationOptions,
        control: &RunControl,
    ) -> Result<AttenuatedTransientResult> {
        options.validate()?;
        check_scene(self.scene(), "transient with the energy-conserving wave")?;
        // Every run starts as the constant-amplitude curve's does (its speed from the period
        // average's estimate at the load: runs near stall settle slowly, and the same start
        // keeps the weak-load limit the constant curve); the profile from the previous run's.
        let mut warm: Option<Vec<f64>> = None;
        let mut run = |model: &TransientModel, load: f64, start: TransientStart, record: bool| {
            let speed = model.initial_speed(load, start)?;
            let result =
                model.run_attenuated_from(load, speed, options, warm.as_deref(), record)?;
            warm = Some(result.amplitude_scale.clone());
            Ok(result)
        };
        let curve = self.curve_with(control, &mut run)?;
        let mut result = curve.result;
        result.model_reason = format!("{}; energy-conserving wave", result.model_reason);
        let all = || curve.points.iter().chain(std::iter::once(&curve.operating));
        Ok(AttenuatedTransientResult {
            power_in_w: options.power_in_w,
            max_balance_residual: all().map(|p| p.balance_residual).fold(0.0, f64::max),
            max_iterations: all().map(|p| p.iterations).max().unwrap_or(0),
            periods_simulated: curve.periods_simulated,
            runs: curve.runs,
            result,
            points: curve.points,
            operating: curve.operating,
        })
    }

    /// One whole run per fixed-point evaluation.
    fn per_run(
        &self,
        load_n: f64,
        mut speed: f64,
        options: &AttenuationOptions,
        x_m: Vec<f64>,
        alpha: Vec<f64>,
        record: bool,
    ) -> Result<AttenuatedRun> {
        let mut periods = 0;
        let mut iterations = 0;
        // A run the load pushes backwards has no steady state to be self-consistent with: it
        // ends the iteration and is reported as the plain run reports it (`steady` false).
        let mut backwards: Option<(TransientRun, Vec<f64>, Vec<f64>)> = None;
        let solution = solve_amplitude_profile(options, alpha, |alpha| {
            let (run, power) = self.run_from(load_n, speed, record, Some(alpha), None)?;
            let power = power.ok_or_else(|| stepper_refused(self.integrator().name()))?;
            speed = run.speed_m_per_s;
            periods += run.periods;
            iterations += 1;
            if !run.steady && run.speed_m_per_s < 0.0 {
                backwards = Some((run, alpha.to_vec(), power));
                return Err(None);
            }
            Ok::<_, Option<StickSlipError>>((power, run))
        });
        let (run, alpha, draw_w, last_change) = match (solution, backwards) {
            (Err(Some(e)), _) => return Err(e),
            (Err(None), Some((run, alpha, draw_w))) => {
                let target = profile_targets(options.power_in_w, &draw_w);
                let change = max_abs(
                    &target
                        .iter()
                        .zip(&alpha)
                        .map(|(t, a)| t - a)
                        .collect::<Vec<_>>(),
                );
                (run, alpha, draw_w, change)
            }
            (Err(None), None) => unreachable!("the iteration stops only on a backwards run"),
            (Ok(solution), _) if !solution.converged => {
                return Err(not_converged(solution.iterations, solution.last_change));
            }
            (Ok(solution), _) => (
                solution.value,
                solution.alpha,
                solution.draw_w,
                solution.last_change,
            ),
        };
        let mut result = AttenuatedRun::new(run, options, x_m, alpha, draw_w, last_change);
        result.iterations = iterations;
        result.periods_simulated = periods;
        Ok(result)
    }

    /// One run that adjusts the profile as it goes (module docs).
    fn in_run(
        &self,
        load_n: f64,
        speed: f64,
        options: &AttenuationOptions,
        x_m: Vec<f64>,
        alpha: Vec<f64>,
        record: bool,
    ) -> Result<AttenuatedRun> {
        let transient = &self.scene().options.transient;
        let periods = transient.periods.ceil() as usize;
        let window = (transient.average_periods.round() as usize).clamp(1, periods);
        let mut hook = InRunProfile {
            options: *options,
            power_unit_w: self.power_unit_w(),
            tangential_ratio: self.scene().wave.tangential_amplitude_m
                / self.scene().wave.normal_amplitude_m,
            window,
            base_window: window,
            settle_min: periods - window,
            settle_periods: IN_RUN_MAX_RUN_FACTOR * periods / 2,
            best_block_change: f64::INFINITY,
            blocks_without_progress: 0,
            max_periods: IN_RUN_MAX_RUN_FACTOR * periods,
            alpha: alpha.clone(),
            block_start: 0,
            block_work: None,
            frozen: false,
            history: Vec::new(),
            updates: 0,
            windows: 0,
            draw_w: Vec::new(),
            last_change: f64::INFINITY,
            converged: false,
            refused: false,
        };
        let (run, _) = self.run_from(load_n, speed, record, Some(&alpha), Some(&mut hook))?;
        if hook.refused {
            return Err(stepper_refused(self.integrator().name()));
        }
        if !hook.converged {
            // The window means fluctuate above the tolerance (slow quasi-periodic stick/slip):
            // finish with whole runs, from this run's profile and speed.
            let mut result =
                self.per_run(load_n, run.speed_m_per_s, options, x_m, hook.alpha, record)?;
            result.iterations += hook.windows;
            result.in_run_updates = hook.updates;
            result.periods_simulated += run.periods;
            return Ok(result);
        }
        let mut result =
            AttenuatedRun::new(run, options, x_m, hook.alpha, hook.draw_w, hook.last_change);
        result.iterations = hook.windows;
        result.in_run_updates = hook.updates;
        Ok(result)
    }
}

/// The in-run profile iteration (module docs): a [`PeriodHook`] on one run.
struct InRunProfile {
    options: AttenuationOptions,
    power_unit_w: f64,
    tangential_ratio: f64,
    /// Periods of an averaging window: `average_periods`, doubled once the window means'
    /// fluctuation keeps the change from falling.
    window: usize,
    base_window: usize,
    /// Periods before which the profile is not frozen: the plain run's settling
    /// (`periods − average_periods`), so a converged profile keeps the plain run's window.
    settle_min: usize,
    /// Periods after which the profile is frozen whatever the blocks say (half the longest
    /// run).
    settle_periods: usize,
    /// Smallest block change so far, and blocks since it last fell by a tenth.
    best_block_change: f64,
    blocks_without_progress: usize,
    /// Periods after which the run stops (`IN_RUN_MAX_RUN_FACTOR` × `periods`).
    max_periods: usize,
    /// The profile the stepper runs at.
    alpha: Vec<f64>,
    /// First period of the current block, and each group's work at its start.
    block_start: usize,
    block_work: Option<Vec<f64>>,
    /// Whether the profile is frozen for an averaging window.
    frozen: bool,
    /// (α, T(α) − α) of the windows so far (Anderson's history).
    history: Vec<(Vec<f64>, Vec<f64>)>,
    updates: usize,
    windows: usize,
    /// Draws of the last window (W).
    draw_w: Vec<f64>,
    last_change: f64,
    converged: bool,
    /// The stepper keeps no per-group work or cannot retune.
    refused: bool,
}

impl InRunProfile {
    /// Each group's mean draw (W) over `records` (the periods since `work_before`), and the
    /// residual T(α) − α.
    fn residual(
        &self,
        records: &[PeriodRecord],
        work_before: &[f64],
        work_now: &[f64],
    ) -> (Vec<f64>, Vec<f64>) {
        let time: f64 = records.iter().map(|r| r.sums.time).sum();
        let draw_w: Vec<f64> = work_before
            .iter()
            .zip(work_now)
            .map(|(b, a)| (a - b) / time * self.power_unit_w)
            .collect();
        let f = profile_targets(self.options.power_in_w, &draw_w)
            .iter()
            .zip(&self.alpha)
            .map(|(t, a)| t - a)
            .collect();
        (draw_w, f)
    }

    /// End of a block: update the profile, or freeze it for a window.
    fn end_block(
        &mut self,
        records: &[PeriodRecord],
        span: &mut Span,
        stepper: &mut dyn Stepper,
        work: &[f64],
    ) {
        let n = records.len();
        let before = self
            .block_work
            .take()
            .unwrap_or_else(|| vec![0.0; work.len()]);
        let block = &records[self.block_start..];
        let (_, f) = self.residual(block, &before, work);
        let change = max_abs(&f);
        // The blocks' own floor: the change has not fallen by a tenth for a few blocks.
        if change < 0.9 * self.best_block_change {
            self.best_block_change = change;
            self.blocks_without_progress = 0;
        } else {
            self.blocks_without_progress += 1;
        }
        let floor = self.blocks_without_progress >= IN_RUN_STALLED_BLOCKS;
        let settled = n >= self.settle_min && (change < self.options.tolerance || floor);
        if settled || n >= self.settle_periods {
            self.frozen = true;
            span.window_start = n;
            span.end = n + self.window;
            return;
        }
        for (a, r) in self.alpha.iter_mut().zip(&f) {
            *a = (*a + IN_RUN_RELAXATION * r).max(0.0);
        }
        self.refused |= !stepper.retune(&self.alpha);
        self.updates += 1;
        self.block_start = n;
        self.block_work = Some(work.to_vec());
        span.end = n + IN_RUN_BLOCK_PERIODS;
    }

    /// End of a window: accept the profile, or run the next window at the Anderson update.
    fn end_window(
        &mut self,
        records: &[PeriodRecord],
        span: &mut Span,
        stepper: &mut dyn Stepper,
        before: &[f64],
        work: &[f64],
    ) {
        let n = records.len();
        let tail = &records[span.window_start..];
        let (draw_w, f) = self.residual(tail, before, work);
        let previous_change = self.last_change;
        self.windows += 1;
        self.last_change = max_abs(&f);
        self.draw_w = draw_w;
        if self.last_change < self.options.tolerance {
            self.converged = true;
            return;
        }
        // A slider the load pushes backwards (beyond the stall thrust) has no steady state to
        // be self-consistent with: it is reported as the plain run reports it (`steady`
        // false), at its last profile, with the books of its window.
        if mean_speed(tail) < 0.0 && !is_steady(tail, self.tangential_ratio) {
            self.converged = true;
            return;
        }
        // A change that no longer halves is the window means' own fluctuation (quasi-periodic
        // stick/slip): a longer window averages it down; if that does not help either, the
        // per-run iteration (a deterministic map) finishes.
        let stagnating = self.last_change > 0.5 * previous_change;
        if self.windows >= self.options.max_iterations
            || n >= self.max_periods
            || (stagnating && self.window > self.base_window)
        {
            return;
        }
        if self
            .history
            .last()
            .is_some_and(|(_, g)| max_abs(g) < self.last_change)
        {
            self.history.clear();
        }
        let next = anderson_step(&self.alpha, &f, &self.history, self.options.relaxation);
        self.history.push((std::mem::take(&mut self.alpha), f));
        if self.history.len() > self.options.anderson_depth {
            self.history.remove(0);
        }
        self.alpha = next.into_iter().map(|a| a.max(0.0)).collect();
        self.refused |= !stepper.retune(&self.alpha);
        if stagnating {
            self.window *= 2;
        }
        span.window_start = n;
        span.end = n + self.window;
    }
}

fn max_abs(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m: f64, r| m.max(r.abs()))
}

impl PeriodHook for InRunProfile {
    fn after_period(
        &mut self,
        records: &[PeriodRecord],
        span: &mut Span,
        stepper: &mut dyn Stepper,
        window_work: Option<&[f64]>,
    ) -> Result<()> {
        let n = records.len();
        let Some(work) = stepper.group_stator_work().map(<[f64]>::to_vec) else {
            self.refused = true;
            span.end = n;
            return Ok(());
        };
        if self.refused {
            span.end = n;
        } else if !self.frozen {
            if n - self.block_start >= IN_RUN_BLOCK_PERIODS {
                self.end_block(records, span, stepper, &work);
            } else {
                span.end = n + 1;
            }
        } else if n == span.end {
            let before = window_work
                .map(<[f64]>::to_vec)
                .unwrap_or_else(|| vec![0.0; work.len()]);
            self.end_window(records, span, stepper, &before, &work);
        }
        if self.refused {
            span.end = n;
        }
        Ok(())
    }
}
