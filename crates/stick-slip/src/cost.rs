//! Size and cost of a run, estimated before anything is allocated or integrated.
//!
//! * Memory: the transient keeps one record per simulated wave period, the histories one sample
//!   per `1/samples_per_period` period, the curve one point per curve point, and the layout one
//!   column per distinct post position. Their sum ([`DynamicScene::memory_estimate`]) is refused
//!   above [`SolveOptions::max_memory_bytes`] (default [`MAX_RUN_MEMORY_BYTES`]).
//! * Work: post-steps = time steps per wave period × wave periods per solve × phase groups
//!   stepped × solves ([`DynamicScene::work_estimate`]); refused above
//!   [`SolveOptions::max_post_steps`] (default [`MAX_POST_STEPS`]). The closed-form event-driven
//!   period average has no time steps and is not limited.
//!
//! Range of validity: upper bounds (the stall search usually stops before its last run); the
//! event-driven transient's event handling is counted as a measured step-equivalent per period.

use crate::error::{Result, StickSlipError};
use crate::history::ContactState;
use crate::integrator::{EVENT_DRIVEN_STEPS_PER_PERIOD, Integrator};
use crate::result::CurvePoint;
use crate::scene::{DynamicScene, ModelKind, SolveOptions};
use crate::slider::PostLayout;

pub use crate::limits::{MAX_POST_STEPS, MAX_RUN_MEMORY_BYTES};
/// Wave periods a fixed-step period average integrates per speed, at most (its periodic steady
/// state search, `post::stepping`). Default 64.
const PERIOD_AVERAGE_PERIODS_PER_SPEED: f64 = 64.0;
/// Speeds the period average evaluates besides the curve points (stall and operating-point root
/// finding), at most. Default 60.
const PERIOD_AVERAGE_EXTRA_SPEEDS: f64 = 60.0;
/// Runs of the transient's stall search, at most: bracket expansions (7) and bisections (16).
const TRANSIENT_STALL_RUNS: f64 = 23.0;
/// Step-equivalents per wave period that the event-driven transient spends on its events
/// (≈ 4 stick/slip transitions per group, each a located root and an RK4 restart), on top of
/// its RK4 steps. Default 900: the event-driven transient of the 10 × 10-post scene (64 RK4
/// steps per period) takes ≈ 4 × the wall time of the 256-step return mapping (5.6 s against
/// 1.5 s, `sawdrive dynamic tests/scenes/small-strip.toml --set effective_ratio=0.36 --set
/// model.lumped.integrator=…`).
const EVENT_DRIVEN_EVENT_STEPS_PER_PERIOD: f64 = 900.0;
/// Bytes of one transient period record (sums, extrema, stored energy) and its mean speed.
const TRANSIENT_BYTES_PER_PERIOD: f64 = 256.0;
/// Bytes of one post-history sample: five f64 series and the contact state.
const POST_HISTORY_BYTES_PER_SAMPLE: f64 =
    (5 * size_of::<f64>() + size_of::<ContactState>()) as f64;

/// Estimated memory of a run, by part (bytes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MemoryEstimate {
    /// Transient per-period records (`options.transient.periods`).
    pub periods_bytes: f64,
    /// Post history (`options.history`).
    pub history_bytes: f64,
    /// Speed–thrust curve (`options.curve_points`).
    pub curve_bytes: f64,
    /// Post columns of the layout.
    pub layout_bytes: f64,
}

impl MemoryEstimate {
    /// Sum of the parts (bytes).
    pub fn total_bytes(&self) -> f64 {
        self.periods_bytes + self.history_bytes + self.curve_bytes + self.layout_bytes
    }

    /// The largest part, named by the option that sets it.
    fn largest(&self) -> &'static str {
        [
            (self.periods_bytes, "options.transient.periods"),
            (self.history_bytes, "options.history"),
            (self.curve_bytes, "options.curve_points"),
            (self.layout_bytes, "slider.layout"),
        ]
        .into_iter()
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map_or("options", |p| p.1)
    }
}

/// Estimated work of a run: post-steps = steps per period × periods × groups × solves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorkEstimate {
    /// Time steps per wave period of the integrator (0: closed form).
    pub steps_per_period: f64,
    /// Wave periods integrated per solve.
    pub periods_per_solve: f64,
    /// Phase groups (posts integrated separately).
    pub groups: f64,
    /// Solves (transient runs, or period-average speeds), at most.
    pub solves: f64,
}

impl WorkEstimate {
    /// Total post-steps.
    pub fn post_steps(&self) -> f64 {
        self.steps_per_period * self.periods_per_solve * self.groups * self.solves
    }
}

impl DynamicScene {
    /// Memory the run of `model` will hold, estimated from the options before allocating.
    pub fn memory_estimate(&self, model: ModelKind) -> MemoryEstimate {
        let o = &self.options;
        let periods_bytes = match model {
            ModelKind::Transient => o.transient.periods.ceil() * TRANSIENT_BYTES_PER_PERIOD,
            ModelKind::PeriodicAverage => 0.0,
        };
        let columns = match &self.slider.layout {
            PostLayout::SquareArray { posts_per_side, .. } => *posts_per_side as f64,
            PostLayout::Positions { x_m, .. } => x_m.len() as f64,
            PostLayout::UniformPhase { post_count } => {
                (o.transient.uniform_phase_groups.min(*post_count)) as f64
            }
        };
        MemoryEstimate {
            periods_bytes,
            history_bytes: o.history.periods.ceil()
                * o.history.samples_per_period as f64
                * POST_HISTORY_BYTES_PER_SAMPLE,
            curve_bytes: (o.curve_points.max(o.transient.curve_loads) as f64
                + PERIOD_AVERAGE_EXTRA_SPEEDS)
                * size_of::<CurvePoint>() as f64,
            layout_bytes: columns * 3.0 * size_of::<f64>() as f64,
        }
    }

    /// Work of the run of `model` with the integrator `integrator` (already resolved for
    /// `model`), estimated before integrating.
    pub fn work_estimate(&self, model: ModelKind, integrator: &Integrator) -> WorkEstimate {
        let period = self.wave.period_s();
        let o = &self.options;
        let steps_per_period = match (*integrator, model) {
            (Integrator::Auto, _) => 0.0,
            (Integrator::EventDriven { .. }, ModelKind::PeriodicAverage) => 0.0,
            (Integrator::EventDriven { max_step_s }, ModelKind::Transient) => {
                let rk4 = max_step_s.map_or(EVENT_DRIVEN_STEPS_PER_PERIOD, |h| {
                    (period / h).max(EVENT_DRIVEN_STEPS_PER_PERIOD)
                });
                rk4 + EVENT_DRIVEN_EVENT_STEPS_PER_PERIOD
            }
            (other, _) => other.fixed_step_s().map_or(0.0, |dt| (period / dt).ceil()),
        };
        match model {
            ModelKind::Transient => WorkEstimate {
                steps_per_period,
                periods_per_solve: o.transient.periods.ceil(),
                groups: self.memory_estimate(model).layout_bytes / (3.0 * 8.0),
                solves: 1.0 + o.transient.curve_loads as f64 + TRANSIENT_STALL_RUNS,
            },
            ModelKind::PeriodicAverage => WorkEstimate {
                steps_per_period,
                periods_per_solve: PERIOD_AVERAGE_PERIODS_PER_SPEED,
                groups: 1.0,
                solves: o.curve_points as f64 + PERIOD_AVERAGE_EXTRA_SPEEDS,
            },
        }
    }

    /// Refuse a run whose memory or work estimate exceeds the options' limits (typed errors
    /// carrying the estimate and the limit).
    pub(crate) fn check_size(&self, model: ModelKind, integrator: &Integrator) -> Result<()> {
        let o: &SolveOptions = &self.options;
        let memory = self.memory_estimate(model);
        if exceeds(memory.total_bytes(), o.max_memory_bytes) {
            return Err(StickSlipError::MemoryLimit {
                parameter: memory.largest(),
                estimate_bytes: memory.total_bytes(),
                limit_bytes: o.max_memory_bytes,
            });
        }
        let work = self.work_estimate(model, integrator);
        if exceeds(work.post_steps(), o.max_post_steps) {
            return Err(StickSlipError::CostLimit {
                integrator: integrator.name(),
                estimate_post_steps: work.post_steps(),
                limit_post_steps: o.max_post_steps,
                detail: format!(
                    "{:.3e} steps per period × {:.0} periods × {:.0} phase groups × ≤ {:.0} solves",
                    work.steps_per_period, work.periods_per_solve, work.groups, work.solves
                ),
            });
        }
        Ok(())
    }
}

/// Whether an estimate exceeds its limit (a NaN estimate counts as exceeding).
fn exceeds(estimate: f64, limit: f64) -> bool {
    estimate.is_nan() || estimate > limit
}
