//! The transient model: every phase group at its real position, the slider's horizontal (and
//! optionally vertical) equations integrated to a steady state. Resolves what the period average
//! cannot: incommensurate pitch, light sliders, slider bounce, decaying waves, bursts, step
//! responses.

mod curve;
mod event_driven;
pub(crate) mod groups;
mod massive;
mod return_mapping;
pub(crate) mod run;
pub(crate) mod system;

pub(crate) use curve::CurveRun;

use std::f64::consts::PI;

use serde::Serialize;

use crate::error::{Result, Warning};
use crate::history::{PostHistory, SliderHistory};
use crate::integrator::{EVENT_DRIVEN_STEPS_PER_PERIOD, Integrator, RK4_STABILITY_BOUND};
use crate::periodic::PeriodicAverageModel;
use crate::scene::{DynamicScene, ModelChoice, ModelKind, TransientStart};
use crate::slider::{PostLayout, VerticalModel};

use event_driven::EventDriven;
use massive::{MassivePosts, TipFriction};
use return_mapping::ReturnMapping;
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
}
