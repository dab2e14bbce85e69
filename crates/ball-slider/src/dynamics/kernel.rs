//! One time step of the ball on the wave, in solver units (length A_n, time 1/ω, force the
//! preload P): Hertz's normal force by its discrete gradient, the MDR spring bed's return
//! mapping, the stator's displacement increments, and the step's energy books.

use std::f64::consts::PI;

use crate::dynamics::MAX_RESONANCE_STEP;
use crate::error::{BallError, Result};
use crate::hertz;
use crate::iwan::{BedStep, SpringBed};
use crate::mindlin::effective_shear_modulus_pa;
use crate::scene::BallScene;

/// Bed extent over the largest contact radius of the periodic state (room for the free
/// ball's vertical motion: the approach may grow by 1.25² − 1 = 56 %). Default 1.25.
const BED_MARGIN: f64 = 1.25;
/// Bisection steps for the equilibrium height (interval halves each step). Default 200.
const HEIGHT_BISECTIONS: usize = 200;

/// The scene in solver units.
#[derive(Debug, Clone)]
pub(crate) struct Kernel {
    /// Â_t = A_t/A_n.
    pub a_t: f64,
    /// κ = kA_n: phase change per unit ball displacement (θ = t − κx).
    pub kappa: f64,
    /// K̂: N̂ = K̂ δ̂^{3/2}.
    pub hertz: f64,
    /// m̂ = mω²A_n/P.
    pub mass: f64,
    /// Height of the ball's lowest point above the stator's mean plane at which the period
    /// mean of the normal force is the preload (ball held vertically still).
    pub z_eq: f64,
    /// Steps per period.
    pub steps: usize,
    /// The released spring bed, solver units.
    pub bed: SpringBed,
    /// Units: length A_n (m), force P (N), ω (rad/s).
    pub length_m: f64,
    pub force_n: f64,
    pub omega: f64,
    /// Contact resonance √(max(k_n, k_t)/m) at the deepest approach (rad/s).
    pub resonance_rad_per_s: f64,
    /// Ball radius (m).
    pub radius_m: f64,
    /// Extent of the spring bed (m).
    pub bed_extent_m: f64,
}

/// The state of the ball and its contact.
#[derive(Debug, Clone)]
pub(crate) struct State {
    /// Time (solver units, advisory).
    pub time: f64,
    /// Wave phase under the ball θ = t − κx, kept in [0, 2π).
    pub theta: f64,
    /// Position along x (advisory; forces depend on θ only).
    pub x: f64,
    /// Height of the ball's lowest point.
    pub z: f64,
    /// Velocity along x.
    pub v: f64,
    /// Vertical velocity.
    pub vz: f64,
    /// Tangential contact memory.
    pub bed: SpringBed,
}

/// Forces and increments of one step.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StepForces {
    /// Step-mean normal force (discrete gradient of Hertz's energy).
    pub normal: f64,
    /// Tangential bed books.
    pub bed: BedStep,
    /// Stator tangential displacement increment ∫∂u/∂t dt.
    pub du: f64,
    /// Normal surface height increment under the ball.
    pub dw: f64,
    /// Approach at the step's end.
    pub approach: f64,
    /// Phase at the step's end (not wrapped).
    pub theta: f64,
}

/// Energy books over an interval (solver units).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Books {
    pub time: f64,
    pub stator_tangential: f64,
    pub stator_normal: f64,
    pub dissipation: f64,
    /// Work delivered by the ball: against the load (free) or to the imposed motion.
    pub output: f64,
    /// ∫Q̄ dt (tangential force on the ball along +x).
    pub force_time: f64,
    /// ∫N̄ dt.
    pub normal_time: f64,
    /// Displacement along +x.
    pub distance: f64,
    /// Time with the approach > 0.
    pub contact_time: f64,
    /// Time with a spring slipping over the whole contact (gross slip: every spring in
    /// contact slipping).
    pub gross_slip_time: f64,
}

impl Books {
    pub fn add(&mut self, f: &StepForces, dx: f64, h: f64, output: f64) {
        self.time += h;
        self.stator_tangential += f.bed.mean_force * f.du;
        self.stator_normal += f.normal * f.dw;
        self.dissipation += f.bed.dissipation;
        self.output += output;
        self.force_time += f.bed.mean_force * h;
        self.normal_time += f.normal * h;
        self.distance += dx;
        if f.approach > 0.0 {
            self.contact_time += h;
            if f.bed.in_contact > 0 && f.bed.slipping >= f.bed.in_contact {
                self.gross_slip_time += h;
            }
        }
    }
}

impl Kernel {
    /// Solver units and the spring bed of a validated scene.
    pub fn new(scene: &BallScene) -> Result<Self> {
        scene.validate()?;
        let w = &scene.wave;
        let (a_n, p) = (w.normal_amplitude_m, scene.preload_n);
        let omega = w.angular_frequency_rad_per_s();
        let r = scene.ball.radius_m();
        let e_star = hertz::effective_modulus_pa(&scene.ball.material, &scene.stator);
        let g_star = effective_shear_modulus_pa(&scene.ball.material, &scene.stator);
        let k_hat = 4.0 / 3.0 * e_star * r.sqrt() * a_n.powf(1.5) / p;
        let z_eq = equilibrium_height(k_hat, scene.numerics.steps_per_period);
        let approach_max_m = (1.0 - z_eq) * a_n;
        let a_max = (r * approach_max_m).sqrt();
        let mass = scene.ball.mass_kg();
        let k_max = 2.0 * a_max * e_star.max(4.0 * g_star);
        let resonance = (k_max / mass).sqrt();
        let resolved = (2.0 * PI * resonance / omega / MAX_RESONANCE_STEP).ceil() as usize;
        let bed = SpringBed::sphere(
            r,
            BED_MARGIN * a_max,
            scene.numerics.springs,
            e_star,
            g_star,
            scene.friction_coefficient,
        )
        .rescaled(a_n, p);
        Ok(Self {
            a_t: w.tangential_amplitude_m / a_n,
            kappa: w.wavenumber_rad_per_m() * a_n,
            hertz: k_hat,
            mass: mass * omega * omega * a_n / p,
            z_eq,
            steps: scene.numerics.steps_per_period.max(resolved),
            bed,
            length_m: a_n,
            force_n: p,
            omega,
            resonance_rad_per_s: resonance,
            radius_m: r,
            bed_extent_m: BED_MARGIN * a_max,
        })
    }

    /// Hertz energy Û(δ) = (2/5)K̂δ₊^{5/2}.
    pub fn normal_energy(&self, d: f64) -> f64 {
        if d <= 0.0 {
            0.0
        } else {
            0.4 * self.hertz * d * d * d.sqrt()
        }
    }

    /// The step's forces for increments (dx, dz) over h from `s`, without changing `s`.
    pub fn forces(&self, s: &State, dx: f64, dz: f64, h: f64) -> Result<StepForces> {
        let theta1 = s.theta + h - self.kappa * dx;
        let rate = (theta1 - s.theta) / h;
        let du = self.a_t * (theta1.cos() - s.theta.cos()) / rate;
        let dw = theta1.sin() - s.theta.sin();
        let d0 = s.theta.sin() - s.z;
        let d1 = theta1.sin() - (s.z + dz);
        if d1 > s.bed.max_approach() {
            return Err(BallError::ContactBeyondBed {
                contact_m: (self.radius_m * d1 * self.length_m).sqrt(),
                bed_m: self.bed_extent_m,
                time_s: s.time / self.omega,
            });
        }
        Ok(StepForces {
            normal: discrete_gradient(self.hertz, d0, d1),
            bed: s.bed.trial(d1, du - dx),
            du,
            dw,
            approach: d1,
            theta: theta1,
        })
    }

    /// Period of the Doppler-shifted wave at drive speed V̂ (ball moving along −x).
    pub fn period(&self, drive_speed: f64) -> f64 {
        2.0 * PI / (1.0 + self.kappa * drive_speed)
    }

    /// Stored energy: kinetic + Hertz + bed + preload potential (solver units).
    pub fn stored_energy(&self, s: &State) -> f64 {
        0.5 * self.mass * (s.v * s.v + s.vz * s.vz)
            + self.normal_energy(s.theta.sin() - s.z)
            + s.bed.energy()
            + s.z
    }

    /// The state at rest height z_eq, phase 0, moving at drive speed V̂, bed saturated in
    /// the direction of forward sliding (or released if `saturate` is false).
    pub fn start(&self, drive_speed: f64, saturate: bool) -> State {
        let mut bed = self.bed.clone();
        let d0 = -self.z_eq;
        if saturate {
            bed.saturate(d0, 1.0);
        }
        State {
            time: 0.0,
            theta: 0.0,
            x: 0.0,
            z: self.z_eq,
            v: -drive_speed,
            vz: 0.0,
            bed,
        }
    }

    /// Power unit P A_n ω (W).
    pub fn power_unit_w(&self) -> f64 {
        self.force_n * self.length_m * self.omega
    }

    /// Speed unit A_n ω (m/s).
    pub fn speed_unit_m_per_s(&self) -> f64 {
        self.length_m * self.omega
    }
}

/// Advance the state's phase and position after a committed step.
pub(crate) fn wrap_phase(theta: f64) -> f64 {
    theta.rem_euclid(2.0 * PI)
}

/// (Û(δ₁) − Û(δ₀))/(δ₁ − δ₀) of Û = (2/5)Kδ₊^{5/2}, without cancellation; K δ^{3/2} in the limit.
pub(crate) fn discrete_gradient(k: f64, d0: f64, d1: f64) -> f64 {
    match (d0 > 0.0, d1 > 0.0) {
        (false, false) => 0.0,
        (true, true) => {
            let (s0, s1) = (d0.sqrt(), d1.sqrt());
            let sum4 =
                s1.powi(4) + s1.powi(3) * s0 + s1 * s1 * s0 * s0 + s1 * s0.powi(3) + s0.powi(4);
            0.4 * k * sum4 / (s0 + s1)
        }
        _ => {
            let u = |d: f64| {
                if d > 0.0 {
                    0.4 * k * d * d * d.sqrt()
                } else {
                    0.0
                }
            };
            (u(d1) - u(d0)) / (d1 - d0)
        }
    }
}

/// z such that the mean over one period (n steps, phase grid 2πj/n, ball still) of the
/// discrete-gradient Hertz force is 1 (the preload).
fn equilibrium_height(k: f64, n: usize) -> f64 {
    let mean = |z: f64| {
        (0..n)
            .map(|j| {
                let t0 = 2.0 * PI * j as f64 / n as f64;
                let t1 = 2.0 * PI * (j + 1) as f64 / n as f64;
                discrete_gradient(k, t0.sin() - z, t1.sin() - z)
            })
            .sum::<f64>()
            / n as f64
    };
    let static_approach = k.powf(-2.0 / 3.0);
    let (mut lo, mut hi) = (-1.0 - static_approach, 1.0);
    for _ in 0..HEIGHT_BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if mean(mid) > 1.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-15 * (1.0 + hi.abs()) {
            break;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discrete_gradient_is_the_energy_difference_quotient() {
        let k = 2.7;
        for (d0, d1) in [(0.3, 0.9), (1.0, 1.0 + 1e-9), (-0.2, 0.5), (0.4, -0.1)] {
            let u = |d: f64| if d > 0.0 { 0.4 * k * d.powf(2.5) } else { 0.0 };
            let got = discrete_gradient(k, d0, d1) * (d1 - d0);
            let want = u(d1) - u(d0);
            assert!(
                (got - want).abs() < 1e-14 * (1.0 + want.abs()),
                "ΔU at ({d0}, {d1}): {got} vs {want}"
            );
        }
        let tiny = discrete_gradient(k, 0.49, 0.49);
        assert!(
            (tiny - k * 0.49f64.powf(1.5)).abs() < 1e-14,
            "N at equal approaches"
        );
    }

    #[test]
    fn equilibrium_height_gives_the_preload_in_the_mean() {
        for k in [0.05, 1.0, 30.0] {
            let z = equilibrium_height(k, 64);
            let mean: f64 = (0..64)
                .map(|j| {
                    let t0 = 2.0 * PI * j as f64 / 64.0;
                    let t1 = 2.0 * PI * (j + 1) as f64 / 64.0;
                    discrete_gradient(k, t0.sin() - z, t1.sin() - z)
                })
                .sum::<f64>()
                / 64.0;
            assert!(
                (mean - 1.0).abs() < 1e-12,
                "mean normal force at K̂ = {k}: {mean}"
            );
        }
    }
}
