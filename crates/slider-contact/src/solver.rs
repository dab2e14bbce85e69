//! Frictionless unilateral contact of N posts under load control, on any compliance operator:
//! the constrained conjugate-gradient method of I. A. Polonsky & L. M. Keer, "A numerical method
//! for solving rough contact problems based on the multi-level multi-summation and conjugate
//! gradient techniques", Wear 231 (1999) 206–219 (§2.2, the load-controlled variant).
//!
//! Problem: post forces f ≥ 0 (N), gaps g_i = z_s − h_i + (C f)_i ≥ 0, f_i g_i = 0, Σ f_i = P,
//! with h_i the obstacle height under post i (stator surface plus the post's extra height) and
//! z_s the slider's rigid approach (the multiplier of the load). It is the minimum of
//! ½ fᵀCf − hᵀf on the simplex {f ≥ 0, Σf = P}. Each iteration: gap on the current contact set
//! I_c = {f_i > 0} with its mean removed (the z_s estimate), conjugate direction t on I_c, exact
//! step τ = (g·t)/(Ct·t) along it, projection f ≥ 0, posts with f = 0 and g < 0 re-enter with
//! f_i = −τ g_i (then the conjugacy restarts), rescaling to Σf = P. One application of C to f and
//! one to t per iteration: O(N log N) with [`crate::LatticeOperator`].
//!
//! Scaled units: forces by the mean post force P/N, lengths by `length_scale_m` (the wave
//! amplitude, or P/N × C_ii on a flat stator). Converged when the natural complementarity
//! residual max_i |min(f̃_i, g̃_i)| is below the tolerance (Σf = P holds to rounding).
//!
//! **Departures from Polonsky & Keer that only change the speed** (as in [`crate::balanced`]):
//! the conjugacy is kept when posts re-enter (re-entered posts start with t_i = 0; a direction that
//! is not a descent one falls back to the steepest descent), and when a step moves no post out of
//! or into the contact set, u = Cf is carried as (u − τ·Ct)·(N/Σf) (the rescaling is linear)
//! instead of recomputed: one operator application per iteration instead of two (recomputed every
//! [`MAX_UPDATED_U`] iterations, after a change of the set and before convergence is declared).
//!
//! The step with re-entry (`step_forces`) and the iteration-limit error (`not_converged`) live
//! here and are shared with [`crate::balanced`], which builds on this module (never the reverse).

use serde::Serialize;

use crate::error::{Result, SliderError, invalid};
use crate::lattice::ComplianceOperator;

/// Default tolerance on the scaled complementarity residual max_i |min(f_i N/P, g_i/L)|.
/// Dimensionless; default 1e-6. Chosen from the accuracy the stage needs: against a solve to
/// 1e-11 on the default slider (4 phases, 10 and 40 N, rigid / ball / pressure) it moves η by
/// ≤ 2.3e-7 relative and any post force by ≤ 3.6e-5 P/N, three decades below the two-scale
/// model's own error against a direct FEM (0.03–0.13 P/N, validation/whole-slider/README.md)
/// and below the four digits η is reported with; 1e-9 costs 1.3–1.5× the iterations.
pub const DEFAULT_TOLERANCE: f64 = 1e-6;
/// Default iteration limit. Default 5000.
pub const DEFAULT_MAX_ITERATIONS: usize = 5000;

/// Most iterations u = Cf is carried by updates before it is recomputed from f (bounds the
/// rounding drift). Default 25.
pub const MAX_UPDATED_U: usize = 25;

/// Options of [`ConstrainedCg`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CgOptions {
    /// See [`DEFAULT_TOLERANCE`].
    pub tolerance: f64,
    /// See [`DEFAULT_MAX_ITERATIONS`].
    pub max_iterations: usize,
}

impl Default for CgOptions {
    fn default() -> Self {
        Self {
            tolerance: DEFAULT_TOLERANCE,
            max_iterations: DEFAULT_MAX_ITERATIONS,
        }
    }
}

/// A solved contact.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CgSolution {
    /// Post forces f_i ≥ 0 (N).
    pub force_n: Vec<f64>,
    /// Gaps g_i ≥ 0 (m) (0 on the contact set up to the residual).
    pub gap_m: Vec<f64>,
    /// Slider approach z_s (m): g_i = z_s − h_i + (Cf)_i.
    pub reference_height_m: f64,
    /// Final scaled complementarity residual max_i |min(f_i N/P, g_i/L)| (with |Σf/P − 1|).
    pub complementarity_residual: f64,
    /// Iterations done.
    pub iterations: usize,
    /// Scaled residual at the start of each iteration.
    pub residual_history: Vec<f64>,
    /// Rigid rotation of a free slider (m per unit moment arm, x and y): the gap gains
    /// θ_x·ξ_i + θ_y·η_i; zero for [`ConstrainedCg::solve`] (the back's orientation is held).
    pub rotation_m: [f64; 2],
}

impl CgSolution {
    /// Posts carrying a force.
    pub fn in_contact(&self) -> Vec<bool> {
        self.force_n.iter().map(|&f| f > 0.0).collect()
    }
}

/// Polonsky–Keer constrained conjugate gradient (module doc).
#[derive(Debug, Clone, Default)]
pub struct ConstrainedCg {
    options: CgOptions,
}

fn mean_on(v: &[f64], mask: &[bool]) -> f64 {
    let (s, n) = v
        .iter()
        .zip(mask)
        .filter(|(_, m)| **m)
        .fold((0.0, 0usize), |(s, n), (x, _)| (s + x, n + 1));
    if n == 0 { 0.0 } else { s / n as f64 }
}

/// Gap g = s·u − h with its mean on the contact set removed (returned) and the scaled residual.
fn gap_and_residual(
    f: &[f64],
    u: &[f64],
    h: &[f64],
    s: f64,
    contact: &[bool],
    g: &mut [f64],
) -> (f64, f64) {
    for i in 0..g.len() {
        g[i] = s * u[i] - h[i];
    }
    let g_mean = mean_on(g, contact);
    g.iter_mut().for_each(|x| *x -= g_mean);
    let sum_f: f64 = f.iter().sum();
    let residual = f
        .iter()
        .zip(g.iter())
        .map(|(a, b)| a.min(*b).abs())
        .fold((sum_f / f.len() as f64 - 1.0).abs(), f64::max);
    (g_mean, residual)
}

impl ConstrainedCg {
    /// A solver with these options.
    pub fn new(options: CgOptions) -> Self {
        Self { options }
    }

    /// Steepest-descent direction t = g on the contact set, r = s·Ct; returns (g·t, (r − r̄)·t).
    fn steepest(
        op: &dyn ComplianceOperator,
        s: f64,
        contact: &[bool],
        g: &[f64],
        t: &mut [f64],
        r: &mut [f64],
    ) -> (f64, f64) {
        for i in 0..t.len() {
            t[i] = if contact[i] { g[i] } else { 0.0 };
        }
        op.apply(t, r);
        r.iter_mut().for_each(|x| *x *= s);
        let r_mean = mean_on(r, contact);
        let (mut gt, mut rt) = (0.0, 0.0);
        for i in (0..t.len()).filter(|&i| contact[i]) {
            gt += g[i] * t[i];
            rt += (r[i] - r_mean) * t[i];
        }
        (gt, rt)
    }

    fn validate(n: usize, height_m: &[f64], preload_n: f64, length_scale_m: f64) -> Result<()> {
        if n == 0 || height_m.len() != n {
            return Err(invalid(
                "obstacle_height_m",
                height_m.len() as f64,
                format!("one height per post is needed, the operator has {n} posts"),
            ));
        }
        if !(preload_n > 0.0 && preload_n.is_finite()) {
            return Err(invalid(
                "preload_n",
                preload_n,
                "must be positive and finite",
            ));
        }
        if !(length_scale_m > 0.0 && length_scale_m.is_finite()) {
            return Err(invalid(
                "length_scale_m",
                length_scale_m,
                "must be positive and finite",
            ));
        }
        if let Some(i) = height_m.iter().position(|h| !h.is_finite()) {
            return Err(invalid(
                "obstacle_height_m",
                height_m[i],
                format!("not finite at post {i}"),
            ));
        }
        Ok(())
    }

    /// The conjugate direction t = g + δ (|g|² / |g_old|²) t on the contact set and r = s·C t;
    /// a direction that does not descend restarts as steepest descent (δ = 0), else δ becomes 1.
    /// Returns (g·t, t·(r − r̄)).
    fn direction(
        op: &dyn ComplianceOperator,
        s: f64,
        contact: &[bool],
        g: &[f64],
        (delta, g_old): (&mut f64, &mut f64),
        t: &mut [f64],
        r: &mut [f64],
    ) -> (f64, f64) {
        let n = g.len();
        let g_norm: f64 = (0..n).filter(|&i| contact[i]).map(|i| g[i] * g[i]).sum();
        for i in 0..n {
            t[i] = if contact[i] {
                g[i] + *delta * (g_norm / *g_old) * t[i]
            } else {
                0.0
            };
        }
        *g_old = g_norm;
        op.apply(t, r);
        r.iter_mut().for_each(|x| *x *= s);
        let r_mean = mean_on(r, contact);
        let (mut gt, mut rt) = (0.0, 0.0);
        for i in (0..n).filter(|&i| contact[i]) {
            gt += g[i] * t[i];
            rt += (r[i] - r_mean) * t[i];
        }
        if gt <= 0.0 && *delta != 0.0 {
            // Not a descent direction (the kept conjugacy failed): steepest descent.
            *delta = 0.0;
            (gt, rt) = Self::steepest(op, s, contact, g, t, r);
        } else {
            *delta = 1.0;
        }
        (gt, rt)
    }

    /// Solves the contact of `op`'s posts on obstacle heights `height_m` (m) under `preload_n`;
    /// gaps are scaled by `length_scale_m` (m).
    pub fn solve(
        &self,
        op: &dyn ComplianceOperator,
        height_m: &[f64],
        preload_n: f64,
        length_scale_m: f64,
    ) -> Result<CgSolution> {
        self.solve_from(op, height_m, preload_n, length_scale_m, None)
    }

    /// [`Self::solve`] started from the forces `start_n` (N, e.g. the solution of nearby
    /// heights; scaled to sum to the preload) instead of equal forces: the same solution (the
    /// problem is a convex QP with one minimiser) to the tolerance, in fewer iterations when
    /// the start's contact set is nearly the solution's. A start of the wrong length or without
    /// a positive force is ignored.
    pub fn solve_from(
        &self,
        op: &dyn ComplianceOperator,
        height_m: &[f64],
        preload_n: f64,
        length_scale_m: f64,
        start_n: Option<&[f64]>,
    ) -> Result<CgSolution> {
        let n = op.len();
        Self::validate(n, height_m, preload_n, length_scale_m)?;
        let f0 = preload_n / n as f64;
        let s = f0 / length_scale_m;
        let h: Vec<f64> = height_m.iter().map(|x| x / length_scale_m).collect();
        let mut f = start_forces(n, start_n).unwrap_or_else(|| vec![1.0; n]);
        let mut t = vec![0.0; n];
        let (mut u, mut r) = (vec![0.0; n], vec![0.0; n]);
        let mut g = vec![0.0; n];
        let mut delta = 0.0;
        let mut g_old = 1.0;
        let mut history = Vec::new();
        // Iterations since u was last computed from f (None: stale, recompute now).
        let mut updated_for: Option<usize> = None;
        for iteration in 0..=self.options.max_iterations {
            if updated_for.is_none() {
                op.apply(&f, &mut u);
                updated_for = Some(0);
            }
            let contact: Vec<bool> = f.iter().map(|&x| x > 0.0).collect();
            let (mut g_mean, mut residual) = gap_and_residual(&f, &u, &h, s, &contact, &mut g);
            if residual <= self.options.tolerance && updated_for != Some(0) {
                // Converged on the updated u: confirm on u recomputed from f.
                op.apply(&f, &mut u);
                updated_for = Some(0);
                (g_mean, residual) = gap_and_residual(&f, &u, &h, s, &contact, &mut g);
            }
            history.push(residual);
            if residual <= self.options.tolerance {
                return Ok(CgSolution {
                    force_n: f.iter().map(|x| x * f0).collect(),
                    gap_m: g.iter().map(|x| x.max(0.0) * length_scale_m).collect(),
                    reference_height_m: -g_mean * length_scale_m,
                    complementarity_residual: residual,
                    iterations: iteration,
                    residual_history: history,
                    rotation_m: [0.0; 2],
                });
            }
            if iteration == self.options.max_iterations {
                break;
            }
            let (gt, rt) = Self::direction(
                op,
                s,
                &contact,
                &g,
                (&mut delta, &mut g_old),
                &mut t,
                &mut r,
            );
            let tau = if rt > 0.0 { gt / rt } else { 0.0 };
            let set_changed = step_forces(&mut f, &t, &g, &contact, tau);
            let sum: f64 = f.iter().sum();
            if sum <= 0.0 {
                f.iter_mut().for_each(|x| *x = 1.0);
                delta = 0.0;
                updated_for = None;
            } else {
                let scale = n as f64 / sum;
                f.iter_mut().for_each(|x| *x *= scale);
                updated_for = rescaled_u(updated_for, set_changed, (tau, s, scale), &r, &mut u);
            }
        }
        Err(not_converged(&self.options, &history, &f))
    }
}

/// A warm start's forces on the solvers' scale (Σf = n, f ≥ 0), or `None` when `start_n` does
/// not fit `n` posts or carries no positive force.
pub(crate) fn start_forces(n: usize, start_n: Option<&[f64]>) -> Option<Vec<f64>> {
    let start = start_n.filter(|f| f.len() == n)?;
    let sum: f64 = start.iter().map(|x| x.max(0.0)).sum();
    (sum > 0.0 && sum.is_finite())
        .then(|| start.iter().map(|x| x.max(0.0) * n as f64 / sum).collect())
}

/// The iteration limit reached: the last residual, the tolerance and the contact set's size.
pub(crate) fn not_converged(options: &CgOptions, history: &[f64], f: &[f64]) -> SliderError {
    SliderError::NotConverged {
        iterations: options.max_iterations,
        residual: history.last().copied().unwrap_or(f64::NAN),
        tolerance: options.tolerance,
        active: f.iter().filter(|&&x| x > 0.0).count(),
        posts: f.len(),
        context: String::new(),
    }
}

/// The step f ← max(f − τ t, 0) on the contact set; a penetrating post outside it re-enters
/// (Polonsky & Keer step 7). Returns whether the contact set changed.
pub(crate) fn step_forces(f: &mut [f64], t: &[f64], g: &[f64], contact: &[bool], tau: f64) -> bool {
    let mut set_changed = false;
    for i in 0..f.len() {
        if contact[i] {
            let fi = f[i] - tau * t[i];
            set_changed |= fi <= 0.0;
            f[i] = fi.max(0.0);
        }
        if f[i] == 0.0 && g[i] < 0.0 {
            f[i] = -tau.max(f64::MIN_POSITIVE) * g[i];
            set_changed = true;
        }
    }
    set_changed
}

/// u ← (u − τ C t) · scale (r = s·C t) while the contact set is unchanged, for at most
/// [`MAX_UPDATED_U`] iterations; `None`: recompute u from f.
fn rescaled_u(
    updated_for: Option<usize>,
    set_changed: bool,
    (tau, s, scale): (f64, f64, f64),
    r: &[f64],
    u: &mut [f64],
) -> Option<usize> {
    match updated_for {
        Some(k) if !set_changed && k < MAX_UPDATED_U => {
            for (ui, ri) in u.iter_mut().zip(r) {
                *ui = (*ui - tau * ri / s) * scale;
            }
            Some(k + 1)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::SliderError;
    use nalgebra::DMatrix;
    use static_contact::lumped::independent_posts;

    #[test]
    fn independent_posts_get_the_closed_form_forces() {
        let k = 1.8e6;
        let n = 50;
        let h: Vec<f64> = (0..n)
            .map(|i| 20e-9 * (1.0 - 2.0 * std::f64::consts::PI * i as f64 / 17.3).sin())
            .collect();
        let c = DMatrix::identity(n, n) / k;
        // Solved to 1e-9 (tighter than the default) to check the forces to 1e-8 of P/N.
        let sol = ConstrainedCg::new(CgOptions {
            tolerance: 1e-9,
            ..CgOptions::default()
        })
        .solve(&c, &h, 0.8, 20e-9)
        .unwrap();
        let (expected, _) = independent_posts(&h, k, 0.8);
        for (i, (f, e)) in sol.force_n.iter().zip(&expected).enumerate() {
            assert!(
                (f - e).abs() < 1e-8 * 0.8 / n as f64,
                "force on post {i}: CG {f} vs closed form {e}"
            );
        }
        assert!(sol.complementarity_residual <= 1e-9, "residual");
    }

    #[test]
    fn too_few_iterations_is_a_named_non_convergence_error() {
        let n = 30;
        let h: Vec<f64> = (0..n).map(|i| 1e-8 * (i as f64 * 0.7).sin()).collect();
        let c = DMatrix::from_fn(n, n, |i, j| 1e-6 / (1.0 + (i as f64 - j as f64).abs()));
        let err = ConstrainedCg::new(CgOptions {
            tolerance: 1e-14,
            max_iterations: 2,
        })
        .solve(&c, &h, 1.0, 1e-8)
        .unwrap_err();
        assert!(
            matches!(err, SliderError::NotConverged { iterations: 2, .. }),
            "non-convergence must be reported with its iteration count: {err}"
        );
    }
}
