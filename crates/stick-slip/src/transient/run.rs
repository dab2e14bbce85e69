//! One transient run: the slider integrated period by period from a given speed, the steady
//! values as means over an averaging window of whole periods at the end of the run.
//!
//! A plain run lasts `options.transient.periods` periods and averages the last
//! `options.transient.average_periods` of them. A [`PeriodHook`] (the energy-conserving wave's
//! in-run profile, `crate::attenuation`) sees every period's record and may change the amplitude
//! profile of the stepper, move the start of the averaging window and extend the run: the
//! window's means are then those of the periods since the window's last start, and the run ends
//! when the hook stops extending it. Without a hook the arithmetic is the plain run's, bit for
//! bit.

use std::f64::consts::PI;

use super::system::{Stepper, Sums, System};
use super::{SliderState, TransientModel, TransientRun};
use crate::error::Result;
use crate::history::{PostHistory, SliderHistory};

/// Largest number of samples of a recorded slider history (keeps charts small). Default 4000.
const MAX_SLIDER_SAMPLES: f64 = 4000.0;
/// Relative speed drift (first vs second half of the averaging window, of the larger of the
/// mean speed and 1e-3 A_t ω) below which a run counts as steady. Default 1e-3.
pub(crate) const STEADY_TOLERANCE: f64 = 1e-3;

/// One wave period's record.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct PeriodRecord {
    pub sums: Sums,
    /// Slider displacement over the period (solver units, along +x).
    pub dx: f64,
    v_min: f64,
    v_max: f64,
    z_min: f64,
    z_max: f64,
    z_time: f64,
    stored_change: f64,
}

/// Where a run's averaging window starts and where the run ends (period indices).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Span {
    /// First period of the averaging window.
    pub window_start: usize,
    /// Periods in the run.
    pub end: usize,
}

/// Sees a run period by period and may steer it (the amplitude profile, the window, the end).
pub(crate) trait PeriodHook {
    /// Called after every period with all records so far; `window_work` is each group's
    /// cumulative stator work at the window's start (solver units, `None` without per-group
    /// work). May retune `stepper`, and move `span.window_start` (to `records.len()`, the next
    /// period) and `span.end` (never below `records.len()`).
    fn after_period(
        &mut self,
        records: &[PeriodRecord],
        span: &mut Span,
        stepper: &mut dyn Stepper,
        window_work: Option<&[f64]>,
    ) -> Result<()>;
}

/// Mean speed of `records` along the drive direction (solver units).
pub(crate) fn mean_speed(records: &[PeriodRecord]) -> f64 {
    let (x, t) = records
        .iter()
        .fold((0.0, 0.0), |(x, t), r| (x + r.dx, t + r.sums.time));
    -x / t
}

/// Whether the speed over `window` stopped drifting: first half against second half within
/// [`STEADY_TOLERANCE`] of the larger of the mean speed and 1e-3 `tangential_ratio`.
pub(crate) fn is_steady(window: &[PeriodRecord], tangential_ratio: f64) -> bool {
    let half = window.len() / 2;
    let drift = if half >= 1 {
        (mean_speed(&window[..half]) - mean_speed(&window[half..])).abs()
    } else {
        0.0
    };
    let (dx, time) = window
        .iter()
        .fold((0.0, 0.0), |(x, t), r| (x + r.dx, t + r.sums.time));
    let mean = -dx / time;
    drift <= STEADY_TOLERANCE * mean.abs().max(1e-3 * tangential_ratio)
}

/// What the period loop produced.
struct Integrated {
    records: Vec<PeriodRecord>,
    span: Span,
    window_work: Option<Vec<f64>>,
    peak_speed: f64,
    slider_history: Option<SliderHistory>,
    post_history: Option<PostHistory>,
}

impl TransientModel {
    /// Power unit of the solver (W): N_eff k_n A_n × A_n ω.
    pub(crate) fn power_unit_w(&self) -> f64 {
        let scene = &self.scene;
        let a_n = scene.wave.normal_amplitude_m;
        scene.slider.effective_post_count()
            * scene.contact.k_n_n_per_m
            * a_n
            * a_n
            * scene.wave.angular_frequency_rad_per_s()
    }

    /// A run from `initial_speed` (m/s) with an amplitude factor per column (`profile`) or the
    /// scene's own wave; also returns each group's mean stator power over the averaging window
    /// (W, whole slider; `None` if the stepper does not keep it per group). `hook` may steer
    /// the run ([`PeriodHook`]).
    pub(crate) fn run_from(
        &self,
        load_n: f64,
        initial_speed: f64,
        record: bool,
        profile: Option<&[f64]>,
        hook: Option<&mut dyn PeriodHook>,
    ) -> Result<(TransientRun, Option<Vec<f64>>)> {
        let scene = &self.scene;
        let a_n = scene.wave.normal_amplitude_m;
        let omega = scene.wave.angular_frequency_rad_per_s();
        let sys = System::new(scene, load_n, profile);
        let start_state = SliderState {
            t: sys.t_start,
            x: 0.0,
            v: -initial_speed / (a_n * omega),
            z: sys.initial_height(),
            w: 0.0,
        };
        let mut stepper = self.stepper(&sys, start_state)?;
        let integrated = self.integrate(&mut *stepper, record, hook)?;
        Ok(self.summarise(load_n, &*stepper, integrated))
    }

    /// The period loop: steps the stepper period by period, records each period (and the
    /// histories if `record`), asks `hook` after every period.
    fn integrate(
        &self,
        stepper: &mut dyn Stepper,
        record: bool,
        mut hook: Option<&mut dyn PeriodHook>,
    ) -> Result<Integrated> {
        let scene = &self.scene;
        let options = &scene.options.transient;
        let units = HistoryUnits::of(scene);
        let t_start = stepper.state().t;
        let periods = options.periods.ceil() as usize;
        let window = (options.average_periods.round() as usize).clamp(1, periods);
        let mut span = Span {
            window_start: periods - window,
            end: periods,
        };
        let history_periods = scene.options.history.periods.ceil() as usize;
        let history_from = periods.saturating_sub(history_periods.max(1));
        let sample_spacing = 2.0 * PI / scene.options.history.samples_per_period as f64;
        let mut slider_history = record.then(SliderHistory::default);
        let mut post_history = record.then(PostHistory::default);
        let slider_spacing = sample_spacing.max(2.0 * PI * periods as f64 / MAX_SLIDER_SAMPLES);
        let mut next_sample = t_start;
        let mut next_slider_sample = t_start;
        let mut records = Vec::with_capacity(periods);
        let mut peak_speed = f64::NEG_INFINITY;
        let t_unit = units.t_unit;
        let mut window_work: Option<Vec<f64>> = None;
        let mut j = 0;
        while j < span.end {
            if j == span.window_start {
                window_work = stepper.group_stator_work().map(<[f64]>::to_vec);
            }
            let t_end = t_start + 2.0 * PI * (j + 1) as f64;
            let first = stepper.state();
            let stored0 = stepper.stored_energy();
            let mut rec = PeriodRecord {
                v_min: first.v,
                v_max: first.v,
                z_min: first.z,
                z_max: first.z,
                ..Default::default()
            };
            let mut sums = Sums::default();
            while stepper.state().t < t_end - 1e-10 * 2.0 * PI {
                let before = stepper.state().t;
                stepper.step(t_end, &mut sums)?;
                let st = stepper.state();
                rec.v_min = rec.v_min.min(st.v);
                rec.v_max = rec.v_max.max(st.v);
                rec.z_min = rec.z_min.min(st.z);
                rec.z_max = rec.z_max.max(st.z);
                rec.z_time += st.z * (st.t - before);
                peak_speed = peak_speed.max(-st.v);
                if record && st.t >= next_slider_sample {
                    next_slider_sample = st.t + slider_spacing;
                    if let Some(h) = slider_history.as_mut() {
                        units.push_slider_sample(h, stepper, t_start);
                    }
                }
                if record && st.t >= next_sample {
                    next_sample = st.t + sample_spacing;
                    if j >= history_from
                        && let Some(h) = post_history.as_mut()
                    {
                        units.push_post_sample(h, stepper, t_start);
                    }
                }
            }
            let last = stepper.state();
            rec.sums = sums;
            rec.dx = last.x - first.x;
            rec.stored_change = stepper.stored_energy() - stored0;
            records.push(rec);
            j += 1;
            if let Some(hook) = hook.as_deref_mut() {
                hook.after_period(&records, &mut span, stepper, window_work.as_deref())?;
                span.end = span.end.max(j);
                span.window_start = span.window_start.min(span.end - 1);
            }
        }
        if let Some(h) = post_history.as_mut() {
            // A run the hook extended keeps only the last history periods.
            if records.len() > periods {
                let from = 2.0 * PI * (records.len() - history_periods.max(1)) as f64 * t_unit;
                h.keep_from(from);
            }
            let t0 = h.time_s.first().copied().unwrap_or(0.0);
            h.time_s.iter_mut().for_each(|t| *t -= t0);
            h.intervals_from_states();
        }
        Ok(Integrated {
            records,
            span,
            window_work,
            peak_speed,
            slider_history,
            post_history,
        })
    }

    /// The run's means over the averaging window, and each group's mean stator power (W).
    fn summarise(
        &self,
        load_n: f64,
        stepper: &dyn Stepper,
        integrated: Integrated,
    ) -> (TransientRun, Option<Vec<f64>>) {
        let Integrated {
            records,
            span,
            window_work,
            peak_speed,
            slider_history,
            mut post_history,
        } = integrated;
        let scene = &self.scene;
        let a_n = scene.wave.normal_amplitude_m;
        let omega = scene.wave.angular_frequency_rad_per_s();
        let force_unit = scene.slider.effective_post_count() * scene.contact.k_n_n_per_m * a_n;
        let tangential_ratio = stepper.system().wave.tangential_ratio;
        // Averages over the window.
        let tail = &records[span.window_start..];
        let Window {
            sums,
            dx,
            z_time,
            residual,
            v: (v_min, v_max),
            z: (z_min, z_max),
        } = Window::of(tail);
        let time = sums.time;
        let power_unit = force_unit * a_n * omega;
        let mean_speed = -dx / time;
        let steady = is_steady(tail, tangential_ratio);
        let stator = sums.stator_work / time * power_unit;
        let output = sums.output_work / time * power_unit;
        if let Some(h) = post_history.as_mut() {
            h.speed_m_per_s = mean_speed * a_n * omega;
        }
        let total_dx: f64 = records.iter().map(|r| r.dx).sum();
        let group_power = group_power(window_work, stepper.group_stator_work(), time, power_unit);
        let dissipation = sums.dissipation / time * power_unit;
        let run = TransientRun {
            load_n,
            speed_m_per_s: mean_speed * a_n * omega,
            velocity_x_m_per_s: -mean_speed * a_n * omega,
            thrust_n: -sums.force_time / time * force_unit,
            output_power_w: output,
            stator_power_w: stator,
            friction_dissipation_w: dissipation,
            efficiency: efficiency(output, dissipation),
            stick_fraction: if sums.contact_time > 0.0 {
                sums.stick_time / sums.contact_time
            } else {
                0.0
            },
            contact_fraction: sums.contact_time / time,
            energy_balance_residual: residual,
            steady,
            speed_ripple_m_per_s: (v_max - v_min) * a_n * omega,
            vertical_bounce_m: (z_max - z_min) * a_n,
            mean_tip_height_m: z_time / time * a_n,
            displacement_m: -total_dx * a_n,
            peak_speed_m_per_s: peak_speed * a_n * omega,
            steps: stepper.steps(),
            periods: records.len(),
            period_speed_m_per_s: records
                .iter()
                .map(|r| -r.dx / r.sums.time * a_n * omega)
                .collect(),
            slider_history,
            post_history,
        };
        (run, group_power)
    }
}

/// Each group's mean stator power (W) over the window: the change of its stator work from
/// the window's start (`before`) to the end (`after`), over the window's `time`.
fn group_power(
    before: Option<Vec<f64>>,
    after: Option<&[f64]>,
    time: f64,
    power_unit: f64,
) -> Option<Vec<f64>> {
    match (before, after) {
        (Some(before), Some(after)) => Some(
            before
                .iter()
                .zip(after)
                .map(|(b, a)| (a - b) / time * power_unit)
                .collect(),
        ),
        _ => None,
    }
}

/// Output over the power the contacts take from the stator, counted as output + dissipation:
/// equal to output/stator in a steady state, and never above 1 when a finite window still sees
/// the slider's stored energy change.
fn efficiency(output: f64, dissipation: f64) -> f64 {
    let delivered = output + dissipation;
    if delivered > 0.0 && output > 0.0 {
        output / delivered
    } else {
        0.0
    }
}

/// The averaging window's sums (solver units): the periods' sums, the slider's displacement
/// and tip-height integral, the energy balance's relative residual, and the ranges of the
/// slider's speed and tip height.
struct Window {
    sums: Sums,
    dx: f64,
    z_time: f64,
    residual: f64,
    v: (f64, f64),
    z: (f64, f64),
}

impl Window {
    fn of(tail: &[PeriodRecord]) -> Self {
        let mut sums = Sums::default();
        let (mut dx, mut stored, mut z_time) = (0.0, 0.0, 0.0);
        for r in tail {
            sums += r.sums;
            dx += r.dx;
            stored += r.stored_change;
            z_time += r.z_time;
        }
        let residual = (sums.stator_work - sums.output_work - sums.dissipation - stored)
            / sums
                .power_flow
                .max(sums.stator_work.abs())
                .max(sums.dissipation.abs())
                .max(1e-300);
        let v = tail
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
                (a.min(r.v_min), b.max(r.v_max))
            });
        let z = tail
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
                (a.min(r.z_min), b.max(r.z_max))
            });
        Self {
            sums,
            dx,
            z_time,
            residual,
            v,
            z,
        }
    }
}

/// The units of the histories: the solver's time, length and force scales.
struct HistoryUnits {
    /// Normal wave amplitude A_n (m).
    a_n: f64,
    /// ω (rad/s).
    omega: f64,
    /// Force unit of the slider's totals, N_eff k_n A_n (N).
    force_unit: f64,
    /// Force unit of one post, k_n A_n (N).
    post_force: f64,
    /// Time unit 1/ω (s).
    t_unit: f64,
}

impl HistoryUnits {
    fn of(scene: &crate::scene::DynamicScene) -> Self {
        let a_n = scene.wave.normal_amplitude_m;
        let omega = scene.wave.angular_frequency_rad_per_s();
        Self {
            a_n,
            omega,
            force_unit: scene.slider.effective_post_count() * scene.contact.k_n_n_per_m * a_n,
            post_force: scene.contact.k_n_n_per_m * a_n,
            t_unit: 1.0 / omega,
        }
    }

    /// One sample of the slider's history at the stepper's state.
    fn push_slider_sample(&self, h: &mut SliderHistory, stepper: &dyn Stepper, t_start: f64) {
        let st = stepper.state();
        let (force, normal) = stepper.totals();
        h.time_s.push((st.t - t_start) * self.t_unit);
        h.speed_m_per_s.push(-st.v * self.a_n * self.omega);
        h.thrust_n.push(-force * self.force_unit);
        h.normal_force_n.push(normal * self.force_unit);
        h.tip_height_m.push(st.z * self.a_n);
    }

    /// One sample of the first group's post history at the stepper's state.
    fn push_post_sample(&self, h: &mut PostHistory, stepper: &dyn Stepper, t_start: f64) {
        let st = stepper.state();
        let sys = stepper.system();
        let (normal, force, mode) = stepper.group(0);
        let post_force = self.post_force;
        h.time_s.push((st.t - t_start) * self.t_unit);
        h.normal_force_n.push(normal * post_force);
        h.tangential_force_n.push(-force * post_force);
        h.friction_bound_n.push(sys.mu_k * normal * post_force);
        let alpha = st.t - sys.wave.doppler * st.x - sys.groups.phase[0];
        let drive = sys.groups.amplitude[0] * sys.wave.amplitude_at(st.x);
        let on = if sys.wave.is_on(alpha) { 1.0 } else { 0.0 };
        h.stator_velocity_m_per_s
            .push(sys.wave.tangential_ratio * on * drive * alpha.sin() * self.a_n * self.omega);
        h.state.push(crate::history::ContactState::from(mode));
    }
}
