//! The transient model: every phase group at its real position, the slider's horizontal (and
//! optionally vertical) equations integrated to a steady state. Resolves what the period average
//! cannot: incommensurate pitch, light sliders, slider bounce, decaying waves, bursts, step
//! responses.

mod event_driven;
pub(crate) mod groups;
mod massive;
mod return_mapping;
pub(crate) mod run;
pub(crate) mod system;

use std::f64::consts::PI;
use std::time::Instant;

use serde::Serialize;

use crate::error::{Result, StickSlipError, Warning};
use crate::history::{PostHistory, SliderHistory};
use crate::integrator::{EVENT_DRIVEN_STEPS_PER_PERIOD, Integrator, RK4_STABILITY_BOUND};
use crate::periodic::PeriodicAverageModel;
use crate::result::{CurvePoint, DynamicResult, OperatingPoint, TransientSummary};
use crate::scene::{DynamicScene, ModelChoice, ModelKind, TransientStart};
use crate::slider::{PostLayout, VerticalModel};
use crate::solve::{ShouldStop, stop_check};

use event_driven::EventDriven;
use massive::{MassivePosts, TipFriction};
use return_mapping::ReturnMapping;
use run::STEADY_TOLERANCE;
use system::{SliderState, Stepper, System};

/// Safety factor on the RK4 stability bound for the default event-driven step.
const EVENT_DRIVEN_SAFETY: f64 = 0.5;
/// Speed (of the no-load speed) below which the slider counts as stalled in the stall search.
/// Default 1e-3.
const STALL_SPEED_FRACTION: f64 = 1e-3;
/// Smallest load scale of the transient curve, as a fraction of μ_k P, when the period-average
/// estimate finds the slider locked. Default 0.05.
const STALL_ESTIMATE_FLOOR: f64 = 0.05;
/// Largest number of runs of the stall search. Default 16.
const MAX_STALL_RUNS: usize = 16;

/// Result of one transient run at one load, SI, speeds and forces along the drive direction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransientRun {
    /// External load (N).
    pub load_n: f64,
    /// Mean speed along the drive direction (−x) over the averaging window (m/s).
    pub speed_m_per_s: f64,
    /// Mean slider velocity along +x, the wave's direction (m/s): negative for a working motor.
    pub velocity_x_m_per_s: f64,
    /// Mean total contact thrust over the averaging window (N).
    pub thrust_n: f64,
    /// Output power thrust × speed, ⟨ΣF·v⟩ (W).
    pub output_power_w: f64,
    /// Mechanical power from the stator through the tangential contacts (W).
    pub stator_power_w: f64,
    /// Friction dissipation (W).
    pub friction_dissipation_w: f64,
    /// Output over stator power.
    pub efficiency: f64,
    /// Time stuck over time in contact (post-weighted).
    pub stick_fraction: f64,
    /// Time in contact over time (post-weighted).
    pub contact_fraction: f64,
    /// (stator − output − dissipation − stored change)/stator over the window.
    pub energy_balance_residual: f64,
    /// Whether the mean speed stopped drifting over the window.
    pub steady: bool,
    /// Peak-to-peak speed over the window (m/s).
    pub speed_ripple_m_per_s: f64,
    /// Peak-to-peak tip height over the window (m).
    pub vertical_bounce_m: f64,
    /// Mean tip height z_s over the window (m).
    pub mean_tip_height_m: f64,
    /// Displacement over the whole run along the drive direction (m).
    pub displacement_m: f64,
    /// Largest instantaneous speed over the run (m/s).
    pub peak_speed_m_per_s: f64,
    /// Integration steps.
    pub steps: u64,
    /// Simulated wave periods.
    pub periods: usize,
    /// Mean speed of every period (m/s), for step responses.
    pub period_speed_m_per_s: Vec<f64>,
    /// Slider motion (if recorded).
    pub slider_history: Option<SliderHistory>,
    /// Forces on the first phase group's posts over the last periods (if recorded).
    pub post_history: Option<PostHistory>,
}

/// The transient model of a scene.
#[derive(Debug, Clone)]
pub struct TransientModel {
    scene: DynamicScene,
    estimate: Option<PeriodicAverageModel>,
    reason: String,
    warnings: Vec<Warning>,
    groups: usize,
}

impl TransientModel {
    /// Build the model: validates the scene and the integrator against the transient's
    /// stability limits (typed errors), builds the phase groups and a period-average estimate
    /// (used for warm starts and the stall bracket).
    pub fn new(scene: &DynamicScene) -> Result<Self> {
        let mut warnings = scene.validate()?;
        let setting = scene.stability_setting(ModelKind::Transient);
        let integrator = scene
            .integrator
            .resolve(ModelKind::Transient, scene.wave.period_s());
        for w in integrator.check(&setting, scene.wave.period_s(), scene.options.stability)? {
            if !warnings.contains(&w) {
                warnings.push(w);
            }
        }
        let reason = match scene.resolve_model()? {
            (ModelKind::Transient, reason) => reason,
            (ModelKind::PeriodicAverage, _) => {
                "transient model built directly (the scene alone would allow the period average)"
                    .into()
            }
        };
        if scene.wave.burst_periods.is_some() && scene.slider.vertical == VerticalModel::PeriodMean
        {
            warnings.push(Warning::new(
                "slider.vertical",
                "burst with quasi-static vertical model: z_s stays at the running-wave equilibrium, so posts hang free before and after the burst; use `dynamic`",
            ));
        }
        let estimate = PeriodicAverageModel::new(&Self::estimate_scene(scene)).ok();
        let groups = groups::Groups::build(scene).len();
        Ok(Self {
            scene: scene.clone(),
            estimate,
            reason,
            warnings,
            groups,
        })
    }

    /// The scene's continuous, uniform-height, quasi-static companion for the period average.
    fn estimate_scene(scene: &DynamicScene) -> DynamicScene {
        let mut companion = scene.clone();
        companion.model = ModelChoice::PeriodicAverage;
        companion.integrator = Integrator::default();
        companion.wave.burst_periods = None;
        companion.wave.decay_length_m = None;
        companion.slider.vertical = VerticalModel::PeriodMean;
        if let PostLayout::Positions { gap_m, .. } = &mut companion.slider.layout {
            *gap_m = None;
        }
        companion
    }

    /// The concrete integrator (`auto` resolved for the transient).
    pub fn integrator(&self) -> Integrator {
        self.scene
            .integrator
            .resolve(ModelKind::Transient, self.scene.wave.period_s())
    }

    /// Number of phase groups integrated.
    pub fn phase_groups(&self) -> usize {
        self.groups
    }

    /// The scene.
    pub fn scene(&self) -> &DynamicScene {
        &self.scene
    }

    /// The period-average estimate of the continuous companion scene, if it could be built.
    pub fn estimate(&self) -> Option<&PeriodicAverageModel> {
        self.estimate.as_ref()
    }

    fn stepper<'s>(&self, sys: &'s System, start: SliderState) -> Result<Box<dyn Stepper + 's>> {
        let omega = self.scene.wave.angular_frequency_rad_per_s();
        Ok(match self.integrator() {
            Integrator::Auto | Integrator::EventDriven { max_step_s: None } => {
                let slider_mode = (sys.rho.max(1.0) / sys.mass).sqrt();
                let h = (2.0 * PI / EVENT_DRIVEN_STEPS_PER_PERIOD)
                    .min(EVENT_DRIVEN_SAFETY * RK4_STABILITY_BOUND / slider_mode);
                Box::new(EventDriven::new(sys, h, start))
            }
            Integrator::EventDriven {
                max_step_s: Some(max_step_s),
            } => Box::new(EventDriven::new(sys, max_step_s * omega, start)),
            Integrator::ReturnMapping { dt_s } => {
                Box::new(ReturnMapping::new(sys, dt_s * omega, start))
            }
            Integrator::PostMass { dt_s } => Box::new(MassivePosts::new(
                sys,
                TipFriction::Coulomb,
                dt_s * omega,
                start,
            )?),
            Integrator::RegularizedExplicit {
                dt_s,
                regularization_speed_m_per_s,
            } => {
                let speed =
                    regularization_speed_m_per_s / (self.scene.wave.normal_amplitude_m * omega);
                Box::new(MassivePosts::new(
                    sys,
                    TipFriction::Regularized { speed },
                    dt_s * omega,
                    start,
                )?)
            }
        })
    }

    /// Run at one external load (N) from `start`; `record` keeps the slider history and the
    /// first group's force history over the last periods.
    pub fn run(&self, load_n: f64, start: TransientStart, record: bool) -> Result<TransientRun> {
        let speed = self.initial_speed(load_n, start)?;
        Ok(self.run_from(load_n, speed, record, None, None)?.0)
    }

    /// The initial slider speed of a run (m/s, drive direction).
    pub(crate) fn initial_speed(&self, load_n: f64, start: TransientStart) -> Result<f64> {
        crate::error::require_finite("load_n", load_n)?;
        Ok(match start {
            TransientStart::Rest => 0.0,
            TransientStart::Estimate => match &self.estimate {
                Some(estimate) => estimate.at_load(load_n)?.map_or(0.0, |s| s.speed_m_per_s),
                None => 0.0,
            },
        })
    }

    fn curve_point(run: &TransientRun) -> CurvePoint {
        CurvePoint {
            speed_m_per_s: run.speed_m_per_s,
            thrust_n: run.thrust_n,
            output_power_w: run.output_power_w,
            efficiency: run.efficiency,
            stick_fraction: run.stick_fraction,
        }
    }

    /// The full result: runs at `curve_loads` loads between 0 and the stall estimate, a stall
    /// search by bisection on the load, and the operating point at the external load.
    pub fn solve(&self) -> Result<DynamicResult> {
        self.solve_with_runs().map(|(result, _)| result)
    }

    /// As [`solve`](Self::solve), also returning the operating-point run (with histories).
    pub fn solve_with_runs(&self) -> Result<(DynamicResult, TransientRun)> {
        self.solve_with_runs_cancellable(&|| false)
    }

    /// [`solve_with_runs`](Self::solve_with_runs) that asks `should_stop` before each run (the
    /// operating point, each curve load, each step of the stall search).
    pub fn solve_with_runs_cancellable(
        &self,
        should_stop: ShouldStop<'_>,
    ) -> Result<(DynamicResult, TransientRun)> {
        let started = Instant::now();
        let scene = &self.scene;
        let options = &scene.options.transient;
        let mut warnings = self.warnings.clone();
        let load = scene.slider.external_load_n;
        // Steady quantities need a continuous wave: a burst is run as given for the operating
        // point, the curve comes from the continuous companion.
        let continuous = if scene.wave.burst_periods.is_some() {
            let mut companion = scene.clone();
            companion.wave.burst_periods = None;
            Some(Self::new(&companion)?)
        } else {
            None
        };
        let curve_model = continuous.as_ref().unwrap_or(self);
        let start = if scene.wave.burst_periods.is_some() {
            TransientStart::Rest
        } else {
            options.start
        };
        stop_check(should_stop, || "the operating-point run".into())?;
        let operating = self.run(load, start, true)?;
        let mut runs = 1;
        // A locked estimate (F(0⁺) ≤ 0) still needs a positive load scale for the curve.
        let stall_estimate = match &self.estimate {
            Some(e) => e.stall_thrust_n()?,
            None => scene.contact.mu_static * scene.slider.preload_n,
        }
        .max(STALL_ESTIMATE_FLOOR * scene.contact.mu_kinetic * scene.slider.preload_n);
        let mut points: Vec<TransientRun> = Vec::new();
        for i in 0..options.curve_loads.max(1) {
            let l = stall_estimate * i as f64 / options.curve_loads.max(1) as f64;
            stop_check(should_stop, || format!("the curve run at load {l:e} N"))?;
            points.push(curve_model.run(l, options.start, false)?);
            runs += 1;
        }
        let no_load = points[0].speed_m_per_s.max(0.0);
        let stalled = |run: &TransientRun| run.speed_m_per_s <= STALL_SPEED_FRACTION * no_load;
        let mut lo = points
            .iter()
            .filter(|r| !stalled(r))
            .map(|r| r.load_n)
            .fold(0.0, f64::max);
        let stall = if options.find_stall && no_load > 0.0 {
            let mut hi = stall_estimate.max(lo) * 1.1;
            let mut expansions = 0;
            loop {
                stop_check(should_stop, || {
                    format!("the stall-bracket run at load {hi:e} N")
                })?;
                let run = curve_model.run(hi, TransientStart::Estimate, false)?;
                runs += 1;
                if stalled(&run) {
                    break;
                }
                points.push(run);
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
                stop_check(should_stop, || {
                    format!("the stall-search run at load {mid:e} N")
                })?;
                let run = curve_model.run(mid, TransientStart::Estimate, false)?;
                runs += 1;
                iterations += 1;
                if stalled(&run) {
                    hi = mid;
                } else {
                    lo = mid;
                    points.push(run);
                }
            }
            0.5 * (lo + hi)
        } else if no_load <= 0.0 {
            warnings.push(Warning::new(
                "slider.preload_n",
                "the slider does not advance under no load (locked: posts never separate and stay stuck); stall thrust reported as 0",
            ));
            0.0
        } else {
            // Linear extrapolation of the two slowest points to zero speed.
            points.sort_by(|a, b| a.speed_m_per_s.total_cmp(&b.speed_m_per_s));
            match points.as_slice() {
                [a, b, ..] if b.speed_m_per_s > a.speed_m_per_s => {
                    a.thrust_n
                        - a.speed_m_per_s * (b.thrust_n - a.thrust_n)
                            / (b.speed_m_per_s - a.speed_m_per_s)
                }
                _ => stall_estimate,
            }
        };
        if points
            .iter()
            .chain(std::iter::once(&operating))
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
        points.sort_by(|a, b| a.speed_m_per_s.total_cmp(&b.speed_m_per_s));
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
                .filter(|r| r.speed_m_per_s > 0.0)
                .map(Self::curve_point),
        );
        if let Some(first) = points.first() {
            curve[0].stick_fraction = first.stick_fraction;
        }
        let efficiency = curve.iter().map(|p| p.efficiency).fold(0.0, f64::max);
        let max_power = curve.iter().map(|p| p.output_power_w).fold(0.0, f64::max);
        let operating_point =
            (load <= stall || scene.wave.burst_periods.is_some()).then_some(OperatingPoint {
                load_n: load,
                speed_m_per_s: operating.speed_m_per_s,
                thrust_n: operating.thrust_n,
                output_power_w: operating.output_power_w,
                stator_power_w: operating.stator_power_w,
                friction_dissipation_w: operating.friction_dissipation_w,
                efficiency: operating.efficiency,
                stick_fraction: operating.stick_fraction,
                contact_fraction: operating.contact_fraction,
                energy_balance_residual: operating.energy_balance_residual,
            });
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
            transient: Some(TransientSummary {
                phase_groups: self.groups,
                periods_per_run: options.periods,
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
            }),
        };
        Ok((result, operating))
    }
}
