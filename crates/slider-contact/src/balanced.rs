//! Contact of a *free* slider (preload by a pressure on the back or a ball at a point): the
//! posts' forces must balance the preload in force **and in both moments**, and the slider's
//! approach and two rotations are the multipliers. This generalises the load-controlled
//! constrained CG of Polonsky & Keer (Wear 231 (1999) 206, [`crate::solver`]), whose single
//! constraint Σf = P has the approach as its multiplier, to the three rigid modes
//! φ_i = (1, ξ_i, η_i) of the back, with (ξ_i, η_i) the post's moment arms about the load point
//! (scaled to O(1)):
//!
//! f ≥ 0, g_i = (Cf)_i − h_i + c·φ_i ≥ 0, f_i g_i = 0, Σ f_i φ_i = (P, 0, 0).
//!
//! It is the minimum of ½ fᵀCf − hᵀf on {f ≥ 0, Σ f φ = (P, 0, 0)} (C symmetric positive
//! definite), solved as Polonsky–Keer with: the gap's mean on the contact set replaced by its
//! least-squares fit by (1, ξ, η) there (the multipliers c), the conjugate direction kept
//! orthogonal to the three modes on the contact set (so a step keeps the balance), and the
//! rescaling Σf = P replaced by the multiplicative correction f_i ← f_i·(a·φ_i), a chosen so that
//! Σ f φ = (P, 0, 0) holds again (Polonsky & Keer's rescale when φ = 1; posts whose factor turns
//! negative drop out). Converged when max_i |min(f̃_i, g̃_i)| and the scaled balance residual
//! |Σ f̃ φ − (N, 0, 0)|/N are below the tolerance. Needs the load point strictly inside the convex
//! hull of the posts (else no balance with f ≥ 0: the slider tips), which the caller checks.
//!
//! **Departures from Polonsky & Keer that only change the speed** (measured on the default
//! slider under a pressure, 10 000 posts, 4 phases: 1203 → 826 iterations, validation/whole-slider
//! README). (1) The conjugacy is *not* restarted when posts re-enter the contact set (Polonsky &
//! Keer set δ = 0 then): the re-entered posts start with t_i = 0, the direction is still projected
//! on the set and off the modes, and a direction that is not a descent one (g·t ≤ 0) falls back
//! to the steepest descent; restarting made the plate's long-wavelength bending converge at the
//! steepest-descent rate while the set still changed. (2) When a step moves no post out of or into
//! the set, f − τt already balances the preload (t is orthogonal to the modes on the set), the
//! rebalancing is skipped and u = Cf is updated as u − τ·Ct, one operator application per
//! iteration instead of two (recomputed from f every `MAX_UPDATED_U` iterations, after any
//! change of the set, and before convergence is declared).

use nalgebra::{Matrix3, Vector3};

use crate::error::{Result, invalid};
use crate::lattice::ComplianceOperator;
use crate::precondition::ContactPreconditioner;
use crate::solver::{CgOptions, CgSolution, not_converged, step_forces};

/// Iterations of the multiplicative balance correction (each drops the posts whose factor is
/// negative). Default 20.
const BALANCE_PASSES: usize = 20;

/// Most iterations the displacement u = C f is carried by the update u ← u − τ C t before it is
/// recomputed from f (bounds the rounding drift; u is also recomputed whenever a post left or
/// entered the contact set, and before convergence is declared). Default 25.
const MAX_UPDATED_U: usize = 25;

fn phi(arm: (f64, f64)) -> Vector3<f64> {
    Vector3::new(1.0, arm.0, arm.1)
}

/// Solves M c = r for a symmetric positive semi-definite 3 × 3 M (pseudo-inverse if singular).
fn solve3(m: Matrix3<f64>, r: Vector3<f64>) -> Vector3<f64> {
    m.cholesky().map_or_else(
        || {
            m.pseudo_inverse(1e-12 * m.norm().max(f64::MIN_POSITIVE))
                .map_or(Vector3::zeros(), |p| p * r)
        },
        |c| c.solve(&r),
    )
}

/// Least-squares fit c of v by the modes on the masked posts.
fn fit_modes(v: &[f64], mask: &[bool], arms: &[(f64, f64)]) -> Vector3<f64> {
    let (mut m, mut r) = (Matrix3::zeros(), Vector3::zeros());
    for i in (0..v.len()).filter(|&i| mask[i]) {
        let p = phi(arms[i]);
        m += p * p.transpose();
        r += p * v[i];
    }
    solve3(m, r)
}

/// Σ f φ − (n, 0, 0), scaled by n.
fn balance_residual(f: &[f64], arms: &[(f64, f64)]) -> f64 {
    let n = f.len() as f64;
    let s = f
        .iter()
        .zip(arms)
        .fold(Vector3::zeros(), |acc, (x, a)| acc + phi(*a) * *x);
    (s - Vector3::new(n, 0.0, 0.0)).abs().max() / n
}

/// Scaled residual: max_i |min(f̃_i, g̃_i)| and the balance residual.
fn complementarity(f: &[f64], g: &[f64], arms: &[(f64, f64)]) -> f64 {
    f.iter()
        .zip(g)
        .map(|(a, b)| a.min(*b).abs())
        .fold(balance_residual(f, arms), f64::max)
}

/// Multiplicative correction f_i ← f_i (a·φ_i) to Σ f φ = (n, 0, 0); false if impossible.
fn rebalance(f: &mut [f64], arms: &[(f64, f64)]) -> bool {
    let target = Vector3::new(f.len() as f64, 0.0, 0.0);
    for _ in 0..BALANCE_PASSES {
        let mut m = Matrix3::zeros();
        for (x, a) in f.iter().zip(arms).filter(|(x, _)| **x > 0.0) {
            let p = phi(*a);
            m += p * p.transpose() * *x;
        }
        let Some(chol) = m.cholesky() else {
            return false;
        };
        let a = chol.solve(&target);
        let mut dropped = false;
        for (x, arm) in f.iter_mut().zip(arms).filter(|(x, _)| **x > 0.0) {
            let factor = a.dot(&phi(*arm));
            if factor > 0.0 {
                *x *= factor;
            } else {
                *x = 0.0;
                dropped = true;
            }
        }
        if !dropped {
            return true;
        }
    }
    balance_residual(f, arms) < 1e-12
}

/// The free-slider constrained CG (module doc).
#[derive(Debug, Clone, Default)]
pub struct BalancedCg {
    options: CgOptions,
}

impl BalancedCg {
    /// A solver with these options.
    pub fn new(options: CgOptions) -> Self {
        Self { options }
    }

    /// Solves the contact of `op`'s posts on obstacle heights `height_m` (m) under `preload_n`
    /// applied at the point about which `arms` (dimensionless, O(1)) are the posts' moment arms;
    /// gaps are scaled by `length_scale_m` (m).
    pub fn solve(
        &self,
        op: &dyn ComplianceOperator,
        height_m: &[f64],
        preload_n: f64,
        length_scale_m: f64,
        arms: &[(f64, f64)],
    ) -> Result<CgSolution> {
        self.solve_preconditioned(op, None, height_m, preload_n, length_scale_m, arms, None)
    }

    /// As [`BalancedCg::solve`], with the conjugate directions preconditioned on the contact set
    /// by `preconditioner` (z = P M_A⁻¹ g, P the projection off the three rigid modes; a
    /// symmetric positive definite M keeps it a conjugate-gradient method): same solution, fewer
    /// iterations when M_A approximates the operator's contact block ([`crate::precondition`]).
    /// `start_n`: forces (N) to start from instead of equal ones, e.g. the solution of nearby
    /// heights (rebalanced against the moments; ignored if it does not fit or cannot be
    /// balanced): the same solution to the tolerance, in fewer iterations.
    #[allow(clippy::too_many_arguments)]
    pub fn solve_preconditioned(
        &self,
        op: &dyn ComplianceOperator,
        mut preconditioner: Option<&mut dyn ContactPreconditioner>,
        height_m: &[f64],
        preload_n: f64,
        length_scale_m: f64,
        arms: &[(f64, f64)],
        start_n: Option<&[f64]>,
    ) -> Result<CgSolution> {
        let n = op.len();
        check_inputs(n, height_m, preload_n, length_scale_m, arms)?;
        let f0 = preload_n / n as f64;
        let s = f0 / length_scale_m;
        let h: Vec<f64> = height_m.iter().map(|x| x / length_scale_m).collect();
        let warm = crate::solver::start_forces(n, start_n)
            .map(|mut f| rebalance(&mut f, arms).then_some(f))
            .and_then(|f| f);
        let mut f = match warm {
            Some(f) => f,
            None => initial_forces(n, arms)?,
        };
        let (mut t, mut u, mut r, mut g) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let mut z = vec![0.0; n];
        let (mut delta, mut g_old) = (0.0, 1.0);
        let mut previous_contact: Vec<bool> = Vec::new();
        let mut history = Vec::new();
        // Iterations since u was last computed from f (None: stale, recompute now).
        let mut updated_for: Option<usize> = None;
        for iteration in 0..=self.options.max_iterations {
            if updated_for.is_none() {
                op.apply(&f, &mut u);
                updated_for = Some(0);
            }
            let contact: Vec<bool> = f.iter().map(|&x| x > 0.0).collect();
            // A preconditioner that changes with the contact set breaks the conjugacy of the
            // old direction: restart (steepest descent in the new metric) when the set changed.
            if preconditioner.is_some() && contact != previous_contact {
                delta = 0.0;
            }
            let c = gaps(s, &u, &h, &contact, arms, &mut g);
            let mut residual = complementarity(&f, &g, arms);
            if residual <= self.options.tolerance && updated_for != Some(0) {
                // Converged on the updated u: confirm on u recomputed from f.
                op.apply(&f, &mut u);
                updated_for = Some(0);
                // The confirmed gaps; the reported rigid position stays the one fitted above.
                gaps(s, &u, &h, &contact, arms, &mut g);
                residual = complementarity(&f, &g, arms);
            }
            history.push(residual);
            if residual <= self.options.tolerance {
                let scales = (f0, length_scale_m);
                return Ok(solution(&f, &g, c, scales, residual, iteration, history));
            }
            if iteration == self.options.max_iterations {
                break;
            }
            let (gt, rt) = Direction {
                op,
                contact: &contact,
                g: &g,
                s,
                arms,
            }
            .search(
                preconditioner.as_deref_mut(),
                (&mut delta, &mut g_old),
                &mut z,
                &mut t,
                &mut r,
            );
            let tau = if rt > 0.0 { gt / rt } else { 0.0 };
            let set_changed = step_forces(&mut f, &t, &g, &contact, tau);
            previous_contact = contact;
            updated_for = advance_u(updated_for, set_changed, tau, &r, &mut u);
            if updated_for.is_none() && !rebalance(&mut f, arms) {
                restart_forces(&mut f, arms);
                delta = 0.0;
            }
        }
        Err(not_converged(&self.options, &history, &f))
    }
}

/// u ← u − τ C t (r = C t) while the contact set is unchanged, for at most
/// [`MAX_UPDATED_U`] iterations; `None`: recompute u from f.
fn advance_u(
    updated_for: Option<usize>,
    set_changed: bool,
    tau: f64,
    r: &[f64],
    u: &mut [f64],
) -> Option<usize> {
    match updated_for {
        Some(k) if !set_changed && k < MAX_UPDATED_U => {
            u.iter_mut().zip(r).for_each(|(ui, ri)| *ui -= tau * ri);
            Some(k + 1)
        }
        _ => None,
    }
}

/// Equal forces balanced against the preload's moments; refused (naming `load.point`) when the
/// posts cannot balance them.
fn initial_forces(n: usize, arms: &[(f64, f64)]) -> Result<Vec<f64>> {
    let mut f = vec![1.0; n];
    if !rebalance(&mut f, arms) {
        return Err(invalid(
            "load.point",
            f64::NAN,
            "the posts cannot balance the preload's moments (load point outside the post array)",
        ));
    }
    Ok(f)
}

/// Forces that cannot be rebalanced start again from equal forces, balanced.
fn restart_forces(f: &mut [f64], arms: &[(f64, f64)]) {
    f.iter_mut().for_each(|x| *x = 1.0);
    rebalance(f, arms);
}

/// The conjugate search direction of one iteration on the contact set.
struct Direction<'a> {
    op: &'a dyn ComplianceOperator,
    contact: &'a [bool],
    g: &'a [f64],
    s: f64,
    arms: &'a [(f64, f64)],
}

impl Direction<'_> {
    /// t = P(z + δ (g·z / g_old) t) with z = P M⁻¹ g (or g), r = C t; a direction that does not
    /// descend restarts as steepest descent (δ = 0), else δ becomes 1. Returns (g·t, t·s·C·t).
    fn search(
        &self,
        preconditioner: Option<&mut (dyn ContactPreconditioner + '_)>,
        (delta, g_old): (&mut f64, &mut f64),
        z: &mut [f64],
        t: &mut [f64],
        r: &mut [f64],
    ) -> (f64, f64) {
        let (contact, g, s, arms) = (self.contact, self.g, self.s, self.arms);
        let n = g.len();
        // z = P M⁻¹ g in the CG's scaled units (operator s·C): z̃ = M⁻¹(g̃)/s.
        match preconditioner {
            Some(pre) => precondition(pre, contact, g, s, arms, z),
            None => z.copy_from_slice(g),
        }
        let g_norm: f64 = (0..n).filter(|&i| contact[i]).map(|i| g[i] * z[i]).sum();
        for i in 0..n {
            t[i] = if contact[i] {
                z[i] + *delta * (g_norm / *g_old) * t[i]
            } else {
                0.0
            };
        }
        remove_modes(t, contact, arms);
        *g_old = g_norm;
        self.op.apply(t, r);
        let (mut gt, mut rt) = descent(g, t, r, s, contact);
        if gt <= 0.0 && *delta != 0.0 {
            // Not a descent direction (the kept conjugacy failed): steepest descent.
            *delta = 0.0;
            for i in 0..n {
                t[i] = if contact[i] { z[i] } else { 0.0 };
            }
            remove_modes(t, contact, arms);
            self.op.apply(t, r);
            (gt, rt) = descent(g, t, r, s, contact);
        } else {
            *delta = 1.0;
        }
        (gt, rt)
    }
}

/// One height and moment arm per post, a positive finite preload and length scale, finite
/// heights.
fn check_inputs(
    n: usize,
    height_m: &[f64],
    preload_n: f64,
    length_scale_m: f64,
    arms: &[(f64, f64)],
) -> Result<()> {
    if arms.len() != n || height_m.len() != n || n == 0 {
        return Err(invalid(
            "obstacle_height_m",
            height_m.len() as f64,
            format!("one height and moment arm per post ({n} posts)"),
        ));
    }
    if !(preload_n > 0.0 && preload_n.is_finite() && length_scale_m > 0.0) {
        return Err(invalid(
            "preload_n",
            preload_n,
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

/// The scaled gaps g = s·u − h with the rigid modes fitted on the contact set taken out of
/// every post; returns the modes' coefficients c (reference height and rotations).
fn gaps(
    s: f64,
    u: &[f64],
    h: &[f64],
    contact: &[bool],
    arms: &[(f64, f64)],
    g: &mut [f64],
) -> Vector3<f64> {
    for i in 0..g.len() {
        g[i] = s * u[i] - h[i];
    }
    let c = fit_modes(g, contact, arms);
    for (gi, a) in g.iter_mut().zip(arms) {
        *gi -= c.dot(&phi(*a));
    }
    c
}

/// `v` on the contact set with the rigid modes fitted there taken out (the projection P).
fn remove_modes(v: &mut [f64], contact: &[bool], arms: &[(f64, f64)]) {
    let cv = fit_modes(v, contact, arms);
    for i in (0..v.len()).filter(|&i| contact[i]) {
        v[i] -= cv.dot(&phi(arms[i]));
    }
}

/// z = P M⁻¹ g, in the CG's scaled units (divided by s).
fn precondition(
    pre: &mut dyn ContactPreconditioner,
    contact: &[bool],
    g: &[f64],
    s: f64,
    arms: &[(f64, f64)],
    z: &mut [f64],
) {
    pre.apply(contact, g, z);
    z.iter_mut().for_each(|x| *x /= s);
    remove_modes(z, contact, arms);
}

/// (g·t, t·s·C·t) on the contact set, with r = C t.
fn descent(g: &[f64], t: &[f64], r: &[f64], s: f64, contact: &[bool]) -> (f64, f64) {
    let (mut gt, mut rt) = (0.0, 0.0);
    for i in (0..g.len()).filter(|&i| contact[i]) {
        gt += g[i] * t[i];
        rt += s * r[i] * t[i];
    }
    (gt, rt)
}

/// The converged solution in SI: forces (scaled by `f0`), gaps, rigid-body position and
/// rotations (scaled by the length scale).
fn solution(
    f: &[f64],
    g: &[f64],
    c: Vector3<f64>,
    (f0, length_scale_m): (f64, f64),
    residual: f64,
    iterations: usize,
    residual_history: Vec<f64>,
) -> CgSolution {
    CgSolution {
        force_n: f.iter().map(|x| x * f0).collect(),
        gap_m: g.iter().map(|x| x.max(0.0) * length_scale_m).collect(),
        reference_height_m: -c[0] * length_scale_m,
        complementarity_residual: residual,
        iterations,
        residual_history,
        rotation_m: [-c[1] * length_scale_m, -c[2] * length_scale_m],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// Rigid punch on independent springs k with a point load at (x_P, y_P): in full contact the
    /// forces are linear in (x, y), f_i = k (z + θ_x ξ_i + θ_y η_i + h_i), with the three
    /// balance equations fixing z, θ.
    #[test]
    fn an_off_centre_point_load_on_springs_gives_the_linear_rigid_punch_distribution() {
        let (nx, ny) = (9, 7);
        let k = 2e6;
        let c = DMatrix::identity(nx * ny, nx * ny) / k;
        // Off-centre but within the core of the array: every post stays in contact.
        let (xp, yp) = (0.6, -0.3);
        let arms: Vec<(f64, f64)> = (0..nx)
            .flat_map(|i| (0..ny).map(move |j| (i as f64 - 4.0 - xp, j as f64 - 3.0 - yp)))
            .collect();
        let h = vec![0.0; nx * ny];
        let p = 0.5;
        let sol = BalancedCg::default().solve(&c, &h, p, 1e-9, &arms).unwrap();
        // Exact: f = a + b ξ + c η with Σf = P, Σ f ξ = 0, Σ f η = 0.
        let mut m = Matrix3::zeros();
        for a in &arms {
            m += phi(*a) * phi(*a).transpose();
        }
        let coef = m.cholesky().unwrap().solve(&Vector3::new(p, 0.0, 0.0));
        for (i, a) in arms.iter().enumerate() {
            let exact = coef.dot(&phi(*a));
            assert!(exact > 0.0, "full contact expected");
            assert!(
                (sol.force_n[i] - exact).abs() < 1e-8 * p / 63.0,
                "post force {i}: CG {} vs rigid punch {exact}",
                sol.force_n[i]
            );
        }
    }

    #[test]
    fn a_load_near_the_edge_lifts_the_far_posts_and_still_balances() {
        let n = 40;
        let k = 1e6;
        let c = DMatrix::from_fn(n * n, n * n, |p, q| {
            let (xp, yp, xq, yq) = (p / n, p % n, q / n, q % n);
            let r = ((xp as f64 - xq as f64).powi(2) + (yp as f64 - yq as f64).powi(2)).sqrt();
            if p == q { 1.0 / k } else { 0.2 / k / r }
        });
        let (xp, yp) = (4.0, 30.0);
        let arms: Vec<(f64, f64)> = (0..n * n)
            .map(|p| (((p / n) as f64 - xp) / 20.0, ((p % n) as f64 - yp) / 20.0))
            .collect();
        let h: Vec<f64> = (0..n * n)
            .map(|p| 1e-8 * ((p / n) as f64 * 0.9).sin())
            .collect();
        let sol = BalancedCg::default()
            .solve(&c, &h, 1.0, 1e-8, &arms)
            .unwrap();
        let f = &sol.force_n;
        let (mut fx, mut fy) = (0.0, 0.0);
        for (fi, a) in f.iter().zip(&arms) {
            fx += fi * a.0;
            fy += fi * a.1;
        }
        assert!(
            fx.abs() < 1e-8 && fy.abs() < 1e-8,
            "moments of the post forces about the load point: {fx}, {fy}"
        );
        assert!(
            (f.iter().sum::<f64>() - 1.0).abs() < 1e-8,
            "total post force"
        );
        assert!(f.contains(&0.0), "far posts lifted off");
        for (i, (fi, gap)) in f.iter().zip(&sol.gap_m).enumerate() {
            assert!(
                *fi >= 0.0 && *gap >= -1e-17 && (fi * gap).abs() < 1e-8 * 1e-8,
                "complementarity at post {i}: f {fi} gap {gap}"
            );
        }
    }
}
