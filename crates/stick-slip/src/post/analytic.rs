//! Event-driven (analytic-switching) integration of one massless Jenkins post at constant
//! speed. Between events every quantity is closed-form in θ:
//!
//! * stick from (θ_a, ê_a): ê(θ) = ê_a + (â/s)(cos θ − cos θ_a) − (v̂/s)(θ − θ_a);
//! * slip along sign ς: ê = ς μ_k N̂(θ)/ρ, lasting while ς·σ_ς(θ) > 0 with the slip rate (per unit
//!   phase) σ_ς = −(â/s) sin θ − ς(μ_k/ρ) cos θ − v̂/s;
//! * separated: ê = 0.
//!
//! Every event function (ê ∓ μ_s N̂/ρ while stuck, σ_ς while slipping) has the form
//! a cos θ + b sin θ + gθ + d, whose critical points are closed-form; the first crossing is found
//! on a monotone bracket to machine precision ([`TrigLinear::first_crossing`]). The scheme is
//! therefore exact up to round-off: no step size, no order.
//!
//! **Event hysteresis (no Zeno loop at the friction-cone apex).** The event functions are
//! evaluated to an absolute accuracy of ≈ ε·(|a| + |b| + |gθ| + |d|) ≈ 1e-15, their O(1)
//! terms cancelling. Where the normal force vanishes (N̂ → 0 at a separation, the apex of the
//! friction cone), the static bound and the deflection of a post that re-sticks at the kinetic
//! bound differ by (μ_s − μ_k)N̂/ρ, which falls below that accuracy: the re-stuck post is judged
//! already past its static bound, the stick→slip event re-triggers at the same instant, and the
//! event sequence never advances (UQ sample 957 of `validation/design/scatter.toml`, seed 1: a
//! post that stays stuck through its contact and meets the lower bound 1 ulp before it
//! separates; test `a_stick_event_at_the_friction_cone_apex_does_not_retrigger`). The remedy is
//! the standard one of event location (L. F. Shampine & S. Thompson, "Event location for
//! ordinary differential equations", Comput. Math. Appl. 39 (2000) 43–54: a root located at the
//! start of a step, i.e. the event just handled, is not reported again): after an event that
//! leaves the post stuck (a re-stick at the kinetic bound, or the end of a slip), the search for
//! the next static-bound event starts [`AnalyticPost::x_tol`] (the tolerance every event is
//! located to, ≈ 1e-14 rad) later. Two events closer than that cannot be told apart anyway; in
//! exact arithmetic no such second event exists (a re-stuck post sits inside its static cone by
//! (μ_s − μ_k)N̂/ρ, or, with μ_s = μ_k, moves inwards), so non-degenerate trajectories are
//! unchanged, and every zero-progress cycle (stick → slip → stick at one θ) is broken.

use std::f64::consts::PI;

use super::{Mode, PeriodIntegrals, PostParams, PostState, SteadyPost};
use crate::error::{Result, StickSlipError};
use crate::math::{Crossing, TrigLinear, integrate};

/// Largest number of stick/slip events accepted in one call of [`AnalyticPost::advance`]
/// (a post has at most ≈ 6 per period; more means a Zeno loop). Default 4096.
const MAX_EVENTS: usize = 4096;
/// Largest number of period evaluations when searching the periodic steady state of a post
/// that never separates. Default 4000.
const MAX_PERIOD_EVALUATIONS: usize = 4000;
/// Relative tolerance (of the deflection scale) for two period-start states to count as equal.
const CYCLE_TOLERANCE: f64 = 1e-11;
/// Relative offset (of the deflection scale) below the upper-touching stuck orbit used for
/// the stall (v → 0⁺) orbit, so that round-off does not trigger a spurious slip. Default 1e-12.
const TOUCH_OFFSET: f64 = 1e-12;
/// Start phase of a period for posts that never separate: the normal-force minimum θ = −π/2.
const ALWAYS_CONTACT_START: f64 = -0.5 * PI;

/// One closed-form piece of a post's trajectory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Segment {
    pub mode: Mode,
    pub start: f64,
    pub end: f64,
    /// Deflection at `start` (stick segments integrate from it).
    pub deflection_start: f64,
}

/// One post at imposed scaled x-velocity `v`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AnalyticPost {
    pub p: PostParams,
    pub v: f64,
    /// Phase rate s = 1 − κ v̂.
    pub s: f64,
    /// â/s.
    alpha: f64,
    /// −v̂/s.
    gamma: f64,
}

impl AnalyticPost {
    pub fn new(p: PostParams, v: f64) -> Self {
        let s = p.phase_rate(v);
        Self {
            p,
            v,
            s,
            alpha: p.tangential_ratio / s,
            gamma: -v / s,
        }
    }

    fn x_tol(theta: f64) -> f64 {
        1e-14 * (1.0 + theta.abs())
    }

    /// The stuck trajectory through (θ_a, ê_a) as a [`TrigLinear`].
    fn stick_line(&self, theta_a: f64, e_a: f64) -> TrigLinear {
        TrigLinear {
            a: self.alpha,
            b: 0.0,
            g: self.gamma,
            d: e_a - self.alpha * theta_a.cos() - self.gamma * theta_a,
        }
    }

    /// Slip rate per unit phase σ_ς(θ) of a post sliding along the bound of sign ς.
    fn slip_rate(&self, sign: f64) -> TrigLinear {
        TrigLinear {
            a: -sign * self.p.mu_kinetic / self.p.stiffness_ratio,
            b: -self.alpha,
            g: 0.0,
            d: self.gamma,
        }
    }

    /// Deflection on a segment at phase θ.
    pub fn deflection(&self, seg: &Segment, theta: f64) -> f64 {
        match seg.mode {
            Mode::Separated => 0.0,
            Mode::Stick => self
                .stick_line(seg.start, seg.deflection_start)
                .value(theta),
            Mode::Slip(sign) => {
                sign * self.p.mu_kinetic * self.p.normal(theta) / self.p.stiffness_ratio
            }
        }
    }

    /// Stick ends at θ with the static bound of sign ς reached: the force drops to the kinetic
    /// bound (releasing ½ρ(ê² − ê_k²) into `dissipated`) and slip starts if the slip rate
    /// points outward, else the post re-sticks at the kinetic bound.
    fn enter_slip(
        &self,
        theta: f64,
        sign: f64,
        deflection: f64,
        dissipated: &mut f64,
    ) -> PostState {
        let rho = self.p.stiffness_ratio;
        let kinetic = sign * self.p.mu_kinetic * self.p.normal(theta) / rho;
        *dissipated += 0.5 * rho * (deflection * deflection - kinetic * kinetic);
        let rate = self.slip_rate(sign);
        let outward = sign * rate.value(theta);
        let tolerance = 1e-13 * (self.alpha + self.gamma.abs() + self.p.mu_kinetic / rho);
        let slipping =
            outward > 0.0 || (outward >= -tolerance && sign * rate.derivative(theta) > 0.0);
        let mode = if slipping {
            Mode::Slip(sign)
        } else {
            Mode::Stick
        };
        PostState {
            mode,
            deflection: kinetic,
            tip_velocity: 0.0,
        }
    }

    /// The stick line of a post stuck at (θ, `deflection`) and its first slip event on
    /// [θ, `limit`]: where it leaves the static band upwards (sign +1) or downwards (−1).
    /// `restuck`: the post re-stuck at θ itself, so that event is not reported again.
    fn stick_event(
        &self,
        theta: f64,
        deflection: f64,
        limit: f64,
        restuck: bool,
        scratch: &mut Vec<f64>,
    ) -> (TrigLinear, Option<(f64, f64)>) {
        let p = &self.p;
        let bound_s = p.mu_static / p.stiffness_ratio;
        let line = self.stick_line(theta, deflection);
        let c_term = bound_s * p.height.c;
        let upper = TrigLinear {
            b: -bound_s,
            d: line.d + c_term,
            ..line
        };
        let lower = TrigLinear {
            b: bound_s,
            d: line.d - c_term,
            ..line
        };
        let tol = Self::x_tol(limit);
        // Just re-stuck here: the event just handled is not reported again.
        let from = if restuck {
            (theta + Self::x_tol(theta)).min(limit)
        } else {
            theta
        };
        let up = upper.first_crossing(from, limit, Crossing::Upward, tol, scratch);
        let down = lower.first_crossing(from, limit, Crossing::Downward, tol, scratch);
        let event = match (up, down) {
            (Some(u), Some(d)) => Some(if u <= d { (u, 1.0) } else { (d, -1.0) }),
            (Some(u), None) => Some((u, 1.0)),
            (None, Some(d)) => Some((d, -1.0)),
            (None, None) => None,
        };
        (line, event)
    }

    /// A post slipping in direction `sign` at θ: its deflection at the kinetic bound.
    fn slipping(&self, sign: f64, theta: f64) -> PostState {
        let p = &self.p;
        PostState {
            mode: Mode::Slip(sign),
            deflection: sign * p.mu_kinetic * p.normal(theta) / p.stiffness_ratio,
            tip_velocity: 0.0,
        }
    }

    /// Where a post slipping in direction `sign` from θ re-sticks before `limit`: the slip
    /// rate's first crossing of zero (downward for sign +1, upward for −1).
    fn restick(&self, sign: f64, theta: f64, limit: f64, scratch: &mut Vec<f64>) -> Option<f64> {
        let rate = self.slip_rate(sign);
        let dir = if sign > 0.0 {
            Crossing::Downward
        } else {
            Crossing::Upward
        };
        rate.first_crossing(theta, limit, dir, Self::x_tol(limit), scratch)
    }

    /// Advance from (θ, state) to θ_end, appending the closed-form segments; energy released by
    /// static→kinetic drops is added to `dissipated`.
    pub fn advance(
        &self,
        mut theta: f64,
        theta_end: f64,
        mut state: PostState,
        segments: &mut Vec<Segment>,
        dissipated: &mut f64,
    ) -> Result<PostState> {
        let p = &self.p;
        let mut scratch = Vec::new();
        // Phase of the last event that left the post stuck (the hysteresis of the module doc).
        let mut restuck_at = None;
        let push = |segments: &mut Vec<Segment>, mode, start: f64, end: f64, e: f64| {
            if end > start {
                segments.push(Segment {
                    mode,
                    start,
                    end,
                    deflection_start: e,
                });
            }
        };
        for _ in 0..MAX_EVENTS {
            if theta >= theta_end {
                return Ok(state);
            }
            let window = p.contact_window(theta);
            let contact_limit = contact_limit(window, theta_end);
            match state.mode {
                Mode::Separated => match window {
                    None | Some((true, _)) => state = touched_down(),
                    Some((false, touchdown)) => {
                        let end = touchdown.min(theta_end);
                        push(segments, Mode::Separated, theta, end, 0.0);
                        theta = end;
                        if touchdown <= theta_end {
                            state = touched_down();
                        }
                    }
                },
                Mode::Stick => {
                    let Some((limit, separates)) = contact_limit else {
                        state = PostState::separated();
                        continue;
                    };
                    let restuck = restuck_at == Some(theta);
                    let (line, event) =
                        self.stick_event(theta, state.deflection, limit, restuck, &mut scratch);
                    match event {
                        Some((at, sign)) => {
                            push(segments, Mode::Stick, theta, at, state.deflection);
                            state = self.enter_slip(at, sign, line.value(at), dissipated);
                            theta = at;
                            restuck_at = (state.mode == Mode::Stick).then_some(at);
                        }
                        None => {
                            push(segments, Mode::Stick, theta, limit, state.deflection);
                            state.deflection = line.value(limit);
                            theta = limit;
                            if separates {
                                state = PostState::separated();
                            }
                        }
                    }
                }
                Mode::Slip(sign) => {
                    let Some((limit, separates)) = contact_limit else {
                        state = PostState::separated();
                        continue;
                    };
                    match self.restick(sign, theta, limit, &mut scratch) {
                        Some(at) => {
                            push(segments, Mode::Slip(sign), theta, at, state.deflection);
                            state = PostState {
                                mode: Mode::Stick,
                                ..self.slipping(sign, at)
                            };
                            theta = at;
                            restuck_at = Some(at);
                        }
                        None => {
                            push(segments, Mode::Slip(sign), theta, limit, state.deflection);
                            theta = limit;
                            state = match separates {
                                true => PostState::separated(),
                                false => self.slipping(sign, limit),
                            };
                        }
                    }
                }
            }
        }
        Err(StickSlipError::NotConverged {
            model: "event-driven post",
            what: "stick/slip event sequence (Zeno loop)",
            iterations: MAX_EVENTS,
            residual: theta_end - theta,
        })
    }

    /// Time integrals over the segments (Gauss–Legendre on each closed-form piece).
    pub fn integrals(&self, segments: &[Segment]) -> PeriodIntegrals {
        let p = &self.p;
        let rho = p.stiffness_ratio;
        let (s, a_t) = (self.s, p.tangential_ratio);
        let mut total = PeriodIntegrals::default();
        for seg in segments {
            let duration = (seg.end - seg.start) / s;
            let mut piece = PeriodIntegrals {
                time: duration,
                ..Default::default()
            };
            match seg.mode {
                Mode::Separated => {}
                Mode::Stick => {
                    let line = self.stick_line(seg.start, seg.deflection_start);
                    let [f, n, w, flow] = integrate(seg.start, seg.end, |t| {
                        let force = rho * line.value(t);
                        let power = -force * a_t * t.sin();
                        [force, p.normal(t), power, power.abs()]
                    });
                    piece.force_time = f / s;
                    piece.normal_time = n / s;
                    piece.stator_work = w / s;
                    piece.power_flow = flow / s;
                    piece.stick_time = duration;
                    piece.contact_time = duration;
                }
                Mode::Slip(sign) => {
                    let rate = self.slip_rate(sign);
                    let mu = p.mu_kinetic;
                    let [f, n, w, d, flow] = integrate(seg.start, seg.end, |t| {
                        let normal = p.normal(t);
                        let force = sign * mu * normal;
                        let power = -force * a_t * t.sin();
                        [
                            force,
                            normal,
                            power,
                            mu * normal * rate.value(t).abs(),
                            power.abs(),
                        ]
                    });
                    piece.force_time = f / s;
                    piece.normal_time = n / s;
                    piece.stator_work = w / s;
                    piece.power_flow = flow / s;
                    piece.dissipation = d;
                    piece.contact_time = duration;
                }
            }
            piece.output_work = piece.force_time * self.v;
            total = total + piece;
        }
        total
    }

    /// One period from (θ0, state): end state, integrals (with drop losses and the stored
    /// elastic energy change) and whether anything but sticking happened.
    fn period_from(
        &self,
        theta0: f64,
        state: PostState,
        segments: &mut Vec<Segment>,
    ) -> Result<(PostState, PeriodIntegrals, bool)> {
        segments.clear();
        let mut dropped = 0.0;
        let end = self.advance(theta0, theta0 + 2.0 * PI, state, segments, &mut dropped)?;
        let mut ints = self.integrals(segments);
        let rho = self.p.stiffness_ratio;
        ints.dissipation += dropped;
        ints.stored_energy_change = 0.5 * rho * (end.deflection.powi(2) - state.deflection.powi(2));
        let slipped = state.mode != Mode::Stick
            || end.mode != Mode::Stick
            || segments.iter().any(|s| s.mode != Mode::Stick);
        Ok((end, ints, slipped))
    }

    /// The periodic steady state of the post.
    ///
    /// * Separating post: the deflection resets at every separation, so one period from
    ///   touchdown is the steady state (unique for every speed, including v = 0).
    /// * Post always in contact, v ≠ 0: the period map is iterated; stuck periods are a pure
    ///   drift of ê by −2πv̂/s and are fast-forwarded in closed form up to the next bound
    ///   contact; the steady cycle is found when a post-slip state repeats.
    /// * Post always in contact, v = 0: the stuck steady state is not unique; the v → 0⁺ limit
    ///   is taken (docs/physics.md §5.1): the orbit dragged against its upper static bound (μ_s = μ_k),
    ///   or, with μ_s > μ_k, the mean over the slow creep between the post-snap orbit and the
    ///   touching orbit (mean thrust is affine in the orbit offset, so the midpoint orbit).
    pub fn steady(&self) -> Result<SteadyPost> {
        let mut segments = Vec::new();
        if let Some(phi) = self.p.height.half_arc {
            let theta0 = 0.5 * PI - phi;
            let start = PostState::separated();
            let (_, ints, _) = self.period_from(theta0, start, &mut segments)?;
            return Ok(SteadyPost {
                integrals: ints,
                start: (theta0, start),
                converged: true,
            });
        }
        if self.v == 0.0
            && let Some(stall) = self.stall_orbit(&mut segments)?
        {
            return Ok(stall);
        }
        let initial = if self.v == 0.0 {
            self.touching_orbit_start()
        } else {
            0.0
        };
        self.iterate_always_contact(
            PostState {
                mode: Mode::Stick,
                deflection: initial,
                tip_velocity: 0.0,
            },
            &mut segments,
        )
    }

    /// Start deflection (at θ = −π/2) of the stuck v = 0 orbit that touches its upper static
    /// bound, minus a round-off offset: ê0 = −(μ_s/ρ)c − hypot(μ_s/ρ, â/s).
    fn touching_orbit_start(&self) -> f64 {
        let bound = self.p.mu_static / self.p.stiffness_ratio;
        -bound * self.p.height.c
            - bound.hypot(self.alpha)
            - TOUCH_OFFSET * self.p.deflection_scale()
    }

    /// The v → 0⁺ orbit of a post that never separates, if it is a stuck orbit.
    fn stall_orbit(&self, segments: &mut Vec<Segment>) -> Result<Option<SteadyPost>> {
        let theta0 = ALWAYS_CONTACT_START;
        let touching = PostState {
            mode: Mode::Stick,
            deflection: self.touching_orbit_start(),
            tip_velocity: 0.0,
        };
        let (_, ints, slipped) = self.period_from(theta0, touching, segments)?;
        if slipped {
            return Ok(None);
        }
        if self.p.mu_kinetic >= self.p.mu_static {
            return Ok(Some(SteadyPost {
                integrals: ints,
                start: (theta0, touching),
                converged: true,
            }));
        }
        // Snap at the touching point θ_t (minimum of (μ_s/ρ) sin θ − (â/s) cos θ), then follow
        // one period to find the orbit the creep restarts from.
        let bound = self.p.mu_static / self.p.stiffness_ratio;
        let touch = self.alpha.atan2(bound) - 0.5 * PI;
        let mut dropped = 0.0;
        let at_touch = bound * self.p.normal(touch);
        let snapped = self.enter_slip(touch, 1.0, at_touch, &mut dropped);
        segments.clear();
        let after = self.advance(touch, touch + 2.0 * PI, snapped, segments, &mut dropped)?;
        if after.mode != Mode::Stick {
            return Ok(None);
        }
        let restart = after.deflection - self.alpha * (touch.cos() - theta0.cos());
        let mid = PostState {
            mode: Mode::Stick,
            deflection: 0.5 * (restart + touching.deflection),
            tip_velocity: 0.0,
        };
        let (_, ints, slipped) = self.period_from(theta0, mid, segments)?;
        Ok((!slipped).then_some(SteadyPost {
            integrals: ints,
            start: (theta0, mid),
            converged: true,
        }))
    }

    /// Distance of the stuck period from (θ0, ê0) to the static bound in the drift direction.
    fn stuck_margin(&self, theta0: f64, e0: f64, direction: f64, scratch: &mut Vec<f64>) -> f64 {
        let bound = self.p.mu_static / self.p.stiffness_ratio;
        let line = self.stick_line(theta0, e0);
        // direction > 0: bound − line; direction < 0: line + bound.
        let gap = TrigLinear {
            a: -direction * line.a,
            b: bound,
            g: -direction * line.g,
            d: -direction * line.d - bound * self.p.height.c,
        };
        gap.min_on(theta0, theta0 + 2.0 * PI, scratch).max(0.0)
    }

    fn iterate_always_contact(
        &self,
        mut state: PostState,
        segments: &mut Vec<Segment>,
    ) -> Result<SteadyPost> {
        let theta0 = ALWAYS_CONTACT_START;
        let tol = CYCLE_TOLERANCE * self.p.deflection_scale();
        let rho = self.p.stiffness_ratio;
        let period_time = 2.0 * PI / self.s;
        let mut cumulative = PeriodIntegrals::default();
        let mut records: Vec<(PostState, PeriodIntegrals)> = Vec::new();
        let mut scratch = Vec::new();
        let mut last_change = f64::INFINITY;
        for _ in 0..MAX_PERIOD_EVALUATIONS {
            let (end, ints, slipped) = self.period_from(theta0, state, segments)?;
            if !slipped {
                let drift = end.deflection - state.deflection;
                if drift == 0.0 {
                    return Ok(SteadyPost {
                        integrals: ints,
                        start: (theta0, state),
                        converged: true,
                    });
                }
                // Periods j = 1..n from ê0 + j·drift stay stuck; add them in closed form.
                let margin =
                    self.stuck_margin(theta0, state.deflection, drift.signum(), &mut scratch);
                let n = (margin / drift.abs()).floor().min(1e12);
                let triangle = 0.5 * n * (n + 1.0);
                let mut skipped = PeriodIntegrals {
                    time: n * ints.time,
                    force_time: n * ints.force_time + rho * drift * period_time * triangle,
                    normal_time: n * ints.normal_time,
                    stator_work: n * ints.stator_work,
                    power_flow: n * ints.power_flow,
                    output_work: n * ints.output_work
                        + self.v * rho * drift * period_time * triangle,
                    dissipation: 0.0,
                    stick_time: n * ints.stick_time,
                    contact_time: n * ints.contact_time,
                    stored_energy_change: 0.0,
                };
                let e_start = state.deflection;
                let e_end = e_start + (n + 1.0) * drift;
                skipped.stored_energy_change =
                    0.5 * rho * (e_end * e_end - end.deflection * end.deflection);
                cumulative = cumulative + ints + skipped;
                state = PostState {
                    deflection: e_end,
                    ..end
                };
                continue;
            }
            cumulative = cumulative + ints;
            let same = |a: &PostState, b: &PostState| {
                a.mode == b.mode && (a.deflection - b.deflection).abs() <= tol
            };
            if same(&end, &state) {
                return Ok(SteadyPost {
                    integrals: ints,
                    start: (theta0, state),
                    converged: true,
                });
            }
            if let Some((_, earlier)) = records.iter().rev().take(16).find(|(s, _)| same(s, &end)) {
                let cycle = cumulative - *earlier;
                return Ok(SteadyPost {
                    integrals: cycle,
                    start: (theta0, end),
                    converged: true,
                });
            }
            last_change = (end.deflection - state.deflection).abs();
            records.push((end, cumulative));
            state = end;
        }
        // Quasi-periodic: average over the second half of the recorded super-cycles.
        match records.get(records.len() / 2) {
            Some((_, mid)) if records.len() >= 2 => Ok(SteadyPost {
                integrals: cumulative - *mid,
                start: (theta0, state),
                converged: false,
            }),
            _ => Err(StickSlipError::NotConverged {
                model: "event-driven post",
                what: "periodic steady state of a post in permanent contact",
                iterations: MAX_PERIOD_EVALUATIONS,
                residual: last_change,
            }),
        }
    }
}

/// End of the current contact (if it ends before `theta_end`) and whether it separates there,
/// from the contact `window` at θ (`None` there: in contact throughout); `None`: not in contact.
fn contact_limit(window: Option<(bool, f64)>, theta_end: f64) -> Option<(f64, bool)> {
    match window {
        None => Some((theta_end, false)),
        Some((true, sep)) => Some(if sep < theta_end {
            (sep, true)
        } else {
            (theta_end, false)
        }),
        Some((false, _)) => None,
    }
}

/// A post that has just touched down: stuck, undeflected, at rest.
fn touched_down() -> PostState {
    PostState {
        mode: Mode::Stick,
        deflection: 0.0,
        tip_velocity: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mean_normal::TipHeight;
    use crate::post::stepping::{StepScheme, SteppedPost};

    /// The post of UQ sample 957 (`sawdrive uq validation/design/scatter.toml --seed 1`: η =
    /// 0.906, μ_s = 0.3076, μ_k = 0.2610; a separating post, c = 0.490) at 0.75 of the crest
    /// speed: stuck through its contact, it meets its lower static bound 1 ulp before it
    /// separates, where N̂ ≈ 1.5e-15.
    fn sample_957_post() -> AnalyticPost {
        let p = PostParams {
            tangential_ratio: 0.9108763652501815,
            stiffness_ratio: 0.8555870355581267,
            mu_static: 0.30759751091833776,
            mu_kinetic: 0.26100453644989396,
            doppler: 0.0003035004312741685,
            height: TipHeight {
                c: 0.490116217649261,
                half_arc: Some(1.0585732493067366),
            },
            mass: None,
        };
        AnalyticPost::new(p, -0.7500395914673577)
    }

    #[test]
    fn a_stick_event_at_the_friction_cone_apex_does_not_retrigger() {
        let post = sample_957_post();
        let phi = post.p.height.half_arc.unwrap();
        let (theta0, separation) = (0.5 * PI - phi, 0.5 * PI + phi);
        let mut segments = Vec::new();
        let mut dropped = 0.0;
        post.advance(
            theta0,
            theta0 + 2.0 * PI,
            PostState::separated(),
            &mut segments,
            &mut dropped,
        )
        .expect("one period of the sample-957 post");
        let flight = segments
            .iter()
            .find(|s| s.mode == Mode::Separated)
            .expect("a separated segment");
        assert!(
            (flight.start - separation).abs() < 1e-12,
            "contact ends at the separation phase {separation}, not {}",
            flight.start
        );
        assert!(
            (segments.last().unwrap().end - (theta0 + 2.0 * PI)).abs() < 1e-12,
            "the segments cover the period"
        );
        assert!(
            dropped.abs() < 1e-25,
            "energy released by the apex event (solver units): {dropped:e}"
        );
    }

    #[test]
    fn the_sample_957_post_agrees_with_the_return_mapping_scheme() {
        let post = sample_957_post();
        let steady = post.steady().expect("steady state of the sample-957 post");
        let ints = steady.integrals;
        assert!(
            ints.energy_balance_residual().abs() < 1e-10,
            "energy balance residual {:e}",
            ints.energy_balance_residual()
        );
        let step = 2.0 * PI / 20_000.0;
        let stepped = SteppedPost::new(post.p, post.v, StepScheme::ReturnMapping { step })
            .unwrap()
            .steady(
                0.5 * PI - post.p.height.half_arc.unwrap(),
                PostState::separated(),
            )
            .unwrap();
        let (exact, fixed) = (ints.mean_force(), stepped.integrals.mean_force());
        let scale = post.p.mu_static * post.p.height.c.abs().max(1.0);
        assert!(
            (exact - fixed).abs() < 1e-3 * scale,
            "mean post force, event-driven {exact:e} vs return mapping {fixed:e}"
        );
    }
}
