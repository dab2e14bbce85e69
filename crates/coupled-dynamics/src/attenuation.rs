//! The energy-conserving wave under the slider: the posts draw the power they take from the
//! wave, so the amplitude falls along the propagation direction.
//!
//! Model (steady state): the wave power entering under the post array at the slider's leading
//! edge, P_in (W; the caller's power per beam width at the scene's amplitude times
//! min(array width, aperture), `saw-wave`), flows along the propagation direction; the
//! time-mean stator power the posts draw up to x leaves it,
//! P(x) = P_in − ∫₀ˣ p_drawn dx, and the local amplitude (normal and tangential together, their
//! ratio fixed by the cut) is A(x) = A₀ √(P(x)/P_in) (the Rayleigh wave's power flux ∝ |A|²).
//! Discretised on the strip's posts in the order the wave reaches them: post i sees the power
//! after the posts before it and half its own draw (midpoint rule),
//! P_i = P_in − Σ_{j before i} p_j − ½ p_i, and P_out = P_in − Σ p_j, so
//! P_in − P_out = Σ p_j = the slider's stator power exactly. The strip is one row of the array;
//! p_j is the whole slider's draw at that x (the strip post's power over the strip share), so
//! each of the count_y rows shares P_in equally. The strip must be a whole row along x for the
//! profile to cover the slider's length.
//!
//! Self-consistency: p_j depends on every post's amplitude (through the preload distribution
//! and the wave each post sees), so the profile α_i = A_i/A₀ is the fixed point of
//! α ← √(max(P_i, 0)/P_in), iterated with under-relaxation from α = 1 (the constant-amplitude
//! wave) until max|Δα| < `tolerance` (default 1e-8). A post that would draw more than what
//! remains is the case the clamp handles: P(x) ≥ 0, and a post at zero amplitude draws nothing.
//!
//! Assumptions: steady state; no reflection at the slider's edges; beam diffraction neglected
//! (the beam's power stays in the aperture); the wave's velocity and phase under the slider
//! unchanged (only its amplitude falls: mass loading and the posts' stiffness do not shift the
//! velocity). Stops holding when the drawn power changes the wave's form (a slider that
//! reflects, a strongly loaded surface), over distances where diffraction spreads the beam
//! (Fresnel length a²/λ ≈ 200 mm for the 9 mm beam, far above the slider), or in transients
//! shorter than the transit time under the slider (L/c ≈ 1 µs).

use crate::error::{CoupledError, Result};
use crate::model::{CoupledModel, CoupledPoint, PeriodState};
use crate::scene::CoupledScene;
use serde::Serialize;

/// Default tolerance of the fixed point: max |Δα| (of A₀). Default 1e-8.
pub const DEFAULT_AMPLITUDE_TOLERANCE: f64 = 1e-8;
/// Default under-relaxation factor of the fixed point (1: none). Default 0.7.
pub const DEFAULT_RELAXATION: f64 = 0.7;
/// Default iteration limit. Default 200.
pub const DEFAULT_MAX_ITERATIONS: usize = 200;

/// Settings of the energy-conserving wave.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AttenuationOptions {
    /// Wave power entering under the post array at the leading edge (W), whole slider.
    pub power_in_w: f64,
    /// Fixed-point tolerance on max |Δα| (α = A/A₀).
    pub tolerance: f64,
    /// Under-relaxation factor in (0, 1].
    pub relaxation: f64,
    /// Iteration limit.
    pub max_iterations: usize,
}

impl AttenuationOptions {
    /// Default tolerance, relaxation and iteration limit for `power_in_w`.
    pub fn new(power_in_w: f64) -> Self {
        Self {
            power_in_w,
            tolerance: DEFAULT_AMPLITUDE_TOLERANCE,
            relaxation: DEFAULT_RELAXATION,
            max_iterations: DEFAULT_MAX_ITERATIONS,
        }
    }
}

/// The self-consistent steady point at one speed with the energy-conserving wave.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttenuatedPoint {
    /// The steady point at the converged amplitude profile.
    pub point: CoupledPoint,
    /// Wave power entering under the array (W).
    pub wave_power_in_w: f64,
    /// Wave power leaving at the trailing edge (W): P_in − Σ p_i.
    pub wave_power_out_w: f64,
    /// A_i/A₀ at each post (scene order).
    pub amplitude_scale: Vec<f64>,
    /// Stator power each post draws (W, whole slider at that x; scene order).
    pub post_power_w: Vec<f64>,
    /// Fixed-point iterations.
    pub iterations: usize,
    /// max |Δα| of the last iteration.
    pub last_change: f64,
    /// |P_in − P_out − stator_power_w| / P_in.
    pub balance_residual: f64,
}

/// The steady point at `speed_m_per_s` with the energy-conserving wave (module docs): the
/// amplitude profile iterated to self-consistency. Errors: bad options (named), a solve of the
/// coupled model, or no convergence within `max_iterations`.
pub fn attenuated_at_speed(
    scene: &CoupledScene,
    speed_m_per_s: f64,
    options: &AttenuationOptions,
) -> Result<AttenuatedPoint> {
    let check = |parameter: &'static str, value: f64, ok: bool, requirement: &str| {
        if ok {
            Ok(())
        } else {
            Err(CoupledError::InvalidParameter {
                parameter,
                value,
                requirement: requirement.into(),
            })
        }
    };
    let o = options;
    check(
        "power_in_w",
        o.power_in_w,
        o.power_in_w.is_finite() && o.power_in_w > 0.0,
        "must be finite and > 0",
    )?;
    check(
        "tolerance",
        o.tolerance,
        o.tolerance > 0.0 && o.tolerance < 1e-2,
        "must lie in (0, 1e-2)",
    )?;
    check(
        "relaxation",
        o.relaxation,
        o.relaxation > 0.0 && o.relaxation <= 1.0,
        "must lie in (0, 1]",
    )?;
    let n = scene.post_x_m.len();
    // Posts in the order the wave reaches them (σx ascending); ties keep scene order.
    let sigma = scene.wave_direction.sign();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| (sigma * scene.post_x_m[a]).total_cmp(&(sigma * scene.post_x_m[b])));
    let mut alpha = vec![1.0; n];
    let mut warm: Option<PeriodState> = None;
    let mut last_change = f64::INFINITY;
    for iteration in 1..=o.max_iterations {
        let mut local = scene.clone();
        local.amplitude_scale = alpha.clone();
        let model = CoupledModel::new(&local)?;
        let (point, power, state) = model.post_stator_power_from(speed_m_per_s, warm.as_ref())?;
        warm = Some(state);
        let mut remaining = o.power_in_w;
        let mut target = vec![0.0; n];
        for &i in &order {
            let at_post = remaining - 0.5 * power[i];
            target[i] = (at_post.max(0.0) / o.power_in_w).sqrt();
            remaining -= power[i];
        }
        last_change = alpha
            .iter()
            .zip(&target)
            .map(|(a, t)| (t - a).abs())
            .fold(0.0, f64::max);
        if last_change < o.tolerance {
            let drawn: f64 = power.iter().sum();
            let out = o.power_in_w - drawn;
            return Ok(AttenuatedPoint {
                balance_residual: (o.power_in_w - out - point.stator_power_w).abs() / o.power_in_w,
                point,
                wave_power_in_w: o.power_in_w,
                wave_power_out_w: out,
                amplitude_scale: alpha,
                post_power_w: power,
                iterations: iteration,
                last_change,
            });
        }
        for (a, t) in alpha.iter_mut().zip(&target) {
            *a += o.relaxation * (t - *a);
        }
    }
    Err(CoupledError::NotConverged {
        what: "energy-conserving wave amplitude (fixed point)",
        iterations: o.max_iterations,
        residual: last_change,
        tolerance: o.tolerance,
        context: format!("at speed {speed_m_per_s:.6e} m/s"),
    })
}

/// Stall thrust, no-load speed and the speed–thrust curve with the energy-conserving wave,
/// every point self-consistent on its own (the profile depends on the operating point).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttenuatedCurve {
    /// F(0⁺) at the self-consistent profile (N); 0 if the slider is locked.
    pub stall_thrust_n: f64,
    /// Speed where the self-consistent thrust vanishes (m/s), Illinois regula falsi.
    pub no_load_speed_m_per_s: f64,
    /// Stall, then `curve_points` − 1 speeds up to the no-load speed.
    pub curve: Vec<AttenuatedPoint>,
    /// Most fixed-point iterations of a curve point.
    pub max_iterations: usize,
    /// Largest |P_in − P_out − stator power| / P_in over the curve.
    pub max_balance_residual: f64,
}

/// [`attenuated_at_speed`] at stall, the no-load speed and the scene's `curve_points` speeds
/// (k v₀/(points − 1)), each point iterated to self-consistency (rayon over the speeds; each
/// point's iteration is sequential, so the bits do not depend on the thread count).
pub fn solve_attenuated(
    scene: &CoupledScene,
    options: &AttenuationOptions,
) -> Result<AttenuatedCurve> {
    use rayon::prelude::*;
    let stall = attenuated_at_speed(scene, 0.0, options)?;
    let stall_n = stall.point.thrust_n;
    let model = CoupledModel::new(scene)?;
    let mut thrust = |speed: f64| -> Result<f64> {
        Ok(attenuated_at_speed(scene, speed, options)?.point.thrust_n)
    };
    let no_load = model.regula_falsi(stall_n, &mut thrust)?;
    let points = scene.curve_points;
    let rest = (1..points)
        .into_par_iter()
        .map(|k| attenuated_at_speed(scene, no_load * k as f64 / (points - 1) as f64, options))
        .collect::<Result<Vec<_>>>()?;
    let mut curve = vec![stall];
    curve.extend(rest);
    Ok(AttenuatedCurve {
        stall_thrust_n: stall_n.max(0.0),
        no_load_speed_m_per_s: no_load,
        max_iterations: curve.iter().map(|p| p.iterations).max().unwrap_or(0),
        max_balance_residual: curve.iter().map(|p| p.balance_residual).fold(0.0, f64::max),
        curve,
    })
}
