//! Fixed-step schemes for one post at constant speed (solver units): return mapping for the
//! massless Jenkins element, and the two schemes for a post with its own mass (Moreau–Jean
//! impulses with exact Coulomb friction, and explicit tanh-regularised friction).
//!
//! The step is shortened to divide the (Doppler-shifted) wave period exactly, so that period
//! averages are sums over whole periods.

use std::f64::consts::PI;

use super::{Mode, PeriodIntegrals, PostParams, PostState, SteadyPost};
use crate::error::{Result, StickSlipError};

/// Periods integrated at most before a fixed-step post is declared quasi-periodic and
/// averaged over its second half. Default 64.
const MAX_PERIODS: usize = 64;
/// Relative change of the period-mean force (of the force scale) between two periods that
/// counts as periodic. Default 1e-10.
const PERIODIC_TOLERANCE: f64 = 1e-10;
/// A deflection beyond this multiple of the deflection scale is a divergence. Default 1e6.
const DIVERGENCE_FACTOR: f64 = 1e6;

/// Fraction of steps in one period with three alternating successive differences above which a
/// stepped post counts as oscillating at the step frequency (a smooth signal has none; tanh
/// chatter during the stick phases alternates at ≈ 20–30 % of the steps). Default 0.05.
const OSCILLATION_FLIP_FRACTION: f64 = 0.05;
/// Fewest alternations per period counted as oscillation (protects coarse grids, where a
/// smooth signal's turning points are a large fraction of the steps). Default 8.
const OSCILLATION_MIN_FLIPS: usize = 8;

/// Outcome of a stability probe ([`crate::PeriodicAverageModel::probe_at_speed`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StabilityProbe {
    /// The stepped post's force grew beyond the divergence bound.
    pub diverged: bool,
    /// The force alternates at the step frequency (chatter).
    pub oscillating: bool,
    /// Mean force of the last period (NaN if diverged).
    pub mean_force: f64,
}

/// A fixed-step scheme in solver units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum StepScheme {
    /// Implicit return mapping on the massless Jenkins element.
    ReturnMapping { step: f64 },
    /// Post mass m̂ with exact Coulomb impulses (Moreau–Jean), explicit spring.
    PostMass { step: f64 },
    /// Post mass with μN·tanh(slip/v̂_reg), symplectic Euler.
    Regularized { step: f64, regularization: f64 },
}

impl StepScheme {
    pub fn name(&self) -> &'static str {
        match self {
            Self::ReturnMapping { .. } => "return-mapping",
            Self::PostMass { .. } => "post-mass",
            Self::Regularized { .. } => "regularized-explicit",
        }
    }

    fn step(&self) -> f64 {
        match *self {
            Self::ReturnMapping { step }
            | Self::PostMass { step }
            | Self::Regularized { step, .. } => step,
        }
    }
}

/// One post stepped at constant scaled x-velocity `v`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SteppedPost {
    pub p: PostParams,
    pub v: f64,
    pub scheme: StepScheme,
    s: f64,
    /// Steps per period and the step that divides the period.
    steps_per_period: usize,
    h: f64,
}

impl SteppedPost {
    pub fn new(p: PostParams, v: f64, scheme: StepScheme) -> Result<Self> {
        if matches!(
            scheme,
            StepScheme::PostMass { .. } | StepScheme::Regularized { .. }
        ) && p.mass.is_none()
        {
            return Err(StickSlipError::MissingPostMass {
                integrator: scheme.name(),
            });
        }
        let s = p.phase_rate(v);
        let period = 2.0 * PI / s;
        let steps = (period / scheme.step()).ceil().max(1.0);
        if steps > 1e12 {
            return Err(StickSlipError::InvalidParameter {
                parameter: "integrator.dt_s",
                value: scheme.step(),
                requirement: "more than 1e12 steps per wave period".into(),
            });
        }
        Ok(Self {
            p,
            v,
            scheme,
            s,
            steps_per_period: steps as usize,
            h: period / steps,
        })
    }

    /// Advance one step from phase θ; returns the new state and adds the step's integrals.
    fn step(&self, theta: f64, state: PostState, ints: &mut PeriodIntegrals) -> PostState {
        let p = &self.p;
        let (h, s) = (self.h, self.s);
        let theta1 = theta + s * h;
        let normal = p.normal(theta1);
        let in_contact = normal > 0.0;
        let threshold = if matches!(state.mode, Mode::Slip(_)) {
            p.mu_kinetic
        } else {
            p.mu_static
        };
        let next = match self.scheme {
            StepScheme::ReturnMapping { .. } => {
                self.return_mapping(theta, theta1, state, normal, threshold, ints)
            }
            StepScheme::PostMass { .. } => self.post_mass(theta1, state, normal, threshold, ints),
            StepScheme::Regularized { regularization, .. } => {
                self.regularized(theta, state, regularization, ints)
            }
        };
        ints.time += h;
        ints.normal_time += normal * h;
        if in_contact {
            ints.contact_time += h;
            if next.mode == Mode::Stick {
                ints.stick_time += h;
            }
        }
        next
    }

    /// The return-mapping step to θ1: the exact stator displacement along the step, then the
    /// trial deflection clamped to the friction cone (`threshold` × `normal`).
    fn return_mapping(
        &self,
        theta: f64,
        theta1: f64,
        state: PostState,
        normal: f64,
        threshold: f64,
        ints: &mut PeriodIntegrals,
    ) -> PostState {
        let p = &self.p;
        let (h, s, a_t, rho) = (self.h, self.s, p.tangential_ratio, p.stiffness_ratio);
        let in_contact = normal > 0.0;
        // Exact stator displacement increment along the step, then clamp.
        let particle = a_t * (theta1.cos() - theta.cos()) / s;
        let trial = state.deflection + particle - self.v * h;
        let (mode, deflection) = if !in_contact {
            (Mode::Separated, 0.0)
        } else if trial.abs() <= threshold * normal / rho {
            (Mode::Stick, trial)
        } else {
            let sign = trial.signum();
            (Mode::Slip(sign), sign * p.mu_kinetic * normal / rho)
        };
        let force = rho * deflection;
        ints.stator_work += force * particle;
        ints.power_flow += (force * particle).abs();
        ints.output_work += force * self.v * h;
        ints.dissipation += force * (trial - deflection);
        ints.force_time += force * h;
        PostState {
            mode,
            deflection,
            tip_velocity: 0.0,
        }
    }

    /// The post-mass step to θ1: the impulse that makes the tip move with the stator if the
    /// cone allows it, else the kinetic impulse.
    fn post_mass(
        &self,
        theta1: f64,
        state: PostState,
        normal: f64,
        threshold: f64,
        ints: &mut PeriodIntegrals,
    ) -> PostState {
        let p = &self.p;
        let (h, a_t, rho) = (self.h, p.tangential_ratio, p.stiffness_ratio);
        let in_contact = normal > 0.0;
        let mass = p.mass.unwrap_or(f64::NAN);
        let free = state.tip_velocity - h * rho * state.deflection / mass;
        let stator = -a_t * theta1.sin();
        let needed = mass * (stator - free);
        let (mode, impulse) = if !in_contact {
            (Mode::Separated, 0.0)
        } else if needed.abs() <= threshold * normal * h {
            (Mode::Stick, needed)
        } else {
            let sign = needed.signum();
            (Mode::Slip(sign), sign * p.mu_kinetic * normal * h)
        };
        let tip_velocity = free + impulse / mass;
        let deflection = state.deflection + h * (tip_velocity - self.v);
        ints.stator_work += impulse * stator;
        ints.power_flow += (impulse * stator).abs();
        ints.dissipation += impulse * (stator - tip_velocity);
        ints.force_time += rho * deflection * h;
        ints.output_work += rho * deflection * self.v * h;
        PostState {
            mode,
            deflection,
            tip_velocity,
        }
    }

    /// The regularised explicit step from θ: friction μ_k N tanh(slip/`regularization`) from the
    /// old-time normal force and stator velocity.
    fn regularized(
        &self,
        theta: f64,
        state: PostState,
        regularization: f64,
        ints: &mut PeriodIntegrals,
    ) -> PostState {
        let p = &self.p;
        let (h, a_t, rho) = (self.h, p.tangential_ratio, p.stiffness_ratio);
        let mass = p.mass.unwrap_or(f64::NAN);
        let normal0 = p.normal(theta);
        let stator = -a_t * theta.sin();
        let slip = stator - state.tip_velocity;
        let friction = p.mu_kinetic * normal0 * (slip / regularization).tanh();
        let tip_velocity = state.tip_velocity + h * (friction - rho * state.deflection) / mass;
        let deflection = state.deflection + h * (tip_velocity - self.v);
        ints.stator_work += friction * stator * h;
        ints.power_flow += (friction * stator * h).abs();
        ints.dissipation += friction * slip * h;
        ints.force_time += rho * deflection * h;
        ints.output_work += rho * deflection * self.v * h;
        let mode = if normal0 <= 0.0 {
            Mode::Separated
        } else if slip.abs() <= regularization {
            Mode::Stick
        } else {
            Mode::Slip(slip.signum())
        };
        PostState {
            mode,
            deflection,
            tip_velocity,
        }
    }

    /// Stored energy of the post: spring ½ρê², plus ½m̂(tip velocity)² with mass.
    fn stored_energy(&self, state: &PostState) -> f64 {
        let spring = 0.5 * self.p.stiffness_ratio * state.deflection * state.deflection;
        spring
            + self
                .p
                .mass
                .map_or(0.0, |m| 0.5 * m * state.tip_velocity * state.tip_velocity)
    }

    /// One period from (θ0, state).
    pub fn period(
        &self,
        theta0: f64,
        mut state: PostState,
    ) -> Result<(PostState, PeriodIntegrals)> {
        let mut ints = PeriodIntegrals::default();
        let start_energy = self.stored_energy(&state);
        let limit = DIVERGENCE_FACTOR * self.p.deflection_scale().max(self.p.tangential_ratio);
        for k in 0..self.steps_per_period {
            let theta = theta0 + k as f64 * self.s * self.h;
            state = self.step(theta, state, &mut ints);
            // Written so that a NaN deflection also counts as divergence.
            let bounded = state.deflection.abs() <= limit && state.tip_velocity.is_finite();
            if !bounded {
                return Err(StickSlipError::Diverged {
                    integrator: self.scheme.name(),
                    time_s: f64::NAN,
                    quantity: "post deflection (units of A_n)",
                    value: state.deflection,
                });
            }
        }
        ints.stored_energy_change = self.stored_energy(&state) - start_energy;
        Ok((state, ints))
    }

    /// Periodic steady state from the start (θ0, state): periods until the mean force repeats,
    /// else the mean over the second half of [`MAX_PERIODS`] periods.
    pub fn steady(&self, theta0: f64, start: PostState) -> Result<SteadyPost> {
        let force_scale = self.p.mu_static.max(1e-12) * (1.0 - self.p.height.c);
        let mut state = start;
        let mut previous: Option<f64> = None;
        let mut history: Vec<PeriodIntegrals> = Vec::with_capacity(MAX_PERIODS);
        for _ in 0..MAX_PERIODS {
            let period_start = state;
            let (end, ints) = self.period(theta0, state)?;
            let mean = ints.mean_force();
            if let Some(prev) = previous
                && (mean - prev).abs() <= PERIODIC_TOLERANCE * force_scale
            {
                return Ok(SteadyPost {
                    integrals: ints,
                    start: (theta0, period_start),
                    converged: true,
                });
            }
            previous = Some(mean);
            history.push(ints);
            state = end;
        }
        let tail = history[MAX_PERIODS / 2..]
            .iter()
            .fold(PeriodIntegrals::default(), |acc, i| acc + *i);
        Ok(SteadyPost {
            integrals: tail,
            start: (theta0, state),
            converged: false,
        })
    }

    /// Run `periods` periods from (θ0, state) for a stability study: divergence, step-to-step
    /// oscillation of the last period, and the mean force of the last period.
    pub fn probe(&self, theta0: f64, start: PostState, periods: usize) -> StabilityProbe {
        let mut state = start;
        let mut ints = PeriodIntegrals::default();
        for _ in 0..periods.saturating_sub(1) {
            match self.period(theta0, state) {
                Ok((end, _)) => state = end,
                Err(_) => {
                    return StabilityProbe {
                        diverged: true,
                        oscillating: false,
                        mean_force: f64::NAN,
                    };
                }
            }
        }
        // Last period step by step: count steps where three successive differences of the
        // signal that would ring (tip velocity with mass, deflection without) alternate in sign
        // — a period-2 pattern at the step frequency; physical ringing resolved by ≳ 6 steps per
        // cycle does not alternate.
        let signal = |s: &PostState| {
            if self.p.mass.is_some() {
                s.tip_velocity
            } else {
                s.deflection
            }
        };
        let (mut previous, mut deltas, mut flips) = (signal(&state), [0.0f64; 2], 0usize);
        let limit = DIVERGENCE_FACTOR * self.p.deflection_scale().max(self.p.tangential_ratio);
        for k in 0..self.steps_per_period {
            let theta = theta0 + k as f64 * self.s * self.h;
            state = self.step(theta, state, &mut ints);
            if !(state.deflection.abs() <= limit && state.tip_velocity.is_finite()) {
                return StabilityProbe {
                    diverged: true,
                    oscillating: false,
                    mean_force: f64::NAN,
                };
            }
            let value = signal(&state);
            let delta = value - previous;
            if delta * deltas[1] < 0.0 && deltas[1] * deltas[0] < 0.0 {
                flips += 1;
            }
            previous = value;
            deltas = [deltas[1], delta];
        }
        let oscillating = flips > OSCILLATION_MIN_FLIPS
            && flips as f64 > OSCILLATION_FLIP_FRACTION * self.steps_per_period as f64;
        StabilityProbe {
            diverged: false,
            oscillating,
            mean_force: ints.mean_force(),
        }
    }

    /// Sample N̂, F̂ = ρê and the mode from (θ0, state) at every step for `periods` periods.
    pub fn sample(
        &self,
        theta0: f64,
        mut state: PostState,
        periods: usize,
    ) -> Vec<(f64, f64, f64, Mode)> {
        let mut samples = Vec::with_capacity(periods * self.steps_per_period + 1);
        let mut ints = PeriodIntegrals::default();
        for k in 0..periods * self.steps_per_period {
            let theta = theta0 + k as f64 * self.s * self.h;
            state = self.step(theta, state, &mut ints);
            let t = (k + 1) as f64 * self.h;
            samples.push((
                t,
                self.p.normal(theta + self.s * self.h),
                self.p.stiffness_ratio * state.deflection,
                state.mode,
            ));
        }
        samples
    }
}
