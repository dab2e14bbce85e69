//! Frictionless unilateral contact of N rigid-tipped posts under load control, condensed onto the
//! posts: a dense linear complementarity problem.
//!
//! With post forces f ≥ 0 (N, pushing the slider up), the slider's rigid reference height z_s (m)
//! and the dense compliance C (m/N, slider + stator, symmetric positive definite), the gap of post
//! i is g_i = z_s − h_i + (C f)_i, where h_i is the obstacle height (stator surface minus the
//! post's initial gap). The problem: g ≥ 0, f ≥ 0, f_i g_i = 0, Σ f_i = P. It is the KKT system of
//! the convex QP min ½ fᵀCf − hᵀf subject to f ≥ 0, Σf = P (z_s is the multiplier of the load).
//!
//! Solver: the primal–dual active-set method (Hintermüller, Ito & Kunisch, SIAM J. Optim. 13
//! (2003) 865; deal.II step-41): on the active set A solve C_AA f_A + z_s 1 = h_A, Σ f_A = P; then
//! A ← {i : f_i − c g_i > 0}; stop when A no longer changes. It converges in few iterations but
//! is not guaranteed to for a dense C that is not an M-matrix; if it revisits a set, it hands over
//! to a primal active-set method (Lawson & Hanson, *Solving Least Squares Problems*, 1974, ch. 23,
//! with the load constraint), which decreases the energy monotonically and terminates finitely.
//! Every iteration is logged (active-set size, residual).
//!
//! All arithmetic is in scaled units: forces by P, lengths by `length_scale_m`.

use std::collections::HashSet;

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::error::{ContactError, Result};

/// Largest accepted scaled complementarity residual (see [`ContactSolution::complementarity_residual`]).
/// Dimensionless; default 1e-9.
pub const DEFAULT_COMPLEMENTARITY_TOLERANCE: f64 = 1e-9;
/// Iteration limit of the primal–dual phase before handing over to the primal method. Default 50.
pub const DEFAULT_MAX_PRIMAL_DUAL_ITERATIONS: usize = 50;
/// Iteration limit of the whole solve (both phases). Default 2000.
pub const DEFAULT_MAX_ITERATIONS: usize = 2000;
/// The primal–dual update weight c in f_i − c g_i (scaled units). Dimensionless; default 1.
pub const DEFAULT_PRIMAL_DUAL_WEIGHT: f64 = 1.0;

/// A dense contact problem: posts with compliance, obstacle heights and a total load.
#[derive(Debug, Clone)]
pub struct ContactProblem {
    /// Compliance C (m/N), symmetric positive definite, n × n.
    pub compliance_m_per_n: DMatrix<f64>,
    /// Obstacle height h_i (m): stator surface under post i minus its initial gap.
    pub obstacle_height_m: Vec<f64>,
    /// Total load P (N) > 0.
    pub preload_n: f64,
    /// Length used to scale gaps (m), e.g. the wave amplitude; `None`: P × max C_ii.
    pub length_scale_m: Option<f64>,
}

/// Options of [`ActiveSetSolver`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ActiveSetOptions {
    /// See [`DEFAULT_COMPLEMENTARITY_TOLERANCE`].
    pub tolerance: f64,
    /// See [`DEFAULT_MAX_PRIMAL_DUAL_ITERATIONS`].
    pub max_primal_dual_iterations: usize,
    /// See [`DEFAULT_MAX_ITERATIONS`].
    pub max_iterations: usize,
    /// See [`DEFAULT_PRIMAL_DUAL_WEIGHT`].
    pub primal_dual_weight: f64,
}

impl Default for ActiveSetOptions {
    fn default() -> Self {
        Self {
            tolerance: DEFAULT_COMPLEMENTARITY_TOLERANCE,
            max_primal_dual_iterations: DEFAULT_MAX_PRIMAL_DUAL_ITERATIONS,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            primal_dual_weight: DEFAULT_PRIMAL_DUAL_WEIGHT,
        }
    }
}

/// Which method produced an iterate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// Primal–dual active set (semi-smooth Newton).
    PrimalDual,
    /// Primal active set (Lawson–Hanson type), monotone fallback.
    Primal,
}

/// One logged iteration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct IterationLog {
    /// Iteration number (1-based).
    pub iteration: usize,
    /// Method of this iteration.
    pub phase: Phase,
    /// Posts in the active (contact) set.
    pub active: usize,
    /// Scaled complementarity residual of the iterate (see [`ContactSolution`]).
    pub residual: f64,
}

/// The solution of a [`ContactProblem`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactSolution {
    /// Post forces f_i ≥ 0 (N).
    pub force_n: Vec<f64>,
    /// Gaps g_i ≥ 0 (m).
    pub gap_m: Vec<f64>,
    /// Whether post i is in the final active set.
    pub in_contact: Vec<bool>,
    /// Slider reference height z_s (m): rigid position of the post tips' reference plane.
    pub reference_height_m: f64,
    /// max_i |min(f_i/P, g_i/L)| together with |Σf/P − 1|: zero exactly at a solution
    /// (the natural residual of the complementarity problem, scaled).
    pub complementarity_residual: f64,
    /// Iterations done.
    pub iterations: usize,
    /// Per-iteration log.
    pub log: Vec<IterationLog>,
}

/// Primal–dual active-set solver with a primal fallback.
#[derive(Debug, Clone, Default)]
pub struct ActiveSetSolver {
    options: ActiveSetOptions,
}

/// Scaled data of one solve.
struct Scaled {
    c: DMatrix<f64>,
    h: DVector<f64>,
    length_m: f64,
}

impl ActiveSetSolver {
    /// A solver with the given options.
    pub fn new(options: ActiveSetOptions) -> Self {
        Self { options }
    }

    /// Its options.
    pub fn options(&self) -> &ActiveSetOptions {
        &self.options
    }

    fn validate(problem: &ContactProblem) -> Result<()> {
        let n = problem.obstacle_height_m.len();
        if n == 0 {
            return Err(ContactError::InvalidParameter {
                parameter: "posts",
                value: 0.0,
                reason: "no posts".into(),
            });
        }
        if problem.compliance_m_per_n.nrows() != n || problem.compliance_m_per_n.ncols() != n {
            return Err(ContactError::InvalidParameter {
                parameter: "compliance_m_per_n",
                value: problem.compliance_m_per_n.nrows() as f64,
                reason: format!(
                    "compliance is {}×{}, there are {n} posts",
                    problem.compliance_m_per_n.nrows(),
                    problem.compliance_m_per_n.ncols()
                ),
            });
        }
        if !(problem.preload_n > 0.0 && problem.preload_n.is_finite()) {
            return Err(ContactError::InvalidParameter {
                parameter: "preload_n",
                value: problem.preload_n,
                reason: "must be positive and finite".into(),
            });
        }
        if let Some(i) = problem
            .obstacle_height_m
            .iter()
            .position(|h| !h.is_finite())
        {
            return Err(ContactError::InvalidParameter {
                parameter: "obstacle_height_m",
                value: problem.obstacle_height_m[i],
                reason: format!("not finite at post {i}"),
            });
        }
        if let Some(i) = (0..n).find(|&i| {
            problem.compliance_m_per_n[(i, i)].is_nan() || problem.compliance_m_per_n[(i, i)] <= 0.0
        }) {
            return Err(ContactError::CompliancePositivity {
                post: i,
                pivot: problem.compliance_m_per_n[(i, i)],
                what: "diagonal of the contact compliance".into(),
            });
        }
        Ok(())
    }

    fn scale(problem: &ContactProblem) -> Scaled {
        let p = problem.preload_n;
        let n = problem.obstacle_height_m.len();
        let max_diag = (0..n)
            .map(|i| problem.compliance_m_per_n[(i, i)])
            .fold(0.0, f64::max);
        let length_m = problem
            .length_scale_m
            .filter(|l| *l > 0.0 && l.is_finite())
            .unwrap_or(p * max_diag);
        Scaled {
            c: &problem.compliance_m_per_n * (p / length_m),
            h: DVector::from_iterator(n, problem.obstacle_height_m.iter().map(|h| h / length_m)),
            length_m,
        }
    }

    /// Solves the problem; [`ContactError::NotConverged`] if the iteration limit is reached.
    pub fn solve(&self, problem: &ContactProblem) -> Result<ContactSolution> {
        self.solve_from(problem, None)
    }

    /// [`Self::solve`] whose primal–dual phase starts from the contact set `start` (e.g. the
    /// solution of a nearby problem: a sequence of problems whose obstacles change a little
    /// then needs one or two equality solves each). The solution is the same (the problem's is
    /// unique for a positive definite compliance); only the path to it changes. `None`, a set
    /// of the wrong length or an empty set: the cold start of [`Self::solve`].
    pub fn solve_from(
        &self,
        problem: &ContactProblem,
        start: Option<&[bool]>,
    ) -> Result<ContactSolution> {
        Self::validate(problem)?;
        let s = Self::scale(problem);
        let n = s.h.len();
        let mut log = Vec::new();
        // Cold start: the post on the highest obstacle carries everything.
        let top = (0..n)
            .max_by(|&a, &b| s.h[a].total_cmp(&s.h[b]))
            .unwrap_or(0);
        let active = match start {
            Some(set) if set.len() == n && set.iter().any(|&a| a) => set.to_vec(),
            _ => {
                let mut cold = vec![false; n];
                cold[top] = true;
                cold
            }
        };
        let mut iteration = 0;
        if let Some(solution) = self.primal_dual(problem, &s, active, &mut iteration, &mut log)? {
            return Ok(solution);
        }
        self.primal(problem, &s, top, iteration, log)
    }

    /// Phase 1: primal–dual active set from `active`; `None` when it stalls or cycles (the
    /// monotone primal method takes over).
    fn primal_dual(
        &self,
        problem: &ContactProblem,
        s: &Scaled,
        mut active: Vec<bool>,
        iteration: &mut usize,
        log: &mut Vec<IterationLog>,
    ) -> Result<Option<ContactSolution>> {
        let n = s.h.len();
        let mut seen: HashSet<Vec<bool>> = HashSet::new();
        while *iteration
            < self
                .options
                .max_primal_dual_iterations
                .min(self.options.max_iterations)
        {
            *iteration += 1;
            seen.insert(active.clone());
            let (f, z) = equality_solve(s, &active)?;
            let g = gaps(s, &f, z);
            let residual = natural_residual(&f, &g);
            log.push(IterationLog {
                iteration: *iteration,
                phase: Phase::PrimalDual,
                active: count(&active),
                residual,
            });
            let next: Vec<bool> = (0..n)
                .map(|i| f[i] - self.options.primal_dual_weight * g[i] > 0.0)
                .collect();
            if next == active && residual <= self.options.tolerance {
                let log = std::mem::take(log);
                return Ok(Some(finish(problem, s, f, g, z, active, *iteration, log)));
            }
            if next == active || seen.contains(&next) || !next.iter().any(|&a| a) {
                break; // stalled or cycling: hand over to the monotone primal method
            }
            active = next;
        }
        Ok(None)
    }

    /// Phase 2: primal active set from a feasible point (all load on the highest post `top`).
    fn primal(
        &self,
        problem: &ContactProblem,
        s: &Scaled,
        top: usize,
        mut iteration: usize,
        mut log: Vec<IterationLog>,
    ) -> Result<ContactSolution> {
        let n = s.h.len();
        let mut f = DVector::zeros(n);
        f[top] = 1.0;
        let mut working = vec![false; n];
        working[top] = true;
        loop {
            if iteration >= self.options.max_iterations {
                let (fz, z) = equality_solve(s, &working)?;
                let residual = natural_residual(&fz, &gaps(s, &fz, z));
                return Err(self.not_converged(iteration, &working, residual, String::new()));
            }
            iteration += 1;
            let (candidate, z) = equality_solve(s, &working)?;
            let negative: Vec<usize> = (0..n)
                .filter(|&i| working[i] && candidate[i] <= 0.0)
                .collect();
            if !negative.is_empty() {
                step_back(&mut f, &candidate, &negative, &mut working, top);
                let g = gaps(s, &f, z);
                log.push(IterationLog {
                    iteration,
                    phase: Phase::Primal,
                    active: count(&working),
                    residual: natural_residual(&f, &g),
                });
                continue;
            }
            f = candidate;
            let g = gaps(s, &f, z);
            let residual = natural_residual(&f, &g);
            log.push(IterationLog {
                iteration,
                phase: Phase::Primal,
                active: count(&working),
                residual,
            });
            // Most violated constraint outside the working set.
            let entering = (0..n)
                .filter(|&i| !working[i])
                .min_by(|&a, &b| g[a].total_cmp(&g[b]));
            match entering {
                Some(i) if g[i] < -self.options.tolerance => working[i] = true,
                _ if residual <= self.options.tolerance => {
                    return Ok(finish(problem, s, f, g, z, working, iteration, log));
                }
                _ => {
                    return Err(self.not_converged(
                        iteration,
                        &working,
                        residual,
                        " (primal active set stalled: ill-conditioned compliance?)".into(),
                    ));
                }
            }
        }
    }

    /// The solver's not-converged error at `iteration` with the set `working`.
    fn not_converged(
        &self,
        iteration: usize,
        working: &[bool],
        residual: f64,
        context: String,
    ) -> ContactError {
        ContactError::NotConverged {
            iterations: iteration,
            active: count(working),
            posts: working.len(),
            residual,
            tolerance: self.options.tolerance,
            context,
        }
    }
}

/// A primal step that would make forces of the working set negative: step from `f` towards
/// `candidate` until the first force reaches zero and drop it (all dropped: back to the load on
/// the highest post `top`).
fn step_back(
    f: &mut DVector<f64>,
    candidate: &DVector<f64>,
    negative: &[usize],
    working: &mut [bool],
    top: usize,
) {
    let n = f.len();
    let alpha = negative
        .iter()
        .map(|&i| f[i] / (f[i] - candidate[i]))
        .fold(1.0, f64::min)
        .max(0.0);
    *f = &*f + (candidate - &*f) * alpha;
    for i in 0..n {
        if working[i] && (f[i] <= 0.0 || (negative.contains(&i) && f[i] <= f64::EPSILON)) {
            working[i] = false;
            f[i] = 0.0;
        }
    }
    if !working.iter().any(|&w| w) {
        working[top] = true;
        *f = DVector::zeros(n);
        f[top] = 1.0;
    }
}

fn count(set: &[bool]) -> usize {
    set.iter().filter(|&&a| a).count()
}

/// Solves C_AA f_A + z 1 = h_A, Σ f_A = 1 (scaled); f = 0 off A. Returns (f, z).
fn equality_solve(s: &Scaled, active: &[bool]) -> Result<(DVector<f64>, f64)> {
    let idx: Vec<usize> = (0..active.len()).filter(|&i| active[i]).collect();
    let m = idx.len();
    let c_aa = DMatrix::from_fn(m, m, |r, c| s.c[(idx[r], idx[c])]);
    let chol = c_aa
        .cholesky()
        .ok_or_else(|| ContactError::CompliancePositivity {
            post: idx[0],
            pivot: f64::NAN,
            what: format!(
                "the compliance restricted to the {m} active posts has no Cholesky factor"
            ),
        })?;
    let h_a = DVector::from_iterator(m, idx.iter().map(|&i| s.h[i]));
    let ones = DVector::from_element(m, 1.0);
    let c_inv_h = chol.solve(&h_a);
    let c_inv_1 = chol.solve(&ones);
    let z = (c_inv_h.sum() - 1.0) / c_inv_1.sum();
    let f_a = c_inv_h - c_inv_1 * z;
    let mut f = DVector::zeros(active.len());
    for (k, &i) in idx.iter().enumerate() {
        f[i] = f_a[k];
    }
    Ok((f, z))
}

/// Scaled gaps g = z − h + C f.
fn gaps(s: &Scaled, f: &DVector<f64>, z: f64) -> DVector<f64> {
    let mut g = &s.c * f - &s.h;
    g.add_scalar_mut(z);
    g
}

/// max_i |min(f_i, g_i)| and |Σf − 1| (scaled).
fn natural_residual(f: &DVector<f64>, g: &DVector<f64>) -> f64 {
    let r = f
        .iter()
        .zip(g.iter())
        .map(|(a, b)| a.min(*b).abs())
        .fold(0.0, f64::max);
    r.max((f.sum() - 1.0).abs())
}

#[allow(clippy::too_many_arguments)]
fn finish(
    problem: &ContactProblem,
    s: &Scaled,
    f: DVector<f64>,
    g: DVector<f64>,
    z: f64,
    active: Vec<bool>,
    iterations: usize,
    log: Vec<IterationLog>,
) -> ContactSolution {
    let p = problem.preload_n;
    let residual = natural_residual(&f, &g);
    ContactSolution {
        // Clip round-off: an active post's force is ≥ 0 by construction up to the tolerance.
        force_n: f.iter().map(|v| v.max(0.0) * p).collect(),
        gap_m: g.iter().map(|v| v.max(0.0) * s.length_m).collect(),
        in_contact: active,
        reference_height_m: z * s.length_m,
        complementarity_residual: residual,
        iterations,
        log,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problem(c: DMatrix<f64>, h: Vec<f64>, p: f64) -> ContactProblem {
        ContactProblem {
            compliance_m_per_n: c,
            obstacle_height_m: h,
            preload_n: p,
            length_scale_m: None,
        }
    }

    #[test]
    fn independent_springs_on_equal_heights_share_the_load_equally() {
        let c = DMatrix::identity(5, 5) * 1e-6;
        let sol = ActiveSetSolver::default()
            .solve(&problem(c, vec![0.0; 5], 10.0))
            .unwrap();
        for (i, f) in sol.force_n.iter().enumerate() {
            assert!(
                (f - 2.0).abs() < 1e-12,
                "force on post {i}: {f} N, expected 2 N"
            );
        }
        assert!(
            (sol.reference_height_m + 2e-6).abs() < 1e-18,
            "approach z_s = −P/(n k): {}",
            sol.reference_height_m
        );
    }

    #[test]
    fn independent_springs_match_the_water_filling_solution() {
        // k = 1e6 N/m, heights 0, 1, 2, 3 µm, P = 3 N: posts with h > z_s carry k (h − z_s).
        let c = DMatrix::identity(4, 4) * 1e-6;
        let h = vec![0.0, 1e-6, 2e-6, 3e-6];
        let sol = ActiveSetSolver::default()
            .solve(&problem(c, h, 3.0))
            .unwrap();
        // Top two: 2·(2.5 − z) = 3 µm... solve: (3 − z) + (2 − z) = 3 → z = 1 µm: post 1 at h = z.
        let expected = [0.0, 0.0, 1.0, 2.0];
        for (i, expected) in expected.iter().enumerate() {
            assert!(
                (sol.force_n[i] - expected).abs() < 1e-9,
                "force on post {i}: {} N vs {expected} N",
                sol.force_n[i]
            );
            assert!(sol.gap_m[i] >= 0.0, "gap of post {i} must be ≥ 0");
        }
        assert!(
            sol.complementarity_residual < 1e-9,
            "residual {}",
            sol.complementarity_residual
        );
    }

    #[test]
    fn coupled_posts_satisfy_complementarity_and_forces_are_positive_only_on_the_active_set() {
        // A dense SPD compliance with strong positive coupling, random-ish heights.
        let n = 30;
        let c = DMatrix::from_fn(n, n, |i, j| {
            1e-6 * (-((i as f64 - j as f64).abs()) / 4.0).exp()
        });
        let h: Vec<f64> = (0..n)
            .map(|i| 1e-7 * ((i as f64 * 0.7).sin() + 0.3 * (i as f64 * 2.3).cos()))
            .collect();
        let sol = ActiveSetSolver::default()
            .solve(&ContactProblem {
                compliance_m_per_n: c.clone(),
                obstacle_height_m: h.clone(),
                preload_n: 0.05,
                length_scale_m: Some(1e-7),
            })
            .unwrap();
        let f = DVector::from_vec(sol.force_n.clone());
        let cf = &c * &f;
        for i in 0..n {
            let gap = sol.reference_height_m - h[i] + cf[i];
            assert!(gap > -1e-7 * 1e-8, "gap of post {i} is negative: {gap} m");
            if sol.in_contact[i] {
                assert!(
                    sol.force_n[i] >= 0.0 && gap.abs() < 1e-15,
                    "active post {i}: force {} N, gap {gap} m",
                    sol.force_n[i]
                );
            } else {
                assert_eq!(sol.force_n[i], 0.0, "inactive post {i} carries force");
            }
        }
        assert!(
            (sol.force_n.iter().sum::<f64>() - 0.05).abs() < 1e-12,
            "total force equals the preload"
        );
        assert!(
            sol.log.iter().all(|l| l.active >= 1),
            "every logged iterate has an active set"
        );
    }

    #[test]
    fn a_periodic_array_on_a_flat_stator_loads_every_post_equally() {
        // Circulant compliance (posts on a ring, coupling decaying with ring distance): every
        // post sees the same neighbourhood, so a uniform preload must load all posts equally.
        let n = 24;
        let c = DMatrix::from_fn(n, n, |i, j| {
            let d = (i as i64 - j as i64)
                .rem_euclid(n as i64)
                .min((j as i64 - i as i64).rem_euclid(n as i64)) as f64;
            1e-6 / (1.0 + d)
        });
        let sol = ActiveSetSolver::default()
            .solve(&problem(c, vec![0.0; n], 2.4))
            .unwrap();
        for (i, f) in sol.force_n.iter().enumerate() {
            assert!(
                (f / 0.1 - 1.0).abs() < 1e-12,
                "force on post {i}: {f} N, expected P/N = 0.1 N"
            );
        }
    }

    #[test]
    fn an_iteration_limit_of_zero_reports_non_convergence() {
        let c = DMatrix::identity(3, 3) * 1e-6;
        let options = ActiveSetOptions {
            max_iterations: 0,
            max_primal_dual_iterations: 0,
            ..Default::default()
        };
        let err = ActiveSetSolver::new(options)
            .solve(&problem(c, vec![0.0, 1e-7, 2e-7], 1.0))
            .unwrap_err();
        assert!(
            matches!(err, ContactError::NotConverged { posts: 3, .. }),
            "non-convergence must be reported: {err}"
        );
        assert!(
            err.to_string().contains("did not converge"),
            "message names the failure: {err}"
        );
    }

    #[test]
    fn a_non_positive_compliance_is_refused() {
        let c = DMatrix::from_row_slice(2, 2, &[1e-6, 0.0, 0.0, -1e-6]);
        let err = ActiveSetSolver::default()
            .solve(&problem(c, vec![0.0, 0.0], 1.0))
            .unwrap_err();
        assert!(
            matches!(err, ContactError::CompliancePositivity { post: 1, .. }),
            "negative diagonal must be refused: {err}"
        );
    }
}
