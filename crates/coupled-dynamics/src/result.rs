//! The coupled run's result (its JSON keys are the command line's contract) and η_dyn, the effective contact
//! ratio at which the lumped period-average model (stick_slip) reproduces the coupled curve
//! best.

use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;
use stick_slip::{DynamicScene, PeriodicAverageModel};

use crate::error::Result;
use crate::model::{CoupledModel, CoupledPoint, PeriodState};
use crate::scene::PreloadBalance;

/// Fewest steps per contact arc below which a warning is given: the stick/slip events inside
/// the arc are then located to worse than ≈ 1/8 of it. Default 8.
pub const MIN_CONTACT_STEPS: usize = 8;

/// Curve points per chain of warm-started neighbouring speeds ([`CoupledModel::at_speed_from`]):
/// a point started from the next faster one's periodic state needs fewer periods than from
/// rest; chains run in parallel. Default 7.
pub const CHAIN_POINTS: usize = 7;

/// Golden-section steps of the η_dyn search on ln η. Default 80.
const ETA_SEARCH_STEPS: usize = 80;
/// Search interval of η_dyn: [1e-3, the largest η the lumped model accepts]
/// (`contact_springs::effective_ratio::MAX_EFFECTIVE_RATIO`, the one η contract).
const ETA_RANGE: (f64, f64) = (1e-3, contact_springs::effective_ratio::MAX_EFFECTIVE_RATIO);

/// Result of a coupled run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoupledResult {
    /// Always "coupled".
    pub model: &'static str,
    /// Drive direction along x (−1 for the wave along +x, +1 for the reversed wave).
    pub drive_direction_x: f64,
    /// Stall thrust F(0⁺) (N).
    pub stall_thrust_n: f64,
    /// No-load speed (m/s).
    pub no_load_speed_m_per_s: f64,
    /// Speed–thrust curve from stall to no load.
    pub curve: Vec<CoupledPoint>,
    /// Largest |energy balance residual| over the curve, relative to the power flow.
    pub energy_balance_residual: f64,
    /// Best-fitting η of the lumped model, if a lumped scene was given.
    pub eta_dyn: Option<f64>,
    /// rms thrust misfit of the lumped model at η_dyn over the curve, relative to the stall
    /// thrust.
    pub eta_dyn_misfit: Option<f64>,
    /// Largest efficiency along the curve.
    pub efficiency: f64,
    /// Stick fraction at stall.
    pub stick_fraction: f64,
    /// Posts of the strip.
    pub posts: usize,
    /// Steps per (Doppler-shifted) period.
    pub steps_per_period: usize,
    /// Preload balance used.
    pub preload_balance: PreloadBalance,
    /// Largest natural residual of any step solve.
    pub max_solver_residual: f64,
    /// Wall time (s), normal solves included.
    pub wall_time_s: f64,
    /// Non-fatal findings.
    pub warnings: Vec<String>,
}

/// Run the coupled model: stall thrust, no-load speed, the curve; with `lumped` (the lumped
/// scene of the same slider: wave, springs, μ, preload, layout) also η_dyn.
pub fn solve(model: &CoupledModel, lumped: Option<&DynamicScene>) -> Result<CoupledResult> {
    let started = Instant::now();
    let stall_point = model.at_speed(0.0)?;
    let stall = stall_point.thrust_n;
    let (no_load, top) = model.no_load_search(stall)?;
    let points = model.scene().curve_points;
    let mut curve = vec![stall_point];
    curve.extend(curve_points(model, no_load, points, top.as_ref())?);
    assemble(model, lumped, no_load, curve, started)
}

/// The result of a solved curve (`curve[0]` the stall point, then the curve points up to the
/// no-load speed `no_load`): the warnings, η_dyn with `lumped`, the largest residuals; the wall
/// time from `started` plus the model's normal solves.
pub(crate) fn assemble(
    model: &CoupledModel,
    lumped: Option<&DynamicScene>,
    no_load: f64,
    curve: Vec<CoupledPoint>,
    started: Instant,
) -> Result<CoupledResult> {
    let scene = model.scene();
    let stall_point = curve[0];
    let stall = stall_point.thrust_n;
    let warnings = warnings(model, stall, &curve);
    let (eta_dyn, eta_dyn_misfit) = match lumped {
        Some(base) if stall > 0.0 => {
            let (eta, misfit) = fit_eta_dyn(&curve, stall, base)?;
            (Some(eta), Some(misfit))
        }
        _ => (None, None),
    };
    Ok(CoupledResult {
        model: "coupled",
        drive_direction_x: model.drive_direction_x(),
        stall_thrust_n: stall.max(0.0),
        no_load_speed_m_per_s: no_load,
        energy_balance_residual: curve
            .iter()
            .map(|p| p.energy_balance_residual.abs())
            .fold(0.0, f64::max),
        efficiency: curve.iter().map(|p| p.efficiency).fold(0.0, f64::max),
        stick_fraction: stall_point.stick_fraction,
        max_solver_residual: curve
            .iter()
            .map(|p| p.max_solver_residual)
            .fold(0.0, f64::max),
        curve,
        eta_dyn,
        eta_dyn_misfit,
        posts: scene.post_x_m.len(),
        steps_per_period: scene.steps_per_period,
        preload_balance: scene.preload_balance,
        wall_time_s: started.elapsed().as_secs_f64() + model.normal_wall_time_s(),
        warnings,
    })
}

/// The non-fatal findings of a curve: a locked slider, coarse contact arcs, posts that never
/// separate, speeds without a periodic cycle.
fn warnings(model: &CoupledModel, stall: f64, curve: &[CoupledPoint]) -> Vec<String> {
    let scene = model.scene();
    let mut warnings = Vec::new();
    if stall <= 0.0 {
        warnings.push(format!(
            "the slider is locked: F(0⁺) = {stall:.4} N ≤ 0; stall thrust and no-load speed reported as 0"
        ));
    }
    if let Some(k) = model.min_contact_steps().filter(|&k| k < MIN_CONTACT_STEPS) {
        let needed = scene.steps_per_period * MIN_CONTACT_STEPS.div_ceil(k);
        warnings.push(format!(
            "steps_per_period = {}: the shortest contact arc is resolved by {k} steps (< {MIN_CONTACT_STEPS}); the stick/slip events are coarsely located; use steps_per_period ≥ {needed}",
            scene.steps_per_period
        ));
    }
    let bound = model.never_separating_posts();
    if bound > 0 {
        warnings.push(format!(
            "{bound} posts never separate: at v = 0 their stuck state is not unique; the stall thrust is the steady state reached from zero tangential forces, not the v → 0⁺ limit"
        ));
    }
    if curve.iter().any(|p| !p.converged) {
        warnings.push(format!(
            "some speeds reached no periodic cycle within {} periods; averaged over the last half",
            crate::model::MAX_PERIODS
        ));
    }
    warnings
}

/// The curve points k = 1…`points`−1 at k v₀/(`points`−1), in order: chains of
/// [`CHAIN_POINTS`] neighbouring speeds solved in parallel, each chain from its fastest point
/// down, every point started from the periodic state of the one above it; the fastest chain
/// starts from `top` (the no-load search's last state), the others from rest. The chains are
/// fixed, so the result does not depend on the number of threads.
fn curve_points(
    model: &CoupledModel,
    no_load: f64,
    points: usize,
    top: Option<&PeriodState>,
) -> Result<Vec<CoupledPoint>> {
    Ok(curve_points_with_states(model, no_load, points, top)?
        .into_iter()
        .map(|(p, _)| p)
        .collect())
}

/// [`curve_points`] with each point's periodic state (the start of a neighbouring speed).
pub(crate) fn curve_points_with_states(
    model: &CoupledModel,
    no_load: f64,
    points: usize,
    top: Option<&PeriodState>,
) -> Result<Vec<(CoupledPoint, PeriodState)>> {
    let speeds: Vec<f64> = (1..points)
        .map(|k| no_load * k as f64 / (points - 1) as f64)
        .collect();
    let chains: Vec<(usize, &[f64])> = speeds.rchunks(CHAIN_POINTS).enumerate().collect();
    let solved = chains
        .into_par_iter()
        .map(|(c, chain)| {
            let mut warm = if c == 0 { top.cloned() } else { None };
            let mut out = Vec::with_capacity(chain.len());
            for &speed in chain.iter().rev() {
                let (point, state) = model.at_speed_from(speed, warm.as_ref())?;
                warm = Some(state.clone());
                out.push((point, state));
            }
            out.reverse();
            Ok(out)
        })
        .collect::<Result<Vec<Vec<(CoupledPoint, PeriodState)>>>>()?;
    Ok(solved.into_iter().rev().flatten().collect())
}

/// rms over the curve of (F_lumped(v; η) − F_coupled(v))/F_stall,coupled.
pub fn lumped_misfit(
    curve: &[CoupledPoint],
    stall_n: f64,
    base: &DynamicScene,
    eta: f64,
) -> Result<f64> {
    let mut scene = base.clone();
    scene.slider.effective_ratio = eta;
    let lumped = PeriodicAverageModel::new(&scene)?;
    let mut sum = 0.0;
    for p in curve {
        let f = lumped.at_speed(p.speed_m_per_s)?.thrust_n;
        sum += ((f - p.thrust_n) / stall_n).powi(2);
    }
    Ok((sum / curve.len() as f64).sqrt())
}

/// η_dyn by golden section on ln η over `ETA_RANGE`: (η, misfit).
pub fn fit_eta_dyn(
    curve: &[CoupledPoint],
    stall_n: f64,
    base: &DynamicScene,
) -> Result<(f64, f64)> {
    let golden = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (ETA_RANGE.0.ln(), ETA_RANGE.1.ln());
    let f = |x: f64| lumped_misfit(curve, stall_n, base, x.exp());
    let mut c = b - golden * (b - a);
    let mut d = a + golden * (b - a);
    let (mut fc, mut fd) = (f(c)?, f(d)?);
    for _ in 0..ETA_SEARCH_STEPS {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - golden * (b - a);
            fc = f(c)?;
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + golden * (b - a);
            fd = f(d)?;
        }
    }
    let x = 0.5 * (a + b);
    Ok((x.exp(), f(x)?))
}
