//! The two ways the ball is moved: at an imposed drive speed (the contact's periodic state,
//! ball held vertically at z_eq) and free (the ball's mass, load and preload, implicit
//! trapezoidal rule with the discrete-gradient normal force).

use crate::dynamics::kernel::{Books, Kernel, State, StepForces, wrap_phase};
use crate::error::{BallError, Result};

/// Largest change of any spring's deflection between two period starts (relative to the
/// largest deflection) that counts as periodic. Default 1e-11.
pub(crate) const PERIODIC_TOLERANCE: f64 = 1e-11;
/// Periods at imposed speed before the contact is declared not periodic. Default 64.
pub(crate) const MAX_IMPOSED_PERIODS: usize = 64;
/// Fixed-point iterations of one implicit free step at most. Default 60.
const MAX_FIXED_POINT_ITERATIONS: usize = 60;
/// Convergence of the free step's increments (solver length units, i.e. of A_n). Default 1e-15.
const FIXED_POINT_TOLERANCE: f64 = 1e-15;

/// Apply a step whose forces were evaluated with (dx, dz).
fn commit(s: &mut State, f: &StepForces, dx: f64, dz: f64, h: f64) {
    s.bed.commit(f.approach, f.du - dx);
    s.theta = wrap_phase(f.theta);
    s.x += dx;
    s.z += dz;
    s.time += h;
}

/// The contact's periodic state at imposed drive speed V̂ ≥ 0 (ball along −x).
#[derive(Debug, Clone)]
pub(crate) struct Periodic {
    /// Books of the last (periodic) period.
    pub books: Books,
    /// Stored energy at the end minus at the start of that period.
    pub stored_change: f64,
    /// The state at the end of it (a period start).
    pub state: State,
    /// Periods integrated.
    pub periods: usize,
}

/// Integrate at imposed speed from the saturated bed until the bed repeats over a period.
pub(crate) fn imposed(k: &Kernel, drive: f64) -> Result<Periodic> {
    let h = k.period(drive) / k.steps as f64;
    let mut s = k.start(drive, true);
    let mut previous = s.bed.deflections().to_vec();
    let mut change = f64::INFINITY;
    for period in 1..=MAX_IMPOSED_PERIODS {
        let stored0 = k.stored_energy(&s);
        let mut books = Books::default();
        for _ in 0..k.steps {
            let dx = -drive * h;
            let f = k.forces(&s, dx, 0.0, h)?;
            commit(&mut s, &f, dx, 0.0, h);
            books.add(&f, dx, h, f.bed.mean_force * dx);
        }
        // The phase grid is exactly periodic: snap the round-off of n steps of 2π/n.
        s.theta = 0.0;
        let e = s.bed.deflections();
        let scale = e
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs()))
            .max(f64::MIN_POSITIVE);
        change = e
            .iter()
            .zip(&previous)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            / scale;
        if period >= 2 && change <= PERIODIC_TOLERANCE {
            let stored_change = k.stored_energy(&s) - stored0;
            return Ok(Periodic {
                books,
                stored_change,
                state: s,
                periods: period,
            });
        }
        previous.copy_from_slice(e);
    }
    Err(BallError::NotPeriodic {
        speed_m_per_s: drive * k.speed_unit_m_per_s(),
        periods: MAX_IMPOSED_PERIODS,
        change,
    })
}

/// One implicit trapezoidal step of the free ball under load L̂ (force +x on the ball):
/// m̂Δv = h(Q̄ + L̂), m̂Δv_z = h(N̄ − 1), Δx = h(v₀ + v₁)/2, Δz = h(v_z0 + v_z1)/2, solved by
/// fixed-point iteration on (Δx, Δz) (a contraction while ω_c h ≤ 0.5).
fn free_step(k: &Kernel, s: &mut State, load: f64, h: f64, books: &mut Books) -> Result<()> {
    let c = 0.5 * h * h / k.mass;
    let mut dx = h * s.v + c * (s.bed.force() + load);
    let mut dz = h * s.vz + c * (k.hertz * (s.theta.sin() - s.z).max(0.0).powf(1.5) - 1.0);
    let mut change = f64::INFINITY;
    for _ in 0..MAX_FIXED_POINT_ITERATIONS {
        let f = k.forces(s, dx, dz, h)?;
        let nx = h * s.v + c * (f.bed.mean_force + load);
        let nz = h * s.vz + c * (f.normal - 1.0);
        change = (nx - dx).abs().max((nz - dz).abs());
        dx = nx;
        dz = nz;
        if change <= FIXED_POINT_TOLERANCE * (1.0 + dx.abs() + dz.abs()) {
            let f = k.forces(s, dx, dz, h)?;
            s.v += h * (f.bed.mean_force + load) / k.mass;
            s.vz += h * (f.normal - 1.0) / k.mass;
            commit(s, &f, dx, dz, h);
            books.add(&f, dx, h, -load * dx);
            return Ok(());
        }
    }
    Err(BallError::StepDidNotConverge {
        time_s: s.time / k.omega,
        iterations: MAX_FIXED_POINT_ITERATIONS,
        change,
    })
}

/// Integrate the free ball for `steps` steps of h; returns the books and the stored-energy
/// change.
pub(crate) fn free(
    k: &Kernel,
    s: &mut State,
    load: f64,
    h: f64,
    steps: usize,
) -> Result<(Books, f64)> {
    let stored0 = k.stored_energy(s);
    let mut books = Books::default();
    for _ in 0..steps {
        free_step(k, s, load, h, &mut books)?;
    }
    Ok((books, k.stored_energy(s) - stored0))
}
