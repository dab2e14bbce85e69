//! Event-driven transient (massless posts, exact Coulomb friction): classical RK4 between
//! events on the smooth system of the current modes, with every stick/slip/contact transition
//! located by root finding on the cubic Hermite interpolant of the step and the step then
//! re-integrated exactly to the event.
//!
//! Event functions (an event when one crosses from ≤ 0 to > 0):
//! * stuck group: max(|ρê| − μ_s·pen, −pen) (static bound reached, or contact lost);
//! * slipping group along ς: max(−ς·(u̇ − v − ς μ_k Ṅ/ρ), −pen) (slip velocity reverses, or
//!   contact lost);
//! * separated group: pen (touchdown), pen = drive·sin θ − z − g.
//!
//! Order 4 between events; events are located to round-off on the interpolant, whose error is
//! O(h⁴). Stability: h·ω_max < 2.78 on the stuck slider modes. The power integrals (stator
//! work, output work, dissipation, normal impulse) are extra ODE states, so the energy balance
//! is RK4-accurate.

use super::groups::Phases;
use super::system::{SliderState, Stepper, Sums, System};
use crate::error::{Result, StickSlipError};
use crate::math::bracketed_root;
use crate::post::Mode;

const IX: usize = 0;
const IV: usize = 1;
const IZ: usize = 2;
const IW: usize = 3;
const I_STATOR: usize = 4;
const I_OUTPUT: usize = 5;
const I_DISSIPATION: usize = 6;
const I_NORMAL: usize = 7;
const I_FORCE: usize = 8;
const I_FLOW: usize = 9;
const IE: usize = 10;

/// Event-function value up to which a group at the start of a step still counts as "not yet
/// crossed" (solver units of force/velocity). Default 1e-12.
const EVENT_TOLERANCE: f64 = 1e-12;
/// Penetration (solver units, of A_n) below zero at which a contact counts as lost: keeps a
/// touchdown located to round-off (pen ≈ −1e-13) from reading as an immediate separation.
/// Forces vanish at pen ≤ 0 anyway. Default 1e-9.
const SEPARATION_OFFSET: f64 = 1e-9;
/// Fraction of the step at which the direction of an event function that starts on zero is
/// probed. Default 1e-3.
const PROBE_FRACTION: f64 = 1e-3;
/// Margin (per squared step, solver units) by which the RK4 stage estimate of an event
/// function at mid-step must be negative to skip the exact midpoint check; bounds the O(h²)
/// error of the stage estimate with a wide safety factor. Default 10.
const MIDPOINT_SCREEN: f64 = 10.0;
/// Transitions of one group at one instant after which the group is held in its mode for one
/// step (breaks tangency ping-pong). Default 3.
const MAX_TRANSITIONS_AT_ONE_INSTANT: u32 = 3;
/// Zero-length steps in a row accepted before declaring a Zeno loop. Default 100000.
const MAX_ZERO_STEPS: u32 = 100_000;

/// Event-driven stepper.
#[derive(Debug)]
pub(crate) struct EventDriven<'a> {
    sys: &'a System,
    h_max: f64,
    t: f64,
    y: Vec<f64>,
    modes: Vec<Mode>,
    /// RHS at (t, y) for the current modes, if valid.
    f0: Option<Vec<f64>>,
    /// Event values at (t, y).
    events0: Vec<f64>,
    k: [Vec<f64>; 4],
    y_stage: Vec<f64>,
    y1: Vec<f64>,
    f1: Vec<f64>,
    events1: Vec<f64>,
    /// Event values at the third RK4 stage (an O(h²) estimate of the step midpoint), used to
    /// screen which groups need the exact midpoint check.
    events_mid: Vec<f64>,
    phases: Phases,
    steps: u64,
    /// Transitions per group at the current instant.
    transitions_now: Vec<u32>,
    transitions_time: f64,
    /// Groups held in their mode until this time.
    held_until: Vec<f64>,
    zero_steps: u32,
}

/// The solver-unit quantities of one group at one state.
struct GroupKinematics {
    pen: f64,
    normal: f64,
    particle_velocity: f64,
    normal_rate: f64,
}

impl<'a> EventDriven<'a> {
    pub fn new(sys: &'a System, h_max: f64, start: SliderState) -> Self {
        let n = sys.groups.len();
        let mut y = vec![0.0; IE + n];
        y[IX] = start.x;
        y[IV] = start.v;
        y[IZ] = start.z;
        y[IW] = start.w;
        let size = y.len();
        let mut stepper = Self {
            sys,
            h_max,
            t: start.t,
            y,
            modes: vec![Mode::Stick; n],
            f0: None,
            events0: vec![0.0; n],
            k: [
                vec![0.0; size],
                vec![0.0; size],
                vec![0.0; size],
                vec![0.0; size],
            ],
            y_stage: vec![0.0; size],
            y1: vec![0.0; size],
            f1: vec![0.0; size],
            events1: vec![0.0; n],
            events_mid: vec![0.0; n],
            phases: Phases::new(n),
            steps: 0,
            transitions_now: vec![0; n],
            transitions_time: f64::NAN,
            held_until: vec![f64::NEG_INFINITY; n],
            zero_steps: 0,
        };
        // Initial modes: contact where the post penetrates, stuck with zero deflection.
        stepper
            .phases
            .fill(&sys.groups, &sys.wave, start.t, start.x);
        for g in 0..n {
            if sys.normal(&stepper.phases, g, start.z) <= 0.0 {
                stepper.modes[g] = Mode::Separated;
            }
        }
        stepper
    }

    fn kinematics(sys: &System, phases: &Phases, g: usize, y: &[f64]) -> GroupKinematics {
        let (v, z, w) = (y[IV], y[IZ], y[IW]);
        let (s, c, d) = (phases.sin[g], phases.cos[g], phases.drive[g]);
        let pen = d * s - z - sys.groups.gap[g];
        let phase_rate = 1.0 - sys.wave.doppler * v;
        let decay_rate = sys.wave.decay_length.map_or(0.0, |l| -v / l);
        GroupKinematics {
            pen,
            normal: pen.max(0.0),
            particle_velocity: -sys.wave.tangential_ratio * d * s,
            normal_rate: d * (c * phase_rate + s * decay_rate) - w,
        }
    }

    fn event_value(
        sys: &System,
        mode: Mode,
        kin: &GroupKinematics,
        deflection: f64,
        v: f64,
    ) -> f64 {
        match mode {
            Mode::Separated => kin.pen,
            Mode::Stick => {
                (sys.rho * deflection.abs() - sys.mu_s * kin.pen).max(-kin.pen - SEPARATION_OFFSET)
            }
            Mode::Slip(sign) => {
                let slip = kin.particle_velocity - v - sign * sys.mu_k * kin.normal_rate / sys.rho;
                (-sign * slip).max(-kin.pen - SEPARATION_OFFSET)
            }
        }
    }

    /// Right-hand side at (t, y) for `modes`; fills the event values too.
    fn rhs(
        sys: &System,
        phases: &mut Phases,
        modes: &[Mode],
        t: f64,
        y: &[f64],
        out: &mut [f64],
        events: Option<&mut [f64]>,
    ) {
        phases.fill(&sys.groups, &sys.wave, t, y[IX]);
        let v = y[IV];
        let (mut force, mut normal, mut stator, mut dissipation, mut flow) =
            (0.0, 0.0, 0.0, 0.0, 0.0);
        let mut events = events;
        for g in 0..sys.groups.len() {
            let kin = Self::kinematics(sys, phases, g, y);
            let weight = sys.groups.weight[g];
            let e = y[IE + g];
            let f = match modes[g] {
                Mode::Separated => {
                    out[IE + g] = 0.0;
                    0.0
                }
                Mode::Stick => {
                    out[IE + g] = kin.particle_velocity - v;
                    sys.rho * e
                }
                Mode::Slip(sign) => {
                    let bound_rate = sign * sys.mu_k * kin.normal_rate / sys.rho;
                    out[IE + g] = if kin.normal > 0.0 { bound_rate } else { 0.0 };
                    let slip = kin.particle_velocity - v - bound_rate;
                    dissipation += weight * sys.mu_k * kin.normal * slip.abs();
                    sign * sys.mu_k * kin.normal
                }
            };
            if let Some(ev) = events.as_deref_mut() {
                ev[g] = Self::event_value(sys, modes[g], &kin, e, v);
            }
            force += weight * f;
            normal += weight * kin.normal;
            stator += weight * f * kin.particle_velocity;
            flow += weight * (f * kin.particle_velocity).abs();
        }
        out[IX] = v;
        out[IV] = (force + sys.load) / sys.mass;
        match sys.vertical_damping {
            Some(damping) => {
                out[IZ] = y[IW];
                out[IW] = (normal - sys.preload - damping * y[IW]) / sys.mass;
            }
            None => {
                out[IZ] = 0.0;
                out[IW] = 0.0;
            }
        }
        out[I_STATOR] = stator;
        out[I_OUTPUT] = force * v;
        out[I_DISSIPATION] = dissipation;
        out[I_NORMAL] = normal;
        out[I_FORCE] = force;
        out[I_FLOW] = flow;
    }

    /// Classical RK4 from (t, y, f0) over h into `y1`.
    fn rk4(&mut self, h: f64) {
        let sys = self.sys;
        let f0 = self.f0.as_ref().expect("f0 computed before stepping");
        let [k1, k2, k3, k4] = &mut self.k;
        k1.copy_from_slice(f0);
        let stage = |out: &mut [f64], y: &[f64], k: &[f64], factor: f64| {
            for ((o, y), k) in out.iter_mut().zip(y).zip(k) {
                *o = y + factor * k;
            }
        };
        stage(&mut self.y_stage, &self.y, k1, 0.5 * h);
        Self::rhs(
            sys,
            &mut self.phases,
            &self.modes,
            self.t + 0.5 * h,
            &self.y_stage,
            k2,
            None,
        );
        stage(&mut self.y_stage, &self.y, k2, 0.5 * h);
        Self::rhs(
            sys,
            &mut self.phases,
            &self.modes,
            self.t + 0.5 * h,
            &self.y_stage,
            k3,
            Some(&mut self.events_mid),
        );
        stage(&mut self.y_stage, &self.y, k3, h);
        Self::rhs(
            sys,
            &mut self.phases,
            &self.modes,
            self.t + h,
            &self.y_stage,
            k4,
            None,
        );
        for (i, y1) in self.y1.iter_mut().enumerate() {
            *y1 = self.y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }

    fn ensure_f0(&mut self) {
        if self.f0.is_none() {
            let mut f0 = vec![0.0; self.y.len()];
            Self::rhs(
                self.sys,
                &mut self.phases,
                &self.modes,
                self.t,
                &self.y,
                &mut f0,
                Some(&mut self.events0),
            );
            self.f0 = Some(f0);
        }
    }

    /// The earliest event crossing among the groups within the step of `h` just taken (as a
    /// fraction τ of the step, and the group); groups held after a transition are skipped.
    fn earliest_event(&self, h: f64) -> Option<(f64, usize)> {
        let n = self.sys.groups.len();
        let mut earliest: Option<(f64, usize)> = None;
        for g in 0..n {
            if self.held_until[g] >= self.t {
                continue;
            }
            let (mut a, b) = (self.events0[g], self.events1[g]);
            if a > EVENT_TOLERANCE {
                continue;
            }
            let mut lo = 0.0;
            if a >= -EVENT_TOLERANCE {
                // On the line (just switched, or a tangency): judge by the local direction, not
                // by the step end, which a coarse step can carry past a grazing contact.
                let probe = self.interpolated_event(g, h, PROBE_FRACTION);
                if probe > EVENT_TOLERANCE {
                    if earliest.is_none_or(|(best, _)| 0.0 < best) {
                        earliest = Some((0.0, g));
                    }
                    continue;
                }
                a = probe;
                lo = PROBE_FRACTION;
            }
            // The midpoint catches a crossing and return within one step (a short slip); the
            // stage estimate screens out groups far from any event.
            let screened = self.events_mid[g] < -MIDPOINT_SCREEN * h * h - EVENT_TOLERANCE;
            let m = if screened {
                f64::NEG_INFINITY
            } else {
                self.interpolated_event(g, h, 0.5)
            };
            let bracket = if m > EVENT_TOLERANCE {
                Some((lo, 0.5))
            } else if b > EVENT_TOLERANCE.max(a) {
                Some((0.5, 1.0))
            } else {
                None
            };
            if let Some((lo, hi)) = bracket {
                let tau = bracketed_root(|tau| self.interpolated_event(g, h, tau), lo, hi, 1e-13);
                if earliest.is_none_or(|(best, _)| tau < best) {
                    earliest = Some((tau, g));
                }
            }
        }
        earliest
    }

    /// Event value of group g at fraction τ ∈ [0, 1] of a step of length h (cubic Hermite).
    fn interpolated_event(&self, g: usize, h: f64, tau: f64) -> f64 {
        let sys = self.sys;
        let f0 = self.f0.as_ref().expect("f0");
        let (t2, t3) = (tau * tau, tau * tau * tau);
        let (h00, h10, h01, h11) = (
            2.0 * t3 - 3.0 * t2 + 1.0,
            t3 - 2.0 * t2 + tau,
            -2.0 * t3 + 3.0 * t2,
            t3 - t2,
        );
        let at =
            |i: usize| h00 * self.y[i] + h10 * h * f0[i] + h01 * self.y1[i] + h11 * h * self.f1[i];
        let mut y = [0.0; IE + 1];
        for i in [IX, IV, IZ, IW] {
            y[i] = at(i);
        }
        let e = at(IE + g);
        let t = self.t + tau * h;
        // One group's phase only.
        let alpha = t - sys.wave.doppler * y[IX];
        let theta = alpha - sys.groups.phase[g];
        let (s, c) = theta.sin_cos();
        let on = sys.wave.is_on(theta);
        let drive = if on {
            sys.groups.amplitude[g] * sys.wave.amplitude_at(y[IX])
        } else {
            0.0
        };
        let kin = {
            let (v, z, w) = (y[IV], y[IZ], y[IW]);
            let pen = drive * s - z - sys.groups.gap[g];
            let phase_rate = 1.0 - sys.wave.doppler * v;
            let decay_rate = sys.wave.decay_length.map_or(0.0, |l| -v / l);
            GroupKinematics {
                pen,
                normal: pen.max(0.0),
                particle_velocity: -sys.wave.tangential_ratio * drive * s,
                normal_rate: drive * (c * phase_rate + s * decay_rate) - w,
            }
        };
        Self::event_value(sys, self.modes[g], &kin, e, y[IV])
    }

    /// Apply the transition of group g at the current (t, y).
    fn transition(&mut self, g: usize) {
        let sys = self.sys;
        self.phases.fill(&sys.groups, &sys.wave, self.t, self.y[IX]);
        let kin = Self::kinematics(sys, &self.phases, g, &self.y);
        let weight = sys.groups.weight[g];
        let e = self.y[IE + g];
        let v = self.y[IV];
        // Contact is being lost only where the penetration is (numerically) zero and falling;
        // at a touchdown pen ≈ 0 too, but rising.
        let separating = kin.pen <= SEPARATION_OFFSET && kin.normal_rate <= 0.0;
        let (mode, deflection) = match self.modes[g] {
            Mode::Separated => {
                if separating {
                    (Mode::Separated, 0.0)
                } else {
                    (Mode::Stick, 0.0)
                }
            }
            Mode::Stick => {
                if separating {
                    // Contact lost while stuck: the springs relax (energy released as dissipation).
                    self.y[I_DISSIPATION] += weight * 0.5 * sys.rho * e * e;
                    (Mode::Separated, 0.0)
                } else {
                    let sign = if e >= 0.0 { 1.0 } else { -1.0 };
                    let kinetic = sign * sys.mu_k * kin.normal / sys.rho;
                    self.y[I_DISSIPATION] += weight * 0.5 * sys.rho * (e * e - kinetic * kinetic);
                    let slip =
                        kin.particle_velocity - v - sign * sys.mu_k * kin.normal_rate / sys.rho;
                    let slipping = sign * slip > -EVENT_TOLERANCE;
                    (
                        if slipping {
                            Mode::Slip(sign)
                        } else {
                            Mode::Stick
                        },
                        kinetic,
                    )
                }
            }
            Mode::Slip(sign) => {
                if separating {
                    self.y[I_DISSIPATION] += weight * 0.5 * sys.rho * e * e;
                    (Mode::Separated, 0.0)
                } else {
                    (Mode::Stick, sign * sys.mu_k * kin.normal / sys.rho)
                }
            }
        };
        self.modes[g] = mode;
        self.y[IE + g] = deflection;
        if self.transitions_time != self.t {
            self.transitions_time = self.t;
            self.transitions_now.iter_mut().for_each(|c| *c = 0);
        }
        self.transitions_now[g] += 1;
        if self.transitions_now[g] >= MAX_TRANSITIONS_AT_ONE_INSTANT {
            self.held_until[g] = self.t + self.h_max;
        }
        self.f0 = None;
    }

    /// Put slipping groups' deflection exactly on their kinetic bound.
    fn project(&mut self) {
        let sys = self.sys;
        self.phases.fill(&sys.groups, &sys.wave, self.t, self.y[IX]);
        for g in 0..sys.groups.len() {
            match self.modes[g] {
                Mode::Slip(sign) => {
                    self.y[IE + g] =
                        sign * sys.mu_k * sys.normal(&self.phases, g, self.y[IZ]) / sys.rho
                }
                Mode::Separated => self.y[IE + g] = 0.0,
                Mode::Stick => {}
            }
        }
    }

    fn weights_by_mode(&self) -> (f64, f64) {
        let sys = self.sys;
        self.modes
            .iter()
            .enumerate()
            .fold((0.0, 0.0), |(stick, contact), (g, m)| {
                let w = sys.groups.weight[g];
                match m {
                    Mode::Stick => (stick + w, contact + w),
                    Mode::Slip(_) => (stick, contact + w),
                    Mode::Separated => (stick, contact),
                }
            })
    }

    fn accept(&mut self, h: f64, sums: &mut Sums) {
        let (stick, contact) = self.weights_by_mode();
        *sums += Sums {
            time: h,
            force_time: self.y1[I_FORCE] - self.y[I_FORCE],
            normal_time: self.y1[I_NORMAL] - self.y[I_NORMAL],
            stator_work: self.y1[I_STATOR] - self.y[I_STATOR],
            power_flow: self.y1[I_FLOW] - self.y[I_FLOW],
            output_work: self.y1[I_OUTPUT] - self.y[I_OUTPUT],
            dissipation: self.y1[I_DISSIPATION] - self.y[I_DISSIPATION],
            stick_time: stick * h,
            contact_time: contact * h,
        };
        std::mem::swap(&mut self.y, &mut self.y1);
        self.t += h;
    }
}

impl Stepper for EventDriven<'_> {
    fn state(&self) -> SliderState {
        SliderState {
            t: self.t,
            x: self.y[IX],
            v: self.y[IV],
            z: self.y[IZ],
            w: self.y[IW],
        }
    }

    fn steps(&self) -> u64 {
        self.steps
    }

    fn name(&self) -> &'static str {
        "event-driven"
    }

    fn group_stator_work(&self) -> Option<&[f64]> {
        None
    }

    fn system(&self) -> &System {
        self.sys
    }

    fn step(&mut self, t_limit: f64, sums: &mut Sums) -> Result<()> {
        let sys = self.sys;
        let n = sys.groups.len();
        if sys.vertical_damping.is_none() {
            self.y[IZ] = sys.z_equilibrium;
            self.y[IW] = 0.0;
        }
        self.ensure_f0();
        // Groups already past their event at the start (round-off, or an event at this very
        // instant) transition now.
        if let Some(g) =
            (0..n).find(|&g| self.events0[g] > EVENT_TOLERANCE && self.held_until[g] < self.t)
        {
            self.transition(g);
            self.zero_steps += 1;
            if self.zero_steps > MAX_ZERO_STEPS {
                return Err(StickSlipError::NotConverged {
                    model: "event-driven transient",
                    what: "event sequence at one instant (Zeno)",
                    iterations: MAX_ZERO_STEPS as usize,
                    residual: self.t,
                });
            }
            return Ok(());
        }
        let h = self.h_max.min(t_limit - self.t);
        if h <= 0.0 {
            return Ok(());
        }
        self.rk4(h);
        let (f1, events1) = (&mut self.f1, &mut self.events1);
        Self::rhs(
            sys,
            &mut self.phases,
            &self.modes,
            self.t + h,
            &self.y1,
            f1,
            Some(events1),
        );
        let earliest = self.earliest_event(h);
        match earliest {
            Some((tau, g)) if tau < 1.0 => {
                let h_event = tau * h;
                if h_event > 0.0 {
                    self.rk4(h_event);
                    self.accept(h_event, sums);
                    self.zero_steps = 0;
                } else {
                    self.zero_steps += 1;
                }
                self.transition(g);
                self.project();
            }
            _ => {
                self.accept(h, sums);
                std::mem::swap(&mut self.events0, &mut self.events1);
                self.project();
                // The RHS does not depend on slipping groups' deflection: f1 stays valid.
                let mut f0 = self.f0.take().unwrap_or_default();
                std::mem::swap(&mut f0, &mut self.f1);
                self.f0 = Some(f0);
                self.zero_steps = 0;
            }
        }
        self.steps += 1;
        let v = self.y[IV];
        if !v.is_finite() || !self.y[IZ].is_finite() {
            return Err(StickSlipError::Diverged {
                integrator: "event-driven",
                time_s: self.t,
                quantity: "slider velocity (solver units)",
                value: v,
            });
        }
        Ok(())
    }

    fn stored_energy(&self) -> f64 {
        let sys = self.sys;
        (0..sys.groups.len())
            .map(|g| sys.groups.weight[g] * 0.5 * sys.rho * self.y[IE + g].powi(2))
            .sum()
    }

    fn group(&self, g: usize) -> (f64, f64, Mode) {
        let sys = self.sys;
        let mut phases = Phases::new(sys.groups.len());
        phases.fill(&sys.groups, &sys.wave, self.t, self.y[IX]);
        let normal = sys.normal(&phases, g, self.y[IZ]);
        (normal, sys.rho * self.y[IE + g], self.modes[g])
    }

    fn totals(&self) -> (f64, f64) {
        let sys = self.sys;
        let mut phases = Phases::new(sys.groups.len());
        phases.fill(&sys.groups, &sys.wave, self.t, self.y[IX]);
        (0..sys.groups.len()).fold((0.0, 0.0), |(f, nn), g| {
            let w = sys.groups.weight[g];
            let normal = sys.normal(&phases, g, self.y[IZ]);
            let force = match self.modes[g] {
                Mode::Slip(sign) => sign * sys.mu_k * normal,
                Mode::Stick => sys.rho * self.y[IE + g],
                Mode::Separated => 0.0,
            };
            (f + w * force, nn + w * normal)
        })
    }
}
