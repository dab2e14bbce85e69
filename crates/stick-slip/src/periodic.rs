//! The period-average model (docs/physics.md §5.1): with posts spread uniformly over the wave phase
//! and a slider much heavier than one period's impulse, the sum over posts equals N_eff times
//! the period average of one post at an imposed constant speed. The tip height follows from
//! ⟨N⟩ = P/N_eff in closed form; thrust F(v) = N_eff⟨F⟩, stall thrust F(0⁺), no-load speed
//! F(v₀) = 0.

use std::f64::consts::PI;
use std::time::Instant;

use serde::Serialize;

use crate::error::stop_check;
use crate::error::{Result, StickSlipError, Warning};
use crate::history::{ContactState, PostHistory};
use crate::integrator::Integrator;
use crate::math::bracketed_root;
use crate::mean_normal::tip_height_for_mean_normal;
use crate::post::analytic::AnalyticPost;
use crate::post::stepping::{StepScheme, SteppedPost};
use crate::post::{Mode, PostParams, PostState, SteadyPost};
use crate::result::{CurvePoint, DynamicResult, OperatingPoint};
use crate::scene::{DynamicScene, ModelChoice, ModelKind};
use run_control::RunControl;

/// Relative tolerance (of the crest speed) of the no-load speed and load-speed roots.
const SPEED_TOLERANCE: f64 = 1e-12;
/// Bracket expansions (× 1.5 each) tried beyond the crest speed when a scheme's thrust is still
/// positive there (fixed-step schemes with large error). Default 6.
const BRACKET_EXPANSIONS: usize = 6;

/// The steady behaviour of the whole slider at one imposed speed, SI.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpeedSample {
    /// Imposed speed along the drive direction (m/s).
    pub speed_m_per_s: f64,
    /// Mean thrust along the drive direction, N_eff⟨−F_x⟩ (N).
    pub thrust_n: f64,
    /// Output power thrust × speed (W).
    pub output_power_w: f64,
    /// Mechanical power delivered by the stator through the tangential contacts (W).
    pub stator_power_w: f64,
    /// Friction dissipation (W).
    pub friction_dissipation_w: f64,
    /// Output over stator power.
    pub efficiency: f64,
    /// Time stuck over time in contact.
    pub stick_fraction: f64,
    /// Time in contact over time.
    pub contact_fraction: f64,
    /// Mean total normal force N_eff⟨N⟩ (N); equals the preload.
    pub mean_normal_force_n: f64,
    /// Relative residual of the energy balance over the steady cycle.
    pub energy_balance_residual: f64,
    /// Whether the steady cycle closed (false: averaged over quasi-periodic cycles).
    pub converged: bool,
}

impl SpeedSample {
    pub(crate) fn curve_point(&self) -> CurvePoint {
        CurvePoint {
            speed_m_per_s: self.speed_m_per_s,
            thrust_n: self.thrust_n,
            output_power_w: self.output_power_w,
            efficiency: self.efficiency,
            stick_fraction: self.stick_fraction,
        }
    }

    pub(crate) fn operating_point(&self, load_n: f64) -> OperatingPoint {
        OperatingPoint {
            load_n,
            speed_m_per_s: self.speed_m_per_s,
            thrust_n: self.thrust_n,
            output_power_w: self.output_power_w,
            stator_power_w: self.stator_power_w,
            friction_dissipation_w: self.friction_dissipation_w,
            efficiency: self.efficiency,
            stick_fraction: self.stick_fraction,
            contact_fraction: self.contact_fraction,
            energy_balance_residual: self.energy_balance_residual,
        }
    }
}

/// The period-average model of a scene.
#[derive(Debug, Clone)]
pub struct PeriodicAverageModel {
    pub(crate) scene: DynamicScene,
    pub(crate) params: PostParams,
    /// `None`: closed-form event-driven post.
    pub(crate) scheme: Option<StepScheme>,
    /// A_n (m).
    pub(crate) length_m: f64,
    /// ω (rad/s).
    pub(crate) omega: f64,
    /// k_n A_n (N).
    pub(crate) force_n: f64,
    /// N_eff.
    pub(crate) n_eff: f64,
    pub(crate) reason: String,
    pub(crate) warnings: Vec<Warning>,
}

impl PeriodicAverageModel {
    /// Build the model: validates the scene (typed errors; warnings kept for the result),
    /// refuses scenes it cannot represent (burst, decay, gaps), solves the tip height.
    pub fn new(scene: &DynamicScene) -> Result<Self> {
        let mut warnings = scene.validate()?;
        // Refuse what the model cannot represent (burst, decay, gaps); whatever model the scene
        // asks for, a period-average model of it may be built (e.g. as the transient's estimate).
        let forced = DynamicScene {
            model: ModelChoice::PeriodicAverage,
            ..scene.clone()
        };
        forced.resolve_model()?;
        let reason = match scene.resolve_model()? {
            (ModelKind::PeriodicAverage, reason) => reason,
            (ModelKind::Transient, _) => {
                "period-average model built directly (the scene's own choice is the transient)"
                    .into()
            }
        };
        if matches!(
            scene.slider.vertical,
            crate::slider::VerticalModel::Dynamic { .. }
        ) {
            warnings.push(Warning::new(
                "slider.vertical",
                "period-average model: the vertical slider dynamics are replaced by the period-mean equilibrium Σ⟨N⟩ = P",
            ));
        }
        let ripple = scene.speed_ripple_estimate();
        if ripple.is_nan() || ripple > crate::scene::SPEED_RIPPLE_LIMIT {
            warnings.push(Warning::new(
                "slider.mass_kg",
                format!("period-average model assumes a steady slider speed; the estimated speed ripple is {ripple:.1e} of A_t ω (post phase non-uniformity {:.3})", scene.phase_nonuniformity()),
            ));
        }
        let wave = &scene.wave;
        let contact = &scene.contact;
        let length_m = wave.normal_amplitude_m;
        let omega = wave.angular_frequency_rad_per_s();
        let force_n = contact.k_n_n_per_m * length_m;
        let n_eff = scene.slider.effective_post_count();
        let scaled = crate::wave::scaled(wave);
        let height = tip_height_for_mean_normal(scene.slider.preload_n / (n_eff * force_n));
        let params = PostParams {
            tangential_ratio: scaled.tangential_ratio,
            stiffness_ratio: contact.k_t_n_per_m / contact.k_n_n_per_m,
            mu_static: contact.mu_static,
            mu_kinetic: contact.mu_kinetic,
            doppler: scaled.doppler,
            height,
            mass: contact
                .post_mass_kg
                .map(|m| m * omega * omega / contact.k_n_n_per_m),
        };
        let integrator = scene
            .integrator
            .resolve(ModelKind::PeriodicAverage, wave.period_s());
        let scheme = match integrator {
            Integrator::Auto | Integrator::EventDriven { .. } => None,
            Integrator::ReturnMapping { dt_s } => {
                Some(StepScheme::ReturnMapping { step: dt_s * omega })
            }
            Integrator::PostMass { dt_s } => Some(StepScheme::PostMass { step: dt_s * omega }),
            Integrator::RegularizedExplicit {
                dt_s,
                regularization_speed_m_per_s,
            } => Some(StepScheme::Regularized {
                step: dt_s * omega,
                regularization: regularization_speed_m_per_s / (length_m * omega),
            }),
        };
        Ok(Self {
            scene: scene.clone(),
            params,
            scheme,
            length_m,
            omega,
            force_n,
            n_eff,
            reason,
            warnings,
        })
    }

    /// The scene this model was built from.
    pub fn scene(&self) -> &DynamicScene {
        &self.scene
    }

    /// Warnings gathered while building the model.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// Post-tip reference height z_s (m) from Σ⟨N⟩ = P.
    pub fn tip_height_m(&self) -> f64 {
        self.params.height.c * self.length_m
    }

    /// Crest speed A_t ω (m/s).
    pub fn crest_speed_m_per_s(&self) -> f64 {
        self.scene.wave.crest_speed_m_per_s()
    }

    pub(crate) fn scaled_velocity(&self, speed_m_per_s: f64) -> f64 {
        // Drive direction is −x.
        -speed_m_per_s / (self.length_m * self.omega)
    }

    fn steady_at(&self, speed_m_per_s: f64) -> Result<SteadyPost> {
        self.steady_with(self.params, self.scaled_velocity(speed_m_per_s))
    }

    /// Steady periodic post with parameters `params` at scaled velocity `v`, by the model's
    /// scheme (closed form, or the fixed-step scheme started from the closed-form state).
    pub(crate) fn steady_with(&self, params: PostParams, v: f64) -> Result<SteadyPost> {
        let analytic = AnalyticPost::new(params, v);
        let Some(scheme) = self.scheme else {
            return analytic.steady();
        };
        let stepped = SteppedPost::new(params, v, scheme)?;
        let (theta0, mut start) = match params.height.half_arc {
            Some(phi) => (0.5 * PI - phi, PostState::separated()),
            None => analytic.steady()?.start,
        };
        start.tip_velocity = if start.mode == Mode::Stick {
            -params.tangential_ratio * theta0.sin()
        } else {
            v
        };
        stepped.steady(theta0, start)
    }

    /// Stability probe of the model's fixed-step scheme at one speed: `None` for the
    /// closed-form event-driven post (no step).
    pub fn probe_at_speed(
        &self,
        speed_m_per_s: f64,
        periods: usize,
    ) -> Result<Option<crate::post::stepping::StabilityProbe>> {
        let Some(scheme) = self.scheme else {
            return Ok(None);
        };
        let v = self.scaled_velocity(speed_m_per_s);
        let stepped = SteppedPost::new(self.params, v, scheme)?;
        let (theta0, mut start) = match self.params.height.half_arc {
            Some(phi) => (0.5 * PI - phi, PostState::separated()),
            None => AnalyticPost::new(self.params, v).steady()?.start,
        };
        start.tip_velocity = if start.mode == Mode::Stick {
            -self.params.tangential_ratio * theta0.sin()
        } else {
            v
        };
        Ok(Some(stepped.probe(theta0, start, periods)))
    }

    /// Steady state of the whole slider at an imposed speed along the drive direction (m/s);
    /// speed 0 is the v → 0⁺ limit.
    pub fn at_speed(&self, speed_m_per_s: f64) -> Result<SpeedSample> {
        crate::error::require_finite("speed_m_per_s", speed_m_per_s)?;
        let steady = self.steady_at(speed_m_per_s)?;
        let i = steady.integrals;
        let power = self.force_n * self.length_m * self.omega * self.n_eff / i.time;
        let stator = i.stator_work * power;
        let output = i.output_work * power;
        Ok(SpeedSample {
            speed_m_per_s,
            thrust_n: -i.mean_force() * self.force_n * self.n_eff,
            output_power_w: output,
            stator_power_w: stator,
            friction_dissipation_w: i.dissipation * power,
            // Output over the power delivered into the contacts, counted as output + friction
            // dissipation: output/stator in an exactly steady period, and bounded by 1 where the
            // two small works near the no-load speed do not balance to round-off.
            efficiency: {
                let delivered = output + (i.dissipation * power).max(0.0);
                if delivered > 0.0 && output > 0.0 {
                    output / delivered
                } else {
                    0.0
                }
            },
            stick_fraction: if i.contact_time > 0.0 {
                i.stick_time / i.contact_time
            } else {
                0.0
            },
            contact_fraction: i.contact_time / i.time,
            mean_normal_force_n: i.normal_time / i.time * self.force_n * self.n_eff,
            energy_balance_residual: i.energy_balance_residual(),
            converged: steady.converged,
        })
    }

    /// Stall thrust F(0⁺) (N). Negative when the slider is locked (posts never separate and
    /// stay stuck: it must be pushed to advance); [`solve`](Self::solve) then reports 0 with a
    /// warning.
    pub fn stall_thrust_n(&self) -> Result<f64> {
        Ok(self.at_speed(0.0)?.thrust_n)
    }

    /// No-load speed v₀ with F(v₀) = 0 (m/s); 0 if the motor cannot move.
    pub fn no_load_speed_m_per_s(&self) -> Result<f64> {
        self.speed_for_thrust(0.0, None)
    }

    /// Speed at which the thrust equals `load_n` on the driving branch. `stall` may pass a
    /// known F(0⁺). Loads above the stall thrust give 0.
    fn speed_for_thrust(&self, load_n: f64, stall: Option<f64>) -> Result<f64> {
        let stall = match stall {
            Some(s) => s,
            None => self.stall_thrust_n()?,
        };
        if stall <= load_n {
            return Ok(0.0);
        }
        let crest = self.crest_speed_m_per_s();
        let excess = |speed: f64| -> Result<f64> { Ok(self.at_speed(speed)?.thrust_n - load_n) };
        let mut hi = crest;
        let mut f_hi = excess(hi)?;
        let mut expansions = 0;
        while f_hi > 0.0 {
            if expansions == BRACKET_EXPANSIONS {
                return Err(StickSlipError::NotConverged {
                    model: "periodic-average",
                    what: "bracket of the no-load speed (thrust still positive far beyond the crest speed)",
                    iterations: expansions,
                    residual: f_hi,
                });
            }
            hi *= 1.5;
            f_hi = excess(hi)?;
            expansions += 1;
        }
        let mut failure = None;
        let root = bracketed_root(
            |speed| match excess(speed) {
                Ok(value) => value,
                Err(e) => {
                    failure.get_or_insert(e);
                    -1.0
                }
            },
            0.0,
            hi,
            SPEED_TOLERANCE * crest,
        );
        match failure {
            Some(e) => Err(e),
            None => Ok(root),
        }
    }

    /// The speed–thrust curve: `points` speeds evenly from 0⁺ to the no-load speed; `control`
    /// is asked before each point ([`RunControl::none()`]: never stops).
    pub fn curve(&self, points: usize, control: &RunControl) -> Result<Vec<SpeedSample>> {
        let v0 = self.no_load_speed_m_per_s()?;
        let n = points.max(2);
        (0..n)
            .map(|i| {
                stop_check(control, || format!("curve point {} of {n}", i + 1))?;
                self.at_speed(v0 * i as f64 / (n - 1) as f64)
            })
            .collect()
    }

    /// Steady state at the external load `load_n` (N); `None` if it exceeds the stall thrust.
    pub fn at_load(&self, load_n: f64) -> Result<Option<SpeedSample>> {
        let stall = self.stall_thrust_n()?;
        if load_n > stall {
            return Ok(None);
        }
        let speed = self.speed_for_thrust(load_n, Some(stall))?;
        self.at_speed(speed).map(Some)
    }

    /// One post's forces over `periods` wave periods of the steady motion at `speed_m_per_s`
    /// (Fig. 6), `samples_per_period` samples per period; stick intervals are exact for the
    /// event-driven scheme.
    pub fn post_history(
        &self,
        speed_m_per_s: f64,
        periods: f64,
        samples_per_period: usize,
    ) -> Result<PostHistory> {
        crate::error::require_positive("history periods", periods)?;
        let v = self.scaled_velocity(speed_m_per_s);
        let steady = self.steady_at(speed_m_per_s)?;
        let (theta0, start) = steady.start;
        let p = &self.params;
        let s = p.phase_rate(v);
        let time_unit = 1.0 / self.omega;
        let samples = (periods * samples_per_period as f64).ceil() as usize;
        let period = 2.0 * PI / s;
        let mut history = PostHistory {
            speed_m_per_s,
            ..Default::default()
        };
        let mut record = |t: f64, theta: f64, force: f64, mode: Mode| {
            history.time_s.push(t * time_unit);
            let normal = p.normal(theta).max(0.0);
            history.normal_force_n.push(normal * self.force_n);
            history.tangential_force_n.push(-force * self.force_n);
            history
                .friction_bound_n
                .push(p.mu_kinetic * normal * self.force_n);
            history
                .stator_velocity_m_per_s
                .push(p.tangential_ratio * theta.sin() * self.length_m * self.omega);
            history.state.push(ContactState::from(mode));
        };
        match self.scheme {
            None => {
                let post = AnalyticPost::new(*p, v);
                let mut segments = Vec::new();
                let mut dropped = 0.0;
                let theta_end = theta0 + periods * 2.0 * PI;
                post.advance(theta0, theta_end, start, &mut segments, &mut dropped)?;
                let mut seg_index = 0;
                for k in 0..=samples {
                    let t = period * periods * k as f64 / samples as f64;
                    let theta = theta0 + s * t;
                    while seg_index + 1 < segments.len() && segments[seg_index].end < theta {
                        seg_index += 1;
                    }
                    let seg = &segments[seg_index];
                    record(
                        t,
                        theta,
                        p.stiffness_ratio * post.deflection(seg, theta),
                        seg.mode,
                    );
                }
                let to_time = |theta: f64| (theta - theta0) / s * time_unit;
                history.stick_intervals_s = stick_intervals(&segments, to_time, time_unit);
            }
            Some(scheme) => {
                let stepped = SteppedPost::new(*p, v, scheme)?;
                let whole = periods.ceil() as usize;
                let raw = stepped.sample(theta0, start, whole);
                let stride = (raw.len() / samples.max(1)).max(1);
                let t_end = period * periods;
                for &(t, _, force, mode) in raw
                    .iter()
                    .step_by(stride)
                    .filter(|r| r.0 <= t_end * (1.0 + 1e-12))
                {
                    record(t, theta0 + s * t, force, mode);
                }
                history.intervals_from_states();
            }
        }
        Ok(history)
    }

    /// The full result: curve, stall, no-load speed, operating point, efficiency; `control` is
    /// asked before each curve point and before the operating point ([`RunControl::none()`]:
    /// never stops).
    pub fn solve(&self, control: &RunControl) -> Result<DynamicResult> {
        let started = Instant::now();
        let mut warnings = self.warnings.clone();
        let stall_sample = self.at_speed(0.0)?;
        let samples = if stall_sample.thrust_n > 0.0 {
            self.curve(self.scene.options.curve_points, control)?
        } else {
            warnings.push(Warning::new(
                "slider.preload_n",
                format!(
                    "the slider is locked: F(0⁺) = {:.4} N ≤ 0 (posts never separate and stay stuck within the friction band); it advances only if pushed along the drive direction by more than {:.4} N",
                    stall_sample.thrust_n, -stall_sample.thrust_n
                ),
            ));
            vec![SpeedSample {
                thrust_n: 0.0,
                ..stall_sample
            }]
        };
        let stall = samples[0].thrust_n;
        let no_load = samples.last().map_or(0.0, |s| s.speed_m_per_s);
        let load = self.scene.slider.external_load_n;
        let operating = if load > stall {
            warnings.push(Warning::new(
                "slider.external_load_n",
                format!("load {load} N exceeds the stall thrust {stall:.4} N: the slider does not advance"),
            ));
            None
        } else if load == 0.0 {
            samples.last().copied()
        } else {
            stop_check(control, || "the operating point".into())?;
            self.at_load(load)?
        };
        if samples.iter().chain(operating.iter()).any(|s| !s.converged) {
            warnings.push(Warning::new(
                "steady state",
                "some speeds reached no exactly periodic cycle (quasi-periodic stick/slip); their values are averages over many cycles",
            ));
        }
        let reference = operating.unwrap_or(samples[0]);
        let efficiency = samples.iter().map(|s| s.efficiency).fold(0.0, f64::max);
        let max_power = samples.iter().map(|s| s.output_power_w).fold(0.0, f64::max);
        let integrator = match self.scheme {
            None => "event-driven (closed-form segments)".to_string(),
            Some(_) => self
                .scene
                .integrator
                .resolve(ModelKind::PeriodicAverage, self.scene.wave.period_s())
                .name()
                .to_string(),
        };
        Ok(DynamicResult {
            model: ModelKind::PeriodicAverage,
            model_reason: self.reason.clone(),
            integrator,
            stall_thrust_n: stall,
            no_load_speed_m_per_s: no_load,
            curve: samples.iter().map(SpeedSample::curve_point).collect(),
            stick_fraction: reference.stick_fraction,
            contact_fraction: reference.contact_fraction,
            efficiency,
            max_output_power_w: max_power,
            operating_point: operating.map(|s| s.operating_point(load)),
            effective_post_count: self.n_eff,
            mean_normal_force_per_post_n: self.scene.mean_normal_force_per_post_n(),
            tip_height_m: self.tip_height_m(),
            friction_limit_n: self.scene.contact.mu_kinetic * self.scene.slider.preload_n,
            crest_speed_m_per_s: self.crest_speed_m_per_s(),
            wall_time_s: started.elapsed().as_secs_f64(),
            warnings,
            transient: None,
        })
    }
}

/// The stick intervals (s) of the analytic post's `segments`, adjacent ones merged; `to_time`
/// maps a wave phase to the history's time.
fn stick_intervals(
    segments: &[crate::post::analytic::Segment],
    to_time: impl Fn(f64) -> f64,
    time_unit: f64,
) -> Vec<(f64, f64)> {
    let mut intervals: Vec<(f64, f64)> = Vec::new();
    for seg in segments.iter().filter(|seg| seg.mode == Mode::Stick) {
        let interval = (to_time(seg.start), to_time(seg.end));
        match intervals.last_mut() {
            Some(last) if (last.1 - interval.0).abs() <= 1e-12 * time_unit => last.1 = interval.1,
            _ => intervals.push(interval),
        }
    }
    intervals
}
