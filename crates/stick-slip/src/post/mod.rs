//! One post at an imposed constant slider speed, in solver units (length A_n, time 1/ω, force
//! k_n A_n): the building block of the period-average model (docs/physics.md §5.1).
//!
//! Phase θ = ωt − k(x_i + x_s) advances at θ̇ = s = 1 − κ v̂ (κ = kA_n, v̂ the slider's x-velocity
//! over A_n ω: the Doppler shift of the wave seen by a moving post). The stator particle under the
//! post moves at u̇ = −â sin θ (â = A_t/A_n), the normal force is N̂ = ⟨sin θ − c⟩₊, and the
//! elastic deflection ê of the Jenkins element obeys dê/dt̂ = u̇ − v̂ while stuck, |ρê| = μN̂ while
//! slipping (ρ = k_t/k_n), ê = 0 while separated.

pub(crate) mod analytic;
pub(crate) mod stepping;

use std::f64::consts::PI;
use std::ops::{Add, Sub};

use crate::math::wrap_angle;
use crate::mean_normal::TipHeight;

/// Parameters of one post in solver units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PostParams {
    /// â = A_t/A_n.
    pub tangential_ratio: f64,
    /// ρ = k_t/k_n.
    pub stiffness_ratio: f64,
    /// μ_s.
    pub mu_static: f64,
    /// μ_k.
    pub mu_kinetic: f64,
    /// κ = k·A_n.
    pub doppler: f64,
    /// Tip height (z_s + g)/A_n.
    pub height: TipHeight,
    /// m̂ = m_p ω²/k_n, if the post has mass.
    pub mass: Option<f64>,
}

impl PostParams {
    /// Phase rate s = 1 − κ v̂ at scaled x-velocity `v`.
    pub fn phase_rate(&self, v: f64) -> f64 {
        1.0 - self.doppler * v
    }

    /// Normal force N̂(θ) = ⟨sin θ − c⟩₊, cancellation-free near the edges of a narrow contact
    /// arc: cos θ' − cos φ = 2 sin((φ+θ')/2) sin((φ−θ')/2), θ' = θ − π/2.
    pub fn normal(&self, theta: f64) -> f64 {
        match self.height.half_arc {
            None => theta.sin() - self.height.c,
            Some(phi) => {
                let rel = wrap_angle(theta - 0.5 * PI);
                if rel.abs() >= phi {
                    0.0
                } else {
                    2.0 * (0.5 * (phi + rel)).sin() * (0.5 * (phi - rel)).sin()
                }
            }
        }
    }

    /// Where the contact state changes next after θ (for a separating post): `(true, θ_sep)`
    /// while in contact, `(false, θ_touchdown)` while separated. `None` if always in contact.
    pub fn contact_window(&self, theta: f64) -> Option<(bool, f64)> {
        let phi = self.height.half_arc?;
        let centre = 0.5 * PI + 2.0 * PI * ((theta - 0.5 * PI) / (2.0 * PI)).round();
        Some(if theta < centre - phi {
            (false, centre - phi)
        } else if theta < centre + phi {
            (true, centre + phi)
        } else {
            (false, centre + 2.0 * PI - phi)
        })
    }

    /// Scale of the tangential deflection: the kinetic friction bound at the crest,
    /// μ_s(1 − c)/ρ (used for relative tolerances).
    pub fn deflection_scale(&self) -> f64 {
        (self.mu_static.max(1e-12) * (1.0 - self.height.c) / self.stiffness_ratio).max(1e-300)
    }
}

/// Contact mode of a post.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Mode {
    /// No contact (N = 0, ê = 0).
    Separated,
    /// Stuck to the stator.
    Stick,
    /// Slipping with the friction force along sign (+1 or −1).
    Slip(f64),
}

/// Mode and elastic deflection of a post.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PostState {
    pub mode: Mode,
    /// Elastic tangential deflection ê (units of A_n).
    pub deflection: f64,
    /// Absolute tangential velocity of the post tip (posts with mass only; else unused).
    pub tip_velocity: f64,
}

impl PostState {
    pub fn separated() -> Self {
        Self {
            mode: Mode::Separated,
            deflection: 0.0,
            tip_velocity: 0.0,
        }
    }
}

/// Time integrals over an interval of the periodic motion of one post, in solver units
/// (time 1/ω, force k_n A_n, energy k_n A_n²).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct PeriodIntegrals {
    /// Duration.
    pub time: f64,
    /// ∫ F dt, F = ρê the tangential force on the slider along +x.
    pub force_time: f64,
    /// ∫ N dt.
    pub normal_time: f64,
    /// Stator work on the post, ∫ F·u̇ dt.
    pub stator_work: f64,
    /// ∫ |F·u̇| dt: the scale of the power flow (normalises the energy balance when the net
    /// stator work vanishes, e.g. a post stuck through the period).
    pub power_flow: f64,
    /// Output work on the slider, ∫ F·v dt.
    pub output_work: f64,
    /// Friction dissipation ∫ |F|·|slip rate| dt plus the elastic energy released when the
    /// friction drops from μ_s to μ_k.
    pub dissipation: f64,
    /// Time stuck.
    pub stick_time: f64,
    /// Time in contact.
    pub contact_time: f64,
    /// Change of the stored (elastic and, with post mass, kinetic) energy of the post.
    pub stored_energy_change: f64,
}

impl Add for PeriodIntegrals {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            time: self.time + o.time,
            force_time: self.force_time + o.force_time,
            normal_time: self.normal_time + o.normal_time,
            stator_work: self.stator_work + o.stator_work,
            power_flow: self.power_flow + o.power_flow,
            output_work: self.output_work + o.output_work,
            dissipation: self.dissipation + o.dissipation,
            stick_time: self.stick_time + o.stick_time,
            contact_time: self.contact_time + o.contact_time,
            stored_energy_change: self.stored_energy_change + o.stored_energy_change,
        }
    }
}

impl Sub for PeriodIntegrals {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self {
            time: self.time - o.time,
            force_time: self.force_time - o.force_time,
            normal_time: self.normal_time - o.normal_time,
            stator_work: self.stator_work - o.stator_work,
            power_flow: self.power_flow - o.power_flow,
            output_work: self.output_work - o.output_work,
            dissipation: self.dissipation - o.dissipation,
            stick_time: self.stick_time - o.stick_time,
            contact_time: self.contact_time - o.contact_time,
            stored_energy_change: self.stored_energy_change - o.stored_energy_change,
        }
    }
}

impl PeriodIntegrals {
    /// Mean tangential force ⟨F⟩ (along +x).
    pub fn mean_force(&self) -> f64 {
        self.force_time / self.time
    }

    /// Residual of the energy balance, stator work − output − dissipation − stored change,
    /// relative to the stator work.
    pub fn energy_balance_residual(&self) -> f64 {
        let residual =
            self.stator_work - self.output_work - self.dissipation - self.stored_energy_change;
        residual
            / self
                .power_flow
                .max(self.stator_work.abs())
                .max(self.dissipation.abs())
                .max(1e-300)
    }
}

/// Steady periodic behaviour of one post at one speed.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct SteadyPost {
    /// Integrals over the steady cycle (one or several wave periods).
    pub integrals: PeriodIntegrals,
    /// State at the start of one representative steady period and that period's start phase.
    pub start: (f64, PostState),
    /// Whether the cycle closed to tolerance (false: averaged over many quasi-periodic cycles).
    pub converged: bool,
}
