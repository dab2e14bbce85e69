//! The transient with the energy-conserving wave: every column of posts its own phase group
//! (columns with equal x mod λ no longer merge: they see different amplitudes), the group's
//! amplitude multiplied by its column's α, and each group's draw the time mean of its stator
//! power Σ w F·Δu over the run's averaging window. Each fixed-point evaluation is one run at the
//! load; runs after the first start from the previous run's mean speed. The tolerance on α is
//! the caller's; a run's window mean is exact for its profile, so the fixed point is that of a
//! deterministic map, and the balance P_in − P_out = Σ draws = stator power closes to round-off.
//! Needs a stepper that keeps the stator work per group (return mapping — the transient's
//! default — post-mass, regularized explicit); the event-driven stepper is refused.

use serde::Serialize;

use super::{AttenuationOptions, check_scene, solve_amplitude_profile};
use crate::error::{Result, StickSlipError};
use crate::scene::TransientStart;
use crate::transient::{TransientModel, TransientRun};

/// One self-consistent transient run with the energy-conserving wave.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttenuatedRun {
    /// The run at the converged profile (`stator_power_w` = Σ group draws).
    pub run: TransientRun,
    /// Wave power entering under the array (W).
    pub wave_power_in_w: f64,
    /// Wave power leaving at the trailing edge (W): P_in − Σ draws.
    pub wave_power_out_w: f64,
    /// x of each column relative to the slider centre (m), ascending.
    pub x_m: Vec<f64>,
    /// A/A₀ of each column.
    pub amplitude_scale: Vec<f64>,
    /// Mean stator power each column draws over the averaging window (W, whole slider).
    pub group_power_w: Vec<f64>,
    /// Fixed-point evaluations (runs).
    pub iterations: usize,
    /// max |T(α) − α| at the reported profile.
    pub last_change: f64,
    /// |P_in − P_out − stator power| / P_in.
    pub balance_residual: f64,
}

impl TransientModel {
    /// The self-consistent run at external load `load_n` (N) with the energy-conserving wave of
    /// `options`, the first run from `start`, the profile from `warm` (one α per column, e.g.
    /// the period average's at the same load, [`crate::AttenuatedPeriodicModel`] without
    /// `bins`) or α = 1. Errors: bad options, a scene the attenuation cannot describe, the
    /// event-driven stepper, a failed run, or no convergence within `max_iterations`.
    pub fn run_attenuated(
        &self,
        load_n: f64,
        start: TransientStart,
        options: &AttenuationOptions,
        warm: Option<&[f64]>,
    ) -> Result<AttenuatedRun> {
        options.validate()?;
        check_scene(self.scene(), "transient with the energy-conserving wave")?;
        let columns = crate::transient::groups::columns(self.scene());
        let x_m: Vec<f64> = columns.iter().map(|c| c.0).collect();
        let start_profile = match warm {
            Some(w) if w.len() == x_m.len() => w.to_vec(),
            Some(w) => {
                return Err(StickSlipError::InvalidParameter {
                    parameter: "warm amplitude profile",
                    value: w.len() as f64,
                    requirement: format!("needs one entry per column ({})", x_m.len()),
                });
            }
            None => vec![1.0; x_m.len()],
        };
        let mut speed = self.initial_speed(load_n, start)?;
        let solution = solve_amplitude_profile(options, start_profile, |alpha| {
            let (run, power) = self.run_from(load_n, speed, false, Some(alpha), None)?;
            let power = power.ok_or(StickSlipError::ModelNotApplicable {
                model: "transient with the energy-conserving wave",
                reason: format!(
                    "the {} stepper keeps no stator power per group: use return-mapping, post-mass or regularized-explicit",
                    self.integrator().name()
                ),
            })?;
            speed = run.speed_m_per_s;
            Ok::<_, StickSlipError>((power, run))
        })?;
        if !solution.converged {
            return Err(StickSlipError::NotConverged {
                model: "transient with the energy-conserving wave",
                what: "amplitude profile (fixed point of the wave's power balance)",
                iterations: solution.iterations,
                residual: solution.last_change,
            });
        }
        let p_in = options.power_in_w;
        let out = p_in - solution.draw_w.iter().sum::<f64>();
        let run = solution.value;
        Ok(AttenuatedRun {
            wave_power_in_w: p_in,
            wave_power_out_w: out,
            balance_residual: (p_in - out - run.stator_power_w).abs() / p_in,
            run,
            x_m,
            amplitude_scale: solution.alpha,
            group_power_w: solution.draw_w,
            iterations: solution.iterations,
            last_change: solution.last_change,
        })
    }
}
