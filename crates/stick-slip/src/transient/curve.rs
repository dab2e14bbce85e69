//! The transient's speed–thrust curve: the operating-point run at the external load, runs at
//! `curve_loads` loads evenly from 0 to the period average's stall estimate, then the stall
//! thrust by bracketing and bisection on the load (a run counts as stalled below 1e-3 of the
//! no-load speed; `stall_tolerance` relative), or by linear extrapolation of the two slowest
//! runs to zero speed without the search. The curve is the stall point (0, stall thrust) and
//! every moving run sorted by speed.
//!
//! One curve for every kind of run: the caller passes the run (a closure of model, load, start
//! and whether to record histories) and gets back its own runs beside the result — the plain
//! constant-amplitude run ([`TransientModel::solve`]) or the self-consistent run with the
//! energy-conserving wave ([`TransientModel::solve_attenuated`]). The stall point (v → 0⁺)
//! carries the slowest run's stick fraction and is backed by the slowest moving run (the same
//! run unless a curve load beyond the stall thrust slid the slider backwards).

use std::time::Instant;

use crate::error::stop_check;
use crate::error::{Result, StickSlipError, Warning};
use crate::integrator::Integrator;
use crate::result::{CurvePoint, DynamicResult, OperatingPoint, TransientSummary};
use crate::scene::{ModelKind, TransientStart};
use run_control::RunControl;

use super::run::STEADY_TOLERANCE;
use super::{
    MAX_STALL_RUNS, STALL_ESTIMATE_FLOOR, STALL_SPEED_FRACTION, TransientModel, TransientRun,
};

/// What a curve run returns: the transient run and whatever the caller keeps with it.
pub(crate) trait CurveRun: Clone {
    /// The run.
    fn run(&self) -> &TransientRun;
    /// Wave periods simulated to produce it.
    fn periods_simulated(&self) -> usize {
        self.run().periods
    }
}

impl CurveRun for TransientRun {
    fn run(&self) -> &TransientRun {
        self
    }
}

/// A transient curve with the caller's runs.
#[derive(Debug, Clone)]
pub(crate) struct Curve<R> {
    pub result: DynamicResult,
    /// The run at the external load (with histories).
    pub operating: R,
    /// The run behind each point of `result.curve`, in its order (the stall point: the slowest
    /// moving run).
    pub points: Vec<R>,
    /// Runs made.
    pub runs: usize,
    /// Wave periods simulated in all runs.
    pub periods_simulated: usize,
}

/// The runs of a curve before assembly.
struct Runs<R> {
    operating: R,
    points: Vec<R>,
    stall_n: f64,
    no_load_m_per_s: f64,
    runs: usize,
    periods_simulated: usize,
}

/// The run a curve asks for: model, load (N), start, record histories.
pub(crate) type RunAt<'a, R> =
    dyn FnMut(&TransientModel, f64, TransientStart, bool) -> Result<R> + 'a;

fn curve_point(run: &TransientRun) -> CurvePoint {
    CurvePoint {
        speed_m_per_s: run.speed_m_per_s,
        thrust_n: run.thrust_n,
        output_power_w: run.output_power_w,
        efficiency: run.efficiency,
        stick_fraction: run.stick_fraction,
    }
}

impl TransientModel {
    /// The full result: runs at `curve_loads` loads between 0 and the stall estimate, a stall
    /// search by bisection on the load, and the operating point at the external load.
    pub fn solve(&self) -> Result<DynamicResult> {
        self.solve_with_runs(&RunControl::none())
            .map(|(result, _)| result)
    }

    /// As [`solve`](Self::solve), also returning the operating-point run (with histories);
    /// `control` is asked before each run (the operating point, each curve load, each step of
    /// the stall search).
    pub fn solve_with_runs(&self, control: &RunControl) -> Result<(DynamicResult, TransientRun)> {
        let curve = self.curve_with(control, &mut |model, load, start, record| {
            model.run(load, start, record)
        })?;
        Ok((curve.result, curve.operating))
    }

    /// The curve (module docs) with `run` as the run at each load.
    pub(crate) fn curve_with<R: CurveRun>(
        &self,
        control: &RunControl,
        run: &mut RunAt<'_, R>,
    ) -> Result<Curve<R>> {
        let started = Instant::now();
        let mut warnings = self.warnings.clone();
        // Steady quantities need a continuous wave: a burst is run as given for the operating
        // point, the curve comes from the continuous companion.
        let continuous = if self.scene.wave.burst_periods.is_some() {
            let mut companion = self.scene.clone();
            companion.wave.burst_periods = None;
            Some(Self::new(&companion)?)
        } else {
            None
        };
        let curve_model = continuous.as_ref().unwrap_or(self);
        let mut periods_simulated = 0;
        let mut counted = |model: &TransientModel, load, start, record| {
            let result = run(model, load, start, record)?;
            periods_simulated += result.periods_simulated();
            Ok(result)
        };
        let mut runs = self.curve_runs(curve_model, control, &mut counted, &mut warnings)?;
        runs.periods_simulated = periods_simulated;
        Ok(self.assemble(runs, warnings, started))
    }

    /// The operating-point run, the curve loads and the stall search.
    fn curve_runs<R: CurveRun>(
        &self,
        curve_model: &TransientModel,
        control: &RunControl,
        run: &mut RunAt<'_, R>,
        warnings: &mut Vec<Warning>,
    ) -> Result<Runs<R>> {
        let scene = &self.scene;
        let options = &scene.options.transient;
        let load = scene.slider.external_load_n;
        let start = if scene.wave.burst_periods.is_some() {
            TransientStart::Rest
        } else {
            options.start
        };
        stop_check(control, || "the operating-point run".into())?;
        let operating = run(self, load, start, true)?;
        let mut runs = 1;
        // A locked estimate (F(0⁺) ≤ 0) still needs a positive load scale for the curve.
        let stall_estimate = match &self.estimate {
            Some(e) => e.stall_thrust_n()?,
            None => scene.contact.mu_static * scene.slider.preload_n,
        }
        .max(STALL_ESTIMATE_FLOOR * scene.contact.mu_kinetic * scene.slider.preload_n);
        let mut points: Vec<R> = Vec::new();
        for i in 0..options.curve_loads.max(1) {
            let l = stall_estimate * i as f64 / options.curve_loads.max(1) as f64;
            stop_check(control, || format!("the curve run at load {l:e} N"))?;
            points.push(run(curve_model, l, options.start, false)?);
            runs += 1;
        }
        let no_load = points[0].run().speed_m_per_s.max(0.0);
        let stalled = |run: &TransientRun| run.speed_m_per_s <= STALL_SPEED_FRACTION * no_load;
        let lo = points
            .iter()
            .map(CurveRun::run)
            .filter(|r| !stalled(r))
            .map(|r| r.load_n)
            .fold(0.0, f64::max);
        let stall = if options.find_stall && no_load > 0.0 {
            let bracket = (lo, stall_estimate.max(lo) * 1.1);
            self.stall_search(curve_model, control, run, &mut points, bracket, &mut runs)?
        } else if no_load <= 0.0 {
            warnings.push(Warning::new(
                "slider.preload_n",
                "the slider does not advance under no load (locked: posts never separate and stay stuck); stall thrust reported as 0",
            ));
            0.0
        } else {
            extrapolated_stall(&mut points, stall_estimate)
        };
        Ok(Runs {
            operating,
            points,
            stall_n: stall,
            no_load_m_per_s: no_load,
            runs,
            periods_simulated: 0,
        })
    }

    /// The stall thrust by bracketing from `bracket` = (lo, hi) (hi × 1.25 until a run stalls,
    /// at most 6 times) and bisection to `stall_tolerance`; the runs that move are added to
    /// `points`, every run counted in `runs`.
    fn stall_search<R: CurveRun>(
        &self,
        curve_model: &TransientModel,
        control: &RunControl,
        run: &mut RunAt<'_, R>,
        points: &mut Vec<R>,
        bracket: (f64, f64),
        runs: &mut usize,
    ) -> Result<f64> {
        let options = &self.scene.options.transient;
        let no_load = points[0].run().speed_m_per_s.max(0.0);
        let stalled = |run: &TransientRun| run.speed_m_per_s <= STALL_SPEED_FRACTION * no_load;
        let (mut lo, mut hi) = bracket;
        let mut expansions = 0;
        loop {
            stop_check(control, || {
                format!("the stall-bracket run at load {hi:e} N")
            })?;
            let result = run(curve_model, hi, TransientStart::Estimate, false)?;
            *runs += 1;
            if stalled(result.run()) {
                break;
            }
            points.push(result);
            lo = hi;
            hi *= 1.25;
            expansions += 1;
            if expansions > 6 {
                return Err(StickSlipError::NotConverged {
                    model: "transient",
                    what: "upper bracket of the stall thrust",
                    iterations: expansions,
                    residual: hi,
                });
            }
        }
        let mut iterations = 0;
        while hi - lo > options.stall_tolerance * hi && iterations < MAX_STALL_RUNS {
            let mid = 0.5 * (lo + hi);
            stop_check(control, || {
                format!("the stall-search run at load {mid:e} N")
            })?;
            let result = run(curve_model, mid, TransientStart::Estimate, false)?;
            *runs += 1;
            iterations += 1;
            if stalled(result.run()) {
                hi = mid;
            } else {
                lo = mid;
                points.push(result);
            }
        }
        Ok(0.5 * (lo + hi))
    }

    /// Warnings on the runs: not steady after the periods asked, or an energy balance residual
    /// above 1 % at the operating point (neither for a burst).
    fn run_warnings<R: CurveRun>(
        &self,
        points: &[R],
        operating: &TransientRun,
        warnings: &mut Vec<Warning>,
    ) {
        let scene = &self.scene;
        let options = &scene.options.transient;
        if points
            .iter()
            .map(CurveRun::run)
            .chain(std::iter::once(operating))
            .any(|r| !r.steady)
            && scene.wave.burst_periods.is_none()
        {
            warnings.push(Warning::new(
                "options.transient.periods",
                format!(
                    "some runs had not reached a steady speed after {} periods (drift above {STEADY_TOLERANCE:.0e})",
                    options.periods
                ),
            ));
        }
        let residual_limit = 1e-2;
        if operating.energy_balance_residual.abs() > residual_limit
            && scene.wave.burst_periods.is_none()
        {
            warnings.push(Warning::new(
                "integrator",
                format!(
                    "energy balance residual {:.2e} at the operating point: the step is coarse for this scene",
                    operating.energy_balance_residual
                ),
            ));
        }
    }

    /// The transient's own summary of the operating-point run (`runs`: runs of the curve).
    fn summary(&self, operating: &TransientRun, runs: usize) -> TransientSummary {
        let scene = &self.scene;
        TransientSummary {
            phase_groups: self.groups,
            periods_per_run: scene.options.transient.periods,
            runs,
            steady: operating.steady,
            speed_ripple_m_per_s: operating.speed_ripple_m_per_s,
            vertical_bounce_m: operating.vertical_bounce_m,
            steps: operating.steps,
            burst_displacement_m: scene.wave.burst_periods.map(|_| operating.displacement_m),
            burst_peak_speed_m_per_s: scene
                .wave
                .burst_periods
                .map(|_| operating.peak_speed_m_per_s),
        }
    }

    /// The result of the curve's runs.
    fn assemble<R: CurveRun>(
        &self,
        runs: Runs<R>,
        mut warnings: Vec<Warning>,
        started: Instant,
    ) -> Curve<R> {
        let scene = &self.scene;
        let load = scene.slider.external_load_n;
        let Runs {
            operating: operating_run,
            mut points,
            stall_n: stall,
            no_load_m_per_s: no_load,
            runs,
            periods_simulated,
        } = runs;
        let operating = operating_run.run();
        self.run_warnings(&points, operating, &mut warnings);
        points.sort_by(|a, b| a.run().speed_m_per_s.total_cmp(&b.run().speed_m_per_s));
        let curve = curve_of(&points, stall);
        let efficiency = curve.iter().map(|p| p.efficiency).fold(0.0, f64::max);
        let max_power = curve.iter().map(|p| p.output_power_w).fold(0.0, f64::max);
        let operating_point = (load <= stall || scene.wave.burst_periods.is_some())
            .then(|| operating_point(load, operating));
        if operating_point.is_none() {
            warnings.push(Warning::new(
                "slider.external_load_n",
                format!("load {load} N exceeds the stall thrust {stall:.4} N: the slider does not advance"),
            ));
        }
        let result = DynamicResult {
            model: ModelKind::Transient,
            model_reason: self.reason.clone(),
            integrator: match self.integrator() {
                Integrator::ReturnMapping { dt_s } => format!(
                    "return-mapping (dt = T/{:.0})",
                    scene.wave.period_s() / dt_s
                ),
                other => other.name().to_string(),
            },
            stall_thrust_n: stall,
            no_load_speed_m_per_s: no_load,
            curve,
            stick_fraction: operating.stick_fraction,
            contact_fraction: operating.contact_fraction,
            efficiency,
            max_output_power_w: max_power,
            operating_point,
            effective_post_count: scene.slider.effective_post_count(),
            mean_normal_force_per_post_n: scene.mean_normal_force_per_post_n(),
            tip_height_m: operating.mean_tip_height_m,
            friction_limit_n: scene.contact.mu_kinetic * scene.slider.preload_n,
            crest_speed_m_per_s: scene.wave.crest_speed_m_per_s(),
            wall_time_s: started.elapsed().as_secs_f64(),
            warnings,
            transient: Some(self.summary(operating, runs)),
        };
        // The run behind each curve point: the slowest moving run backs the stall point (a
        // curve load beyond the stall thrust slides the slider backwards: not a stall state).
        let slowest = points
            .iter()
            .position(|r| r.run().speed_m_per_s > 0.0)
            .unwrap_or(0);
        let mut backing: Vec<R> = points.get(slowest).cloned().into_iter().collect();
        backing.extend(points.into_iter().filter(|r| r.run().speed_m_per_s > 0.0));
        Curve {
            result,
            operating: operating_run,
            points: backing,
            runs,
            periods_simulated,
        }
    }
}

/// The stall thrust by linear extrapolation of the two slowest points to zero speed (sorts
/// `points` by speed); `stall_estimate` if they do not bracket a slope.
fn extrapolated_stall<R: CurveRun>(points: &mut [R], stall_estimate: f64) -> f64 {
    points.sort_by(|a, b| a.run().speed_m_per_s.total_cmp(&b.run().speed_m_per_s));
    match &*points {
        [a, b, ..] if b.run().speed_m_per_s > a.run().speed_m_per_s => {
            let (a, b) = (a.run(), b.run());
            a.thrust_n
                - a.speed_m_per_s * (b.thrust_n - a.thrust_n) / (b.speed_m_per_s - a.speed_m_per_s)
        }
        _ => stall_estimate,
    }
}

/// The curve: the stall point (stall thrust at zero speed, the slowest run's stick fraction),
/// then every run that moves, in the order of `points` (sorted by speed).
fn curve_of<R: CurveRun>(points: &[R], stall: f64) -> Vec<CurvePoint> {
    let mut curve = vec![CurvePoint {
        speed_m_per_s: 0.0,
        thrust_n: stall,
        output_power_w: 0.0,
        efficiency: 0.0,
        stick_fraction: f64::NAN,
    }];
    curve.extend(
        points
            .iter()
            .map(CurveRun::run)
            .filter(|r| r.speed_m_per_s > 0.0)
            .map(curve_point),
    );
    if let Some(first) = points.first() {
        curve[0].stick_fraction = first.run().stick_fraction;
    }
    curve
}

/// The operating point at the external load `load_n` from its run.
fn operating_point(load_n: f64, operating: &TransientRun) -> OperatingPoint {
    OperatingPoint {
        load_n,
        speed_m_per_s: operating.speed_m_per_s,
        thrust_n: operating.thrust_n,
        output_power_w: operating.output_power_w,
        stator_power_w: operating.stator_power_w,
        friction_dissipation_w: operating.friction_dissipation_w,
        efficiency: operating.efficiency,
        stick_fraction: operating.stick_fraction,
        contact_fraction: operating.contact_fraction,
        energy_balance_residual: operating.energy_balance_residual,
    }
}
