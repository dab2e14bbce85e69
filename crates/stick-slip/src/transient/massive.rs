//! Transient with posts that carry their own mass m_p (tip on the spring k_t), symplectic
//! Euler: the slider and the tips' spring forces are explicit, the friction is either an exact
//! Coulomb impulse (Moreau–Jean, `post-mass`) or μN·tanh(slip/v_reg) (`regularized-explicit`).
//! Stable for h·ω_p < 2 (post-mass) or h·γ + (h·ω_p)²/2 < 2 (regularised), ω_p = √(k_t/m_p).
//!
//! Tip equation: m_p ṗ = −k_t q + F_f with p the tip's absolute velocity and q its deflection
//! from the anchor on the slider (q̇ = p − v); the slider feels Σ k_t q.

use std::borrow::Cow;
use std::f64::consts::PI;

use super::groups::Phases;
use super::system::{SliderState, Stepper, Sums, System};
use crate::error::{Result, StickSlipError};
use crate::post::Mode;

/// Friction law of the tips.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum TipFriction {
    /// Exact Coulomb friction as an impulse per step.
    Coulomb,
    /// μ_k N tanh(slip / v̂_reg).
    Regularized { speed: f64 },
}

/// Symplectic-Euler stepper for posts with mass.
#[derive(Debug)]
pub(crate) struct MassivePosts<'a> {
    /// The system, borrowed until the amplitude profile is retuned mid-run (then owned).
    sys: Cow<'a, System>,
    friction: TipFriction,
    mass: f64,
    h: f64,
    steps: u64,
    st: SliderState,
    deflection: Vec<f64>,
    tip_velocity: Vec<f64>,
    mode: Vec<Mode>,
    normal: Vec<f64>,
    phases: Phases,
    /// Stator work of each group since the start (weighted).
    group_work: Vec<f64>,
}

impl<'a> MassivePosts<'a> {
    /// The slider's explicit step of `h` from the forces at the old time: (v, x, z, w) new.
    fn slider_step(&self, h: f64) -> (f64, f64, f64, f64) {
        let sys = &*self.sys;
        // Slider: explicit forces at t0.
        let (force0, normal0) = self.totals();
        let v1 = self.st.v + h * (force0 + sys.load) / sys.mass;
        let x1 = self.st.x + h * v1;
        let (z1, w1) = match sys.vertical_damping {
            Some(damping) => {
                let w1 = self.st.w + h * (normal0 - sys.preload - damping * self.st.w) / sys.mass;
                (self.st.z + h * w1, w1)
            }
            None => (sys.z_equilibrium, 0.0),
        };
        (v1, x1, z1, w1)
    }

    /// A stepper with step ≈ `step` (shortened to divide the wave period) from `start`.
    pub fn new(
        sys: &'a System,
        friction: TipFriction,
        step: f64,
        start: SliderState,
    ) -> Result<Self> {
        let name = match friction {
            TipFriction::Coulomb => "post-mass",
            TipFriction::Regularized { .. } => "regularized-explicit",
        };
        let mass = sys
            .post_mass
            .ok_or(StickSlipError::MissingPostMass { integrator: name })?;
        let n = sys.groups.len();
        let per_period = (2.0 * PI / step).ceil().max(1.0);
        let mut phases = Phases::new(n);
        phases.fill(&sys.groups, &sys.wave, start.t, start.x);
        let normal: Vec<f64> = (0..n).map(|g| sys.normal(&phases, g, start.z)).collect();
        // Tips start moving with the stator where in contact, with the slider elsewhere.
        let tip_velocity = (0..n)
            .map(|g| {
                if normal[g] > 0.0 {
                    sys.particle_velocity(&phases, g)
                } else {
                    start.v
                }
            })
            .collect();
        Ok(Self {
            sys: Cow::Borrowed(sys),
            friction,
            mass,
            h: 2.0 * PI / per_period,
            steps: 0,
            st: start,
            deflection: vec![0.0; n],
            tip_velocity,
            mode: vec![Mode::Stick; n],
            normal,
            phases,
            group_work: vec![0.0; n],
        })
    }
}

impl Stepper for MassivePosts<'_> {
    fn state(&self) -> SliderState {
        self.st
    }

    fn steps(&self) -> u64 {
        self.steps
    }

    fn name(&self) -> &'static str {
        match self.friction {
            TipFriction::Coulomb => "post-mass",
            TipFriction::Regularized { .. } => "regularized-explicit",
        }
    }

    fn step(&mut self, _t_limit: f64, sums: &mut Sums) -> Result<()> {
        let sys = &*self.sys;
        let n = sys.groups.len();
        let (h, m) = (self.h, self.mass);
        let t0 = self.st.t;
        let t1 = sys.t_start + (self.steps + 1) as f64 * h;
        let (v1, x1, z1, w1) = self.slider_step(h);
        // Old-time friction inputs (regularised law is explicit).
        let regularized_inputs: Option<Vec<(f64, f64)>> = match self.friction {
            TipFriction::Regularized { .. } => Some(
                (0..n)
                    .map(|g| (self.normal[g], sys.particle_velocity(&self.phases, g)))
                    .collect(),
            ),
            TipFriction::Coulomb => None,
        };
        self.phases.fill(&sys.groups, &sys.wave, t1, x1);
        let mut step_sums = Sums {
            time: h,
            ..Default::default()
        };
        for g in 0..n {
            let weight = sys.groups.weight[g];
            let q = self.deflection[g];
            step_sums.force_time += weight * sys.rho * q * h;
            step_sums.output_work += weight * sys.rho * q * v1 * h;
            let normal1 = sys.normal(&self.phases, g, z1);
            let stator1 = sys.particle_velocity(&self.phases, g);
            let (mode, tip, friction_work, dissipated) = match self.friction {
                TipFriction::Coulomb => {
                    let tip = Tip {
                        mode: self.mode[g],
                        velocity: self.tip_velocity[g],
                        deflection: q,
                    };
                    coulomb_tip(sys, tip, h, m, normal1, stator1)
                }
                TipFriction::Regularized { speed } => {
                    let (normal_old, stator_old) = regularized_inputs
                        .as_ref()
                        .map_or((0.0, 0.0), |inputs| inputs[g]);
                    let tip = self.tip_velocity[g];
                    regularized_tip(sys, tip, q, h, m, speed, normal_old, stator_old)
                }
            };
            add_post(
                &mut step_sums,
                weight,
                h,
                mode,
                normal1,
                friction_work,
                dissipated,
            );
            self.group_work[g] += weight * friction_work;
            self.tip_velocity[g] = tip;
            self.deflection[g] = q + h * (tip - v1);
            self.mode[g] = mode;
            self.normal[g] = normal1;
        }
        *sums += step_sums;
        self.st = SliderState {
            t: t1,
            x: x1,
            v: v1,
            z: z1,
            w: w1,
        };
        self.steps += 1;
        let worst = self.deflection.iter().fold(0.0f64, |a, q| a.max(q.abs()));
        if !(worst.is_finite() && worst < 1e8 && v1.is_finite()) {
            return Err(StickSlipError::Diverged {
                integrator: self.name(),
                time_s: t0,
                quantity: "post deflection (units of A_n)",
                value: worst,
            });
        }
        Ok(())
    }

    fn stored_energy(&self) -> f64 {
        let sys = &*self.sys;
        (0..sys.groups.len())
            .map(|g| {
                let tip = self.tip_velocity[g];
                sys.groups.weight[g]
                    * (0.5 * sys.rho * self.deflection[g].powi(2) + 0.5 * self.mass * tip * tip)
            })
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

/// One post's share of a step's sums: friction work (and its magnitude), dissipation, the
/// normal force's impulse, contact and stick time, each weighted by the group's `weight`.
fn add_post(
    sums: &mut Sums,
    weight: f64,
    h: f64,
    mode: Mode,
    normal: f64,
    friction_work: f64,
    dissipated: f64,
) {
    sums.stator_work += weight * friction_work;
    sums.power_flow += weight * friction_work.abs();
    sums.dissipation += weight * dissipated;
    sums.normal_time += weight * normal * h;
    if mode != Mode::Separated {
        sums.contact_time += weight * h;
    }
    if mode == Mode::Stick {
        sums.stick_time += weight * h;
    }
}

/// A post tip at the start of a step: its contact mode, velocity and deflection q.
#[derive(Debug, Clone, Copy)]
struct Tip {
    mode: Mode,
    velocity: f64,
    deflection: f64,
}

/// The Coulomb tip's step of `h` (mass `m`): the impulse that makes the tip move with the
/// stator at the new time (`stator1`) if the friction cone (static from stick, kinetic from
/// slip) under `normal1` allows it, else the kinetic impulse; separated without load. Returns
/// (mode, tip velocity, friction work, dissipated work).
fn coulomb_tip(
    sys: &System,
    tip: Tip,
    h: f64,
    m: f64,
    normal1: f64,
    stator1: f64,
) -> (Mode, f64, f64, f64) {
    let free = tip.velocity - h * sys.rho * tip.deflection / m;
    let needed = m * (stator1 - free);
    let threshold = if matches!(tip.mode, Mode::Slip(_)) {
        sys.mu_k
    } else {
        sys.mu_s
    };
    let (mode, impulse) = if normal1 <= 0.0 {
        (Mode::Separated, 0.0)
    } else if needed.abs() <= threshold * normal1 * h {
        (Mode::Stick, needed)
    } else {
        let sign = needed.signum();
        (Mode::Slip(sign), sign * sys.mu_k * normal1 * h)
    };
    let tip = free + impulse / m;
    (mode, tip, impulse * stator1, impulse * (stator1 - tip))
}

/// The regularised tip's explicit step of `h`: friction μ_k N tanh(slip/`speed`) from the
/// old-time normal force and stator velocity; stick while |slip| ≤ `speed`. Returns (mode, tip
/// velocity, friction work, dissipated work).
#[allow(clippy::too_many_arguments)]
fn regularized_tip(
    sys: &System,
    tip_velocity: f64,
    q: f64,
    h: f64,
    m: f64,
    speed: f64,
    normal_old: f64,
    stator_old: f64,
) -> (Mode, f64, f64, f64) {
    let slip = stator_old - tip_velocity;
    let friction = sys.mu_k * normal_old * (slip / speed).tanh();
    let tip = tip_velocity + h * (friction - sys.rho * q) / m;
    let mode = if normal_old <= 0.0 {
        Mode::Separated
    } else if slip.abs() <= speed {
        Mode::Stick
    } else {
        Mode::Slip(slip.signum())
    };
    (mode, tip, friction * stator_old * h, friction * slip * h)
}
