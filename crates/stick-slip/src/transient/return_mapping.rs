//! Fixed-step return mapping for the transient (massless posts): backward Euler on the slider,
//! Moreau's catching-up algorithm on every Jenkins element.
//!
//! Per step: the stator displacement increment under each group is exact along the step's phase
//! path; the vertical velocity solves the (monotone) backward-Euler equation; then the slider's
//! new velocity v solves M(v − v_n)/h = Σw F_g(v) + L with F_g = ρ·clamp(ê_g + Δu_g − v h) by an
//! active-set iteration (stuck groups are linear in v, slipping ones constant). First order,
//! unconditionally stable; friction dissipates the numerical ½ρ(Δê)² per step as well.

use std::borrow::Cow;
use std::f64::consts::PI;

use super::groups::Phases;
use super::system::{SliderState, Stepper, Sums, System};
use crate::error::{Result, StickSlipError};
use crate::post::Mode;

/// Active-set iterations allowed per step (a status flips at most once per group).
const MAX_ACTIVE_SET_ITERATIONS: usize = 64;
/// Newton iterations allowed for the vertical velocity per step.
const MAX_VERTICAL_ITERATIONS: usize = 60;

/// Return-mapping stepper.
#[derive(Debug)]
pub(crate) struct ReturnMapping<'a> {
    /// The system, borrowed until the amplitude profile is retuned mid-run (then owned).
    sys: Cow<'a, System>,
    h: f64,
    steps: u64,
    st: SliderState,
    /// Phase path variable α = t − κx at the current step start (with the predicted x).
    alpha: f64,
    deflection: Vec<f64>,
    mode: Vec<Mode>,
    phases0: Phases,
    phases1: Phases,
    normal: Vec<f64>,
    increment: Vec<f64>,
    /// ê + Δu: the trial deflection before the slider's own displacement −v h.
    trial: Vec<f64>,
    /// Stick threshold τN/ρ on the trial (τ = μ_s, or μ_k after slipping).
    threshold: Vec<f64>,
    /// Status during the active-set iteration: 0 stuck, ±1 slipping, [`SEPARATED`].
    status: Vec<i8>,
    /// Stator work of each group since the start (weighted).
    group_work: Vec<f64>,
}

/// Status code of a separated group in the active-set iteration.
const SEPARATED: i8 = 2;

impl<'a> ReturnMapping<'a> {
    /// A stepper with step ≈ `step` (shortened to divide the wave period) from `start`.
    pub fn new(sys: &'a System, step: f64, start: SliderState) -> Self {
        let n = sys.groups.len();
        let per_period = (2.0 * PI / step).ceil().max(1.0);
        let mut phases0 = Phases::new(n);
        phases0.fill(&sys.groups, &sys.wave, start.t, start.x);
        let normal = (0..n).map(|g| sys.normal(&phases0, g, start.z)).collect();
        Self {
            sys: Cow::Borrowed(sys),
            h: 2.0 * PI / per_period,
            steps: 0,
            st: start,
            alpha: start.t - sys.wave.doppler * start.x,
            deflection: vec![0.0; n],
            mode: vec![Mode::Stick; n],
            phases0,
            phases1: Phases::new(n),
            normal,
            increment: vec![0.0; n],
            trial: vec![0.0; n],
            threshold: vec![0.0; n],
            status: vec![0; n],
            group_work: vec![0.0; n],
        }
    }

    /// Each group's stator displacement Δu over the step to the phase `alpha1`.
    fn increments(&mut self, alpha1: f64) {
        let sys = &*self.sys;
        let n = sys.groups.len();
        let h = self.h;
        if sys.wave.burst_phase_end.is_none() {
            // Continuous wave: Δu = â·drive·(cos θ1 − cos θ0)/s, s the phase rate over the step.
            let scale = sys.wave.tangential_ratio * h / (alpha1 - self.alpha);
            let (p0, p1) = (&self.phases0, &self.phases1);
            for (g, du) in self.increment.iter_mut().enumerate() {
                *du = scale * 0.5 * (p0.drive[g] + p1.drive[g]) * (p1.cos[g] - p0.cos[g]);
            }
        } else {
            for g in 0..n {
                self.increment[g] = self.particle_increment(g, self.alpha, alpha1);
            }
        }
    }

    /// The slider's new velocity by the active set of the groups' status (0 stuck, ±1
    /// slipping, [`SEPARATED`]), from the trials, thresholds and normal forces of the step.
    #[allow(clippy::needless_range_loop)]
    fn active_set(&mut self, h: f64) -> Result<f64> {
        let sys = &*self.sys;
        let n = sys.groups.len();
        let (rho, mu_k, mu_s) = (sys.rho, sys.mu_k, sys.mu_s);
        let weights = &sys.groups.weight;
        // Active set on the slider velocity: status 0 stuck, ±1 slipping, 2 separated.
        let v0 = self.st.v;
        let status_of = |base: f64, threshold: f64, normal: f64, v: f64| {
            status_of(base - v * h, threshold, normal)
        };
        for g in 0..n {
            self.status[g] = status_of(self.trial[g], self.threshold[g], self.normal[g], v0);
        }
        // With μ_s > μ_k a group that lost sticking in this step does not regain it (keeps
        // the iteration finite on the non-monotone static→kinetic drop).
        let monotone = mu_s == mu_k;
        let mut v1 = v0;
        let mut converged = false;
        for _ in 0..MAX_ACTIVE_SET_ITERATIONS {
            let (mut lhs, mut rhs) = (sys.mass / h, sys.mass * v0 / h + sys.load);
            for g in 0..n {
                let w = weights[g];
                match self.status[g] {
                    0 => {
                        lhs += w * rho * h;
                        rhs += w * rho * self.trial[g];
                    }
                    SEPARATED => {}
                    sign => rhs += w * f64::from(sign) * mu_k * self.normal[g],
                }
            }
            v1 = rhs / lhs;
            let mut changed = false;
            for g in 0..n {
                let old = self.status[g];
                let new = status_of(self.trial[g], self.threshold[g], self.normal[g], v1);
                let may_return = monotone || matches!(self.mode[g], Mode::Slip(_));
                if new != old && (new != 0 || may_return) {
                    self.status[g] = new;
                    changed = true;
                }
            }
            if !changed {
                converged = true;
                break;
            }
        }
        if !converged {
            return Err(StickSlipError::NotConverged {
                model: "return-mapping transient",
                what: "stick/slip active set of the slider velocity",
                iterations: MAX_ACTIVE_SET_ITERATIONS,
                residual: v1,
            });
        }
        Ok(v1)
    }

    /// The posts' modes and deflections at the slider velocity `v1`, and the step's sums.
    #[allow(clippy::needless_range_loop)]
    fn update_posts(&mut self, h: f64, v1: f64) -> Sums {
        let sys = &*self.sys;
        let n = sys.groups.len();
        let (rho, mu_k) = (sys.rho, sys.mu_k);
        let weights = &sys.groups.weight;
        // Update the posts and the sums.
        let mut step_sums = Sums {
            time: h,
            ..Default::default()
        };
        for g in 0..n {
            let w = weights[g];
            let trial = self.trial[g] - v1 * h;
            let normal = self.normal[g];
            let (mode, e) = match self.status[g] {
                SEPARATED => (Mode::Separated, 0.0),
                0 => (Mode::Stick, trial),
                sign => {
                    let sign = f64::from(sign);
                    (Mode::Slip(sign), sign * mu_k * normal / rho)
                }
            };
            let force = rho * e;
            let stator = force * self.increment[g];
            step_sums.force_time += w * force * h;
            step_sums.normal_time += w * normal * h;
            step_sums.stator_work += w * stator;
            self.group_work[g] += w * stator;
            step_sums.power_flow += w * stator.abs();
            step_sums.output_work += w * force * v1 * h;
            step_sums.dissipation += w * force * (trial - e);
            match mode {
                Mode::Separated => {}
                Mode::Stick => {
                    step_sums.contact_time += w * h;
                    step_sums.stick_time += w * h;
                }
                Mode::Slip(_) => step_sums.contact_time += w * h,
            }
            self.mode[g] = mode;
            self.deflection[g] = e;
        }
        step_sums
    }

    /// Stator particle displacement increment under group g over the step (exact along the
    /// phase path, clipped to the burst window).
    fn particle_increment(&self, g: usize, alpha0: f64, alpha1: f64) -> f64 {
        let sys = &*self.sys;
        let a_t = sys.wave.tangential_ratio;
        let rate = (alpha1 - alpha0) / self.h;
        let drive = 0.5 * (self.phases0.drive[g] + self.phases1.drive[g]);
        match sys.wave.burst_phase_end {
            None => a_t * drive * (self.phases1.cos[g] - self.phases0.cos[g]) / rate,
            Some(end) => {
                let phase = sys.groups.phase[g];
                let (lo, hi) = ((alpha0 - phase).max(0.0), (alpha1 - phase).min(end));
                if hi <= lo {
                    return 0.0;
                }
                let amplitude = self.phases0.drive[g].max(self.phases1.drive[g]);
                a_t * amplitude * (hi.cos() - lo.cos()) / rate
            }
        }
    }

    /// Backward-Euler vertical velocity: M(w1 − w)/h = Σ w N(z + h w1) − P − C w1.
    fn vertical(&self, damping: f64) -> Result<f64> {
        let sys = &*self.sys;
        let (h, m) = (self.h, sys.mass);
        let SliderState { z, w, .. } = self.st;
        let mut w1 = w;
        for _ in 0..MAX_VERTICAL_ITERATIONS {
            let z1 = z + h * w1;
            let (mut total, mut active) = (0.0, 0.0);
            for g in 0..sys.groups.len() {
                let pen = self.phases1.drive[g] * self.phases1.sin[g] - z1 - sys.groups.gap[g];
                if pen > 0.0 {
                    total += sys.groups.weight[g] * pen;
                    active += sys.groups.weight[g];
                }
            }
            let residual = m * (w1 - w) / h - total + sys.preload + damping * w1;
            let slope = m / h + h * active + damping;
            let next = w1 - residual / slope;
            if (next - w1).abs() <= 1e-14 * (1.0 + w1.abs()) {
                return Ok(next);
            }
            w1 = next;
        }
        Err(StickSlipError::NotConverged {
            model: "return-mapping transient",
            what: "backward-Euler vertical velocity",
            iterations: MAX_VERTICAL_ITERATIONS,
            residual: w1,
        })
    }
}

impl Stepper for ReturnMapping<'_> {
    fn state(&self) -> SliderState {
        self.st
    }

    fn steps(&self) -> u64 {
        self.steps
    }

    fn name(&self) -> &'static str {
        "return-mapping"
    }

    // Structure-of-arrays over the groups: index loops read several arrays at once.
    #[allow(clippy::needless_range_loop)]
    fn step(&mut self, _t_limit: f64, sums: &mut Sums) -> Result<()> {
        let sys = &*self.sys;
        let n = sys.groups.len();
        let h = self.h;
        let t1 = sys.t_start + (self.steps + 1) as f64 * h;
        let x_predicted = self.st.x + h * self.st.v;
        self.phases1.fill(&sys.groups, &sys.wave, t1, x_predicted);
        let alpha1 = t1 - sys.wave.doppler * x_predicted;
        self.increments(alpha1);
        let sys = &*self.sys;
        let (z1, w1) = match sys.vertical_damping {
            Some(damping) => {
                let w1 = self.vertical(damping)?;
                (self.st.z + h * w1, w1)
            }
            None => (sys.z_equilibrium, 0.0),
        };
        let (rho, mu_k, mu_s) = (sys.rho, sys.mu_k, sys.mu_s);
        // Per group: normal force, base = ê + Δu (trial = base − v h), stick threshold.
        for g in 0..n {
            let normal = sys.normal(&self.phases1, g, z1);
            self.normal[g] = normal;
            self.trial[g] = self.deflection[g] + self.increment[g];
            let threshold = if matches!(self.mode[g], Mode::Slip(_)) {
                mu_k
            } else {
                mu_s
            };
            self.threshold[g] = threshold * normal / rho;
        }
        let v1 = self.active_set(h)?;
        let step_sums = self.update_posts(h, v1);
        *sums += step_sums;
        self.st = SliderState {
            t: t1,
            x: self.st.x + h * v1,
            v: v1,
            z: z1,
            w: w1,
        };
        self.alpha = alpha1;
        std::mem::swap(&mut self.phases0, &mut self.phases1);
        self.steps += 1;
        Ok(())
    }

    fn stored_energy(&self) -> f64 {
        let sys = &*self.sys;
        (0..sys.groups.len())
            .map(|g| sys.groups.weight[g] * 0.5 * sys.rho * self.deflection[g].powi(2))
            .sum()
    }

    fn group(&self, g: usize) -> (f64, f64, Mode) {
        (
            self.normal[g],
            self.sys.rho * self.deflection[g],
            self.mode[g],
        )
    }

    fn totals(&self) -> (f64, f64) {
        self.sys.spring_totals(&self.deflection, &self.normal)
    }

    fn group_stator_work(&self) -> Option<&[f64]> {
        Some(&self.group_work)
    }

    fn system(&self) -> &System {
        &self.sys
    }

    fn retune(&mut self, profile: &[f64]) -> bool {
        self.sys.to_mut().set_profile(profile);
        true
    }
}

/// A group's status for the trial deflection `trial`: [`SEPARATED`] without load, 0 (stuck)
/// within the threshold, else the sign of the slip.
fn status_of(trial: f64, threshold: f64, normal: f64) -> i8 {
    if normal <= 0.0 {
        SEPARATED
    } else if trial.abs() <= threshold {
        0
    } else if trial > 0.0 {
        1
    } else {
        -1
    }
}
