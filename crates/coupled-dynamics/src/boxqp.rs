//! Box-constrained convex QP: min ½ xᵀA x − bᵀx subject to lo ≤ x ≤ hi, A symmetric positive
//! definite. Its KKT conditions are the incremental frictional (and, with lo = 0, hi = ∞, the
//! frictionless unilateral) contact problem: with λ = b − A x,
//! x_i = hi_i ⇒ λ_i ≥ 0, x_i = lo_i ⇒ λ_i ≤ 0, lo_i < x_i < hi_i ⇒ λ_i = 0.
//!
//! Method: primal–dual active set = semi-smooth Newton on x − clamp(x + λ, lo, hi) = 0
//! (Hintermüller, Ito & Kunisch, SIAM J. Optim. 13 (2003) 865), warm-started from the caller's
//! sets; it terminates at the exact solution once the sets repeat. Safeguard: if it has not
//! settled after [`MAX_ACTIVE_SET_ITERATIONS`], projected Gauss–Seidel from the best iterate,
//! which converges for any SPD A (Cryer, SIAM J. Control 9 (1971) 385; Luo & Tseng, JOTA 72
//! (1992) 7), to the natural residual tolerance, else a named error.
//!
//! Cost: a Newton step needs the Cholesky factor of the free block of A (m³/6 multiply-adds
//! for m free unknowns). Between the steps of a time integration the free set changes by a few
//! unknowns (posts entering or leaving stick), so [`ActiveSet`] keeps the last factor and
//! updates it: an unknown that leaves the free set is deleted from the factor by a rank-one
//! update of the trailing block (O((m−k)²), always stable: Golub & Van Loan, Matrix
//! Computations, 4th ed., §6.5.4), one that joins is appended as a new last row by a forward
//! solve (O(m²)); a fresh factorisation is made when more than m/[`UPDATE_SHARE`] unknowns
//! change, after [`MAX_FACTOR_UPDATES`] updates, or when an updated factor's Newton step misses
//! the tolerance (round-off of the updates). Products with A are plain column loops over the
//! nonzero entries of x (bound unknowns at zero bounds — separated posts — cost nothing).
//! Everything is sequential and deterministic: the same calls give the same bits.
//!
//! **Matrix-free variant** ([`solve_operator`], the whole slider's 10⁴ posts, whose A is only
//! available as a product, the lattice FFT convolution): the same primal–dual active set, each
//! Newton step's free block A_FF x_F = b_F − A_FB x_B solved by conjugate gradients on the free
//! unknowns (Hestenes & Stiefel 1952; A_FF is SPD as a principal block of an SPD A), started from
//! the caller's previous solution, to a tenth of the natural-residual tolerance (tightened
//! ×[`CG_TIGHTENING`] when the sets repeat but the residual misses). Inexact Newton (Dembo,
//! Eisenstat & Steihaug, SIAM J. Numer. Anal. 19 (1982) 400): while the sets still change, a
//! step's CG stops at [`INEXACT_CG_REDUCTION`] of its first residual, since its solution only
//! serves to predict the next sets; the step whose sets repeat goes to the tolerance. Only the
//! path changes, not the answer: the same KKT conditions to the same natural residual. The natural residual is
//! evaluated on a freshly applied A x, so the reported accuracy is that of the exact KKT
//! conditions. No factor: the cost is (Newton steps) × (CG iterations) products with A. A x
//! between Newton steps is the CG's running one (updated with each A p: no product of its own,
//! round-off ≈ 1e-15 of the force scale); a solution is accepted only on a fresh product.
//! Mixed precision: the inner products A p of an inexact step's CG are in the caller's
//! precision (`inexact`; [`Precision::Single`]: the lattice's f32 transforms, ≈ 1e-7 of
//! ‖A‖‖p‖), every CG's first product (its residual) and every product of a step that goes to
//! the tolerance are double, so the f32 error only perturbs a step whose solution predicts the
//! next sets, and each CG restarts from a double residual (iterative refinement). All-single
//! CGs were measured too: their drift in the running residual costs ≈ 35 % more products on
//! the paper's slider.

use nalgebra::{DMatrix, DVector};
use slider_contact::Precision;

/// Active-set iterations before the projected Gauss–Seidel fallback. Default 40.
pub const MAX_ACTIVE_SET_ITERATIONS: usize = 40;
/// Projected Gauss–Seidel sweeps at most. Default 20000.
pub const MAX_GAUSS_SEIDEL_SWEEPS: usize = 20000;
/// The kept factor is updated (not recomputed) while fewer than m/`UPDATE_SHARE` of its m
/// unknowns change: an update costs ≈ m² per unknown, a factorisation m³/6. Default 6.
pub const UPDATE_SHARE: usize = 6;
/// Updates of a kept factor before it is recomputed from A, bounding the round-off the updates
/// accumulate. Default 256.
pub const MAX_FACTOR_UPDATES: usize = 256;

/// CG iterations per Newton step at most, in units of √n + 50 (CG on an SPD block converges
/// in ≈ √κ log(1/ε) iterations; the lattice blocks have κ ≲ 10²). Default 40.
pub const CG_ITERATIONS_PER_SQRT_N: usize = 40;
/// Factor by which the CG tolerance is tightened when the active sets repeat but the natural
/// residual misses the tolerance (the inner solve was not accurate enough). Default 1e-2.
pub const CG_TIGHTENING: f64 = 1e-2;
/// Inexact Newton steps of the matrix-free solve: while the active sets are still changing,
/// each step's CG stops once its residual has fallen by this factor (a step whose sets are
/// about to change needs no more); once a step's sets repeat, CG goes to the tolerance.
/// Measured on the paper's slider: 1e-3 → 21.6 CG iterations per time step at stall, 1e-2 → 18.7,
/// 1e-1 → 16.7 (all to the tolerance: 37.2). Default 1e-1.
pub const INEXACT_CG_REDUCTION: f64 = 1e-1;
/// Newton steps of the matrix-free solve after which every CG goes to the tolerance (no
/// inexact steps), bounding what the inexact steps can cost. Default 8.
pub const MAX_INEXACT_STEPS: usize = 8;

/// Where each unknown sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bound {
    /// Strictly inside the box (stick for friction, contact for the normal problem).
    Free,
    /// At the lower bound.
    Lower,
    /// At the upper bound.
    Upper,
}

/// Warm start of a sequence of solves with the same matrix A: the sets of the last solve and
/// the Cholesky factor of A's block on its free unknowns.
#[derive(Debug, Clone)]
pub struct ActiveSet {
    /// Where each unknown sat at the end of the last solve (the next one's first guess).
    pub sets: Vec<Bound>,
    /// The factor of A on the last free set.
    factor: Factor,
}

impl ActiveSet {
    /// All `n` unknowns free, no factor yet.
    pub fn new(n: usize) -> Self {
        Self {
            sets: vec![Bound::Free; n],
            factor: Factor::default(),
        }
    }
}

/// Cholesky factor L Lᵀ of A on an ordered list of unknowns (`order`; not sorted once updated).
/// L is lower triangular, row-major with row stride n = A's size (row r at `l[r n..]`).
#[derive(Debug, Clone, Default)]
struct Factor {
    /// The unknowns of the factor, in factor order.
    order: Vec<usize>,
    /// Rows of L.
    l: Vec<f64>,
    /// A's size (row stride).
    n: usize,
    /// Updates since the last factorisation from A.
    updates: usize,
    /// Whether the factor must be recomputed before its next use.
    stale: bool,
}

/// A_ij of the symmetric `a` from its lower triangle (as a Cholesky factorisation reads it).
fn lower(a: &[f64], n: usize, i: usize, j: usize) -> f64 {
    if i >= j { a[j * n + i] } else { a[i * n + j] }
}

fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

impl Factor {
    /// Append unknown `p` as the last row: L₂₁ = L₁₁⁻¹ A₁ₚ, l_pp = √(A_pp − L₂₁·L₂₁). `false`
    /// if the block is not (numerically) positive definite.
    fn append(&mut self, a: &[f64], p: usize) -> bool {
        let (n, m) = (self.n, self.order.len());
        let (done, row) = self.l.split_at_mut(m * n);
        let row = &mut row[..=m];
        for c in 0..m {
            let lc = &done[c * n..c * n + c + 1];
            row[c] = (lower(a, n, p, self.order[c]) - dot(&row[..c], &lc[..c])) / lc[c];
        }
        let d = a[p * n + p] - dot(&row[..m], &row[..m]);
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        row[m] = d.sqrt();
        self.order.push(p);
        true
    }

    /// Delete the unknown at factor position `k`: drop row and column k, then the rank-one
    /// update L₃₃L₃₃ᵀ + v vᵀ of the trailing block with v its old column k (rotations).
    fn remove(&mut self, k: usize, v: &mut Vec<f64>) {
        let (n, m) = (self.n, self.order.len());
        v.clear();
        v.extend((k + 1..m).map(|r| self.l[r * n + k]));
        for r in k + 1..m {
            self.l.copy_within(r * n..r * n + k, (r - 1) * n);
            self.l
                .copy_within(r * n + k + 1..r * n + r + 1, (r - 1) * n + k);
        }
        self.order.remove(k);
        for j in k..m - 1 {
            let vj = v[j - k];
            if vj == 0.0 {
                continue;
            }
            let ljj = self.l[j * n + j];
            let r = ljj.hypot(vj);
            let (c, s) = (r / ljj, vj / ljj);
            self.l[j * n + j] = r;
            for i in j + 1..m - 1 {
                let lij = (self.l[i * n + j] + s * v[i - k]) / c;
                self.l[i * n + j] = lij;
                v[i - k] = c * v[i - k] - s * lij;
            }
        }
    }

    /// Factor A on `free` from scratch. `false` if that block is not positive definite.
    fn refactor(&mut self, a: &[f64], n: usize, free: &[usize]) -> bool {
        self.n = n;
        self.l.resize(n * n, 0.0);
        self.order.clear();
        self.updates = 0;
        self.stale = false;
        free.iter().all(|&p| self.append(a, p))
    }

    /// Make this the factor of A on `free` (sorted): updated from the kept one when few
    /// unknowns changed, else recomputed. `mark` is scratch of length n. `false` if the block is
    /// not positive definite.
    fn set_free(
        &mut self,
        a: &[f64],
        n: usize,
        free: &[usize],
        mark: &mut [bool],
        v: &mut Vec<f64>,
    ) -> bool {
        if self.stale || self.n != n || self.order.is_empty() {
            return self.refactor(a, n, free);
        }
        mark.fill(false);
        for &p in free {
            mark[p] = true;
        }
        let leaving: Vec<usize> = (0..self.order.len())
            .filter(|&k| !mark[self.order[k]])
            .collect();
        for &p in &self.order {
            mark[p] = false;
        }
        let joining: Vec<usize> = free.iter().copied().filter(|&p| mark[p]).collect();
        let changes = leaving.len() + joining.len();
        if changes == 0 {
            return true;
        }
        if changes * UPDATE_SHARE > free.len().max(self.order.len())
            || self.updates + changes > MAX_FACTOR_UPDATES
        {
            return self.refactor(a, n, free);
        }
        for &k in leaving.iter().rev() {
            self.remove(k, v);
        }
        self.updates += changes;
        joining.iter().all(|&p| self.append(a, p)) || self.refactor(a, n, free)
    }

    /// Solve L Lᵀ y = r in factor order, in place.
    fn solve(&self, r: &mut [f64]) {
        let (n, m) = (self.n, self.order.len());
        for i in 0..m {
            let row = &self.l[i * n..i * n + i + 1];
            r[i] = (r[i] - dot(&row[..i], &r[..i])) / row[i];
        }
        for i in (0..m).rev() {
            let row = &self.l[i * n..i * n + i + 1];
            r[i] /= row[i];
            let ri = r[i];
            for (rc, lc) in r[..i].iter_mut().zip(&row[..i]) {
                *rc -= lc * ri;
            }
        }
    }
}

/// y += A x over the unknowns `columns` where x is nonzero (column-major A, column by column).
/// Every yᵢ is summed in column order with separate multiply and add (no fused multiply-add),
/// so the bits are the same with and without the AVX path.
fn add_product(a: &[f64], x: &[f64], columns: impl Iterator<Item = usize>, y: &mut [f64]) {
    let n = x.len();
    #[cfg(target_arch = "x86_64")]
    let avx = std::arch::is_x86_feature_detected!("avx");
    for j in columns {
        let xj = x[j];
        if xj != 0.0 {
            let column = &a[j * n..(j + 1) * n];
            #[cfg(target_arch = "x86_64")]
            if avx {
                // SAFETY: the CPU has AVX (checked above).
                unsafe { add_column_avx(column, xj, y) };
                continue;
            }
            add_column(column, xj, y);
        }
    }
}

/// y += c x, element by element.
#[inline(always)]
fn add_column(c: &[f64], x: f64, y: &mut [f64]) {
    for (yi, ci) in y.iter_mut().zip(c) {
        *yi += ci * x;
    }
}

/// [`add_column`] compiled for AVX (four lanes instead of SSE2's two; the same operations).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn add_column_avx(c: &[f64], x: f64, y: &mut [f64]) {
    add_column(c, x, y);
}

/// Outcome of a solve.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxSolution {
    /// The minimiser.
    pub x: DVector<f64>,
    /// λ = b − A x (the slip increment for friction, the gap for normal contact).
    pub lambda: DVector<f64>,
    /// A x (for friction the tips' elastic deflection Ĉ_t T).
    pub ax: DVector<f64>,
    /// Natural residual max|x − clamp(x + λ, lo, hi)| relative to `scale`.
    pub residual: f64,
    /// Active-set iterations plus Gauss–Seidel sweeps.
    pub iterations: usize,
    /// Whether the fallback ran.
    pub fallback: bool,
}

fn natural_residual(x: &DVector<f64>, lambda: &DVector<f64>, lo: &[f64], hi: &[f64]) -> f64 {
    (0..x.len())
        .map(|i| (x[i] - (x[i] + lambda[i]).clamp(lo[i], hi[i])).abs())
        .fold(0.0, f64::max)
}

/// Solve with `active` as warm start (updated to the final sets; its factor must be of this
/// `a`: use one [`ActiveSet`] per matrix). `scale` makes the residual relative; `tolerance`
/// applies to it. `Err((iterations, residual))` if neither method reaches the tolerance.
pub fn solve(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    lo: &[f64],
    hi: &[f64],
    active: &mut ActiveSet,
    scale: f64,
    tolerance: f64,
) -> std::result::Result<BoxSolution, (usize, f64)> {
    let n = b.len();
    let data = a.as_slice();
    let scale = scale.max(1e-300);
    let mut x = DVector::zeros(n);
    let mut ax = DVector::zeros(n);
    let mut mark = vec![false; n];
    let mut scratch = Vec::with_capacity(n);
    let mut best: Option<(f64, DVector<f64>)> = None;
    let mut iteration = 0;
    while iteration < MAX_ACTIVE_SET_ITERATIONS {
        iteration += 1;
        let Some(updated) = newton_step(
            data,
            b,
            lo,
            hi,
            active,
            &mut x,
            &mut ax,
            &mut mark,
            &mut scratch,
        ) else {
            return Err((iteration, f64::INFINITY));
        };
        let lambda = b - &ax;
        let residual = natural_residual(&x, &lambda, lo, hi) / scale;
        if residual <= tolerance {
            return Ok(BoxSolution {
                x,
                lambda,
                ax,
                residual,
                iterations: iteration,
                fallback: false,
            });
        }
        if best.as_ref().is_none_or(|(r, _)| residual < *r) {
            best = Some((residual, x.clone()));
        }
        let repeated = update_sets(&x, &lambda, lo, hi, active);
        // The sets repeat but the step missed the tolerance: an updated factor's round-off; the
        // next Newton step uses a fresh one.
        active.factor.stale |= repeated && updated;
    }
    gauss_seidel(a, b, lo, hi, active, scale, tolerance, best.map(|(_, x)| x))
}

/// Fixed unknowns at their bounds, Newton step on the free ones (A_FF x_F = b_F − A_FB x_B by
/// the updated factor), with `ax` = A x. `Some(whether the factor was updated rather than
/// made)`, `None` if the free block could not be factored.
#[allow(clippy::too_many_arguments)]
fn newton_step(
    data: &[f64],
    b: &DVector<f64>,
    lo: &[f64],
    hi: &[f64],
    active: &mut ActiveSet,
    x: &mut DVector<f64>,
    ax: &mut DVector<f64>,
    mark: &mut [bool],
    scratch: &mut Vec<f64>,
) -> Option<bool> {
    let n = b.len();
    for i in 0..n {
        if lo[i] == hi[i] {
            active.sets[i] = Bound::Lower;
        }
        x[i] = match active.sets[i] {
            Bound::Lower => lo[i],
            Bound::Upper => hi[i],
            Bound::Free => 0.0,
        };
    }
    let free: Vec<usize> = (0..n).filter(|&i| active.sets[i] == Bound::Free).collect();
    let mut updated = false;
    // The bound unknowns' part of A x (x is zero on the free ones here): their pull on the
    // free ones; the free columns are added after the Newton step.
    ax.fill(0.0);
    add_product(data, x.as_slice(), 0..n, ax.as_mut_slice());
    if !free.is_empty() {
        if !active.factor.set_free(data, n, &free, mark, scratch) {
            return None;
        }
        updated = active.factor.updates > 0;
        let factor = &active.factor;
        scratch.clear();
        scratch.extend(factor.order.iter().map(|&p| b[p] - ax[p]));
        factor.solve(scratch);
        for (&p, &xp) in factor.order.iter().zip(scratch.iter()) {
            x[p] = xp;
        }
        add_product(data, x.as_slice(), free.iter().copied(), ax.as_mut_slice());
    }
    Some(updated)
}

/// The next sets by the trial x + λ clamped to the bounds; whether they repeat the current ones.
fn update_sets(
    x: &DVector<f64>,
    lambda: &DVector<f64>,
    lo: &[f64],
    hi: &[f64],
    active: &mut ActiveSet,
) -> bool {
    let mut repeated = true;
    for i in 0..x.len() {
        let trial = x[i] + lambda[i];
        let set = if lo[i] == hi[i] || trial < lo[i] {
            Bound::Lower
        } else if trial > hi[i] {
            Bound::Upper
        } else {
            Bound::Free
        };
        repeated &= set == active.sets[i];
        active.sets[i] = set;
    }
    repeated
}

/// Why a matrix-free solve stopped short of its tolerance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unsolved {
    /// Active-set plus CG iterations done.
    pub iterations: usize,
    /// The residual reached (relative).
    pub residual: f64,
    /// The unknown with the largest residual (for friction: the post that did not settle), if
    /// known.
    pub worst: Option<usize>,
}

/// The index of the largest |v_i| (0 for an empty v).
fn argmax_abs(v: impl Iterator<Item = f64>) -> usize {
    v.enumerate()
        .fold(
            (0, -1.0),
            |(k, m), (i, x)| if x.abs() > m { (i, x.abs()) } else { (k, m) },
        )
        .0
}

/// A symmetric positive definite matrix given by its product: y = A x.
pub trait SymmetricProduct: Sync {
    /// Size n.
    fn size(&self) -> usize;
    /// y = A x (y overwritten) in `precision` (an operator without a single-precision
    /// product computes in double).
    fn product(&self, x: &[f64], y: &mut [f64], precision: Precision);
}

/// [`solve`] with A given only by its product (module doc, matrix-free variant): `active.sets`
/// is the warm start of the sets (its factor is not used), `start` the first guess of the free
/// unknowns (e.g. the previous step's solution), `inexact` the precision of the inexact steps'
/// inner products (module doc, mixed precision). [`Unsolved`] (with the unknown that did not
/// settle) if the tolerance is not reached.
pub fn solve_operator(
    a: &dyn SymmetricProduct,
    b: &DVector<f64>,
    lo: &[f64],
    hi: &[f64],
    active: &mut ActiveSet,
    start: &DVector<f64>,
    scale: f64,
    tolerance: f64,
    inexact: Precision,
) -> std::result::Result<BoxSolution, Unsolved> {
    let n = b.len();
    let scale = scale.max(1e-300);
    let mut x = start.clone();
    let mut worst = 0;
    let mut ax = DVector::zeros(n);
    let mut cg_tolerance = 0.1 * tolerance * scale;
    let mut iterations = 0;
    let mut residual = f64::INFINITY;
    let mut previous_sets: Option<Vec<Bound>> = None;
    let mut exact = false;
    for step in 0..MAX_ACTIVE_SET_ITERATIONS {
        iterations += 1;
        hold_bound(active, lo, hi, &mut x);
        let free: Vec<bool> = active.sets.iter().map(|s| *s == Bound::Free).collect();
        let (reduction, inner) = if exact || step >= MAX_INEXACT_STEPS {
            (0.0, Precision::Double)
        } else {
            (INEXACT_CG_REDUCTION, inexact)
        };
        let cg = (cg_tolerance, reduction, inner);
        iterations +=
            conjugate_gradient(a, b, &free, &mut x, &mut ax, cg).map_err(|(r, worst)| {
                Unsolved {
                    iterations,
                    residual: r / scale,
                    worst: Some(worst),
                }
            })?;
        let mut lambda = b - &ax;
        residual = natural_residual(&x, &lambda, lo, hi) / scale;
        if residual <= tolerance {
            // Accepted on a freshly applied A x, not on the CG's running one.
            a.product(x.as_slice(), ax.as_mut_slice(), Precision::Double);
            lambda = b - &ax;
            residual = natural_residual(&x, &lambda, lo, hi) / scale;
        }
        if residual <= tolerance {
            return Ok(BoxSolution {
                x,
                lambda,
                ax,
                residual,
                iterations,
                fallback: false,
            });
        }
        worst = argmax_abs((0..n).map(|i| x[i] - (x[i] + lambda[i]).clamp(lo[i], hi[i])));
        update_sets(&x, &lambda, lo, hi, active);
        if previous_sets.as_ref() == Some(&active.sets) {
            if exact {
                cg_tolerance *= CG_TIGHTENING;
            }
            exact = true;
        }
        previous_sets = Some(active.sets.clone());
    }
    Err(Unsolved {
        iterations,
        residual,
        worst: Some(worst),
    })
}

/// Unknowns with lo = hi go to the lower set; the bound unknowns of `x` to their bounds (the
/// free ones keep their values: the next CG's start).
fn hold_bound(active: &mut ActiveSet, lo: &[f64], hi: &[f64], x: &mut DVector<f64>) {
    for i in 0..x.len() {
        if lo[i] == hi[i] {
            active.sets[i] = Bound::Lower;
        }
        match active.sets[i] {
            Bound::Lower => x[i] = lo[i],
            Bound::Upper => x[i] = hi[i],
            Bound::Free => {}
        }
    }
}

/// CG on the free unknowns of A x = b (the bound ones held): x updated in place, `ax` = A x
/// (a product at the start, then updated with every step's A p, so the caller needs no
/// product of its own).
/// Stops at the residual max(`tolerance`, `reduction` × the first residual); the products of
/// its iterations in `inner` (the first is double: module docs, mixed precision). Returns the
/// iterations, or the residual reached and the unknown that carries it if the iteration limit
/// is hit or the block is not positive definite.
fn conjugate_gradient(
    a: &dyn SymmetricProduct,
    b: &DVector<f64>,
    free: &[bool],
    x: &mut DVector<f64>,
    ax: &mut DVector<f64>,
    (tolerance, reduction, inner): (f64, f64, Precision),
) -> std::result::Result<usize, (f64, usize)> {
    let n = b.len();
    a.product(x.as_slice(), ax.as_mut_slice(), Precision::Double);
    let mut r = b - &*ax;
    for (ri, &f) in r.iter_mut().zip(free) {
        if !f {
            *ri = 0.0;
        }
    }
    let mut r_max = r.amax();
    let tolerance = tolerance.max(reduction * r_max);
    let limit = CG_ITERATIONS_PER_SQRT_N * ((n as f64).sqrt() as usize + 50);
    let mut p = r.clone();
    let mut rr = r.dot(&r);
    let mut ap = DVector::zeros(n);
    for k in 0..limit {
        if r_max <= tolerance {
            return Ok(k);
        }
        a.product(p.as_slice(), ap.as_mut_slice(), inner);
        // p is zero on the bound unknowns: pᵀA p needs no mask.
        let pap = p.dot(&ap);
        if pap.is_nan() || pap <= 0.0 {
            return Err((r_max, argmax_abs(r.iter().copied())));
        }
        let alpha = rr / pap;
        let (rr_new, largest) = cg_update(alpha, free, &p, &ap, x, ax, &mut r);
        let beta = rr_new / rr;
        for (pi, &ri) in p.iter_mut().zip(r.iter()) {
            *pi = ri + *pi * beta;
        }
        (rr, r_max) = (rr_new, largest);
    }
    if r_max <= tolerance {
        Ok(limit)
    } else {
        Err((r_max, argmax_abs(r.iter().copied())))
    }
}

/// One CG update in a single pass: x += α p, A x += α A p, r −= α A p on the free unknowns
/// (r stays zero on the bound ones); returns rᵀr and max |r_i| of the new residual.
fn cg_update(
    alpha: f64,
    free: &[bool],
    p: &DVector<f64>,
    ap: &DVector<f64>,
    x: &mut DVector<f64>,
    ax: &mut DVector<f64>,
    r: &mut DVector<f64>,
) -> (f64, f64) {
    let n = free.len();
    let (p, ap) = (&p.as_slice()[..n], &ap.as_slice()[..n]);
    let (x, ax, r) = (
        &mut x.as_mut_slice()[..n],
        &mut ax.as_mut_slice()[..n],
        &mut r.as_mut_slice()[..n],
    );
    let (mut rr, mut largest) = (0.0, 0.0_f64);
    for i in 0..n {
        x[i] += alpha * p[i];
        ax[i] += alpha * ap[i];
        let ri = r[i] - alpha * ap[i] * f64::from(u8::from(free[i]));
        r[i] = ri;
        rr += ri * ri;
        largest = largest.max(ri.abs());
    }
    (rr, largest)
}

/// Projected Gauss–Seidel from `start` (else zero), clamped into the box.
#[allow(clippy::too_many_arguments)]
fn gauss_seidel(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    lo: &[f64],
    hi: &[f64],
    active: &mut ActiveSet,
    scale: f64,
    tolerance: f64,
    start: Option<DVector<f64>>,
) -> std::result::Result<BoxSolution, (usize, f64)> {
    let n = b.len();
    let mut x = start.unwrap_or_else(|| DVector::zeros(n));
    for i in 0..n {
        x[i] = x[i].clamp(lo[i], hi[i]);
    }
    let mut residual = f64::INFINITY;
    for sweep in 1..=MAX_GAUSS_SEIDEL_SWEEPS {
        for i in 0..n {
            let off: f64 = (0..n).filter(|&j| j != i).map(|j| a[(i, j)] * x[j]).sum();
            x[i] = ((b[i] - off) / a[(i, i)]).clamp(lo[i], hi[i]);
        }
        if sweep % 8 == 0 || sweep == MAX_GAUSS_SEIDEL_SWEEPS {
            let ax = a * &x;
            let lambda = b - &ax;
            residual = natural_residual(&x, &lambda, lo, hi) / scale;
            if residual <= tolerance {
                for i in 0..n {
                    active.sets[i] = if x[i] <= lo[i] {
                        Bound::Lower
                    } else if x[i] >= hi[i] {
                        Bound::Upper
                    } else {
                        Bound::Free
                    };
                }
                active.factor.stale = true;
                return Ok(BoxSolution {
                    x,
                    lambda,
                    ax,
                    residual,
                    iterations: MAX_ACTIVE_SET_ITERATIONS + sweep,
                    fallback: true,
                });
            }
        }
    }
    Err((
        MAX_ACTIVE_SET_ITERATIONS + MAX_GAUSS_SEIDEL_SWEEPS,
        residual,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_solve_that_cannot_converge_reports_its_iterations_and_residual() {
        // Indefinite A: no Cholesky factor of the free block, the solve stops with an error
        // that the model turns into CoupledError::NotConverged naming the speed and step.
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        let b = DVector::from_vec(vec![0.1, 0.2]);
        let mut active = ActiveSet::new(2);
        let err = solve(&a, &b, &[-1.0; 2], &[1.0; 2], &mut active, 1.0, 1e-12).unwrap_err();
        assert!(
            err.0 >= 1 && err.1.is_infinite(),
            "non-convergence reported with iterations and residual: {err:?}"
        );
    }

    struct Dense(DMatrix<f64>);
    impl SymmetricProduct for Dense {
        fn size(&self) -> usize {
            self.0.nrows()
        }
        fn product(&self, x: &[f64], y: &mut [f64], _: Precision) {
            let v = &self.0 * DVector::from_column_slice(x);
            y.copy_from_slice(v.as_slice());
        }
    }

    #[test]
    fn the_matrix_free_solve_equals_the_factored_one() {
        let n = 30;
        let a = DMatrix::from_fn(n, n, |i, j| {
            1.0 / (1.0 + (i as f64 - j as f64).powi(2)) + if i == j { 0.5 } else { 0.0 }
        });
        for shift in [0.0, 0.7, 2.0] {
            let b = DVector::from_fn(n, |i, _| (i as f64 * 0.9 + shift).sin() * 2.0);
            let lo: Vec<f64> = (0..n)
                .map(|i| {
                    if i % 7 == 3 {
                        0.0
                    } else {
                        -0.3 - 0.02 * i as f64
                    }
                })
                .collect();
            let hi: Vec<f64> = lo.iter().map(|l| -l).collect();
            let exact = solve(&a, &b, &lo, &hi, &mut ActiveSet::new(n), 1.0, 1e-14).unwrap();
            let free = solve_operator(
                &Dense(a.clone()),
                &b,
                &lo,
                &hi,
                &mut ActiveSet::new(n),
                &DVector::zeros(n),
                1.0,
                1e-13,
                Precision::Single,
            )
            .unwrap();
            assert!(
                (&free.x - &exact.x).amax() < 1e-12,
                "matrix-free vs factored minimiser (shift {shift}): {:e}",
                (&free.x - &exact.x).amax()
            );
            assert!(free.residual <= 1e-13, "natural residual {}", free.residual);
        }
    }

    #[test]
    fn diagonal_problem_is_the_clamped_unconstrained_minimiser() {
        let a = DMatrix::from_diagonal(&DVector::from_vec(vec![2.0, 1.0, 4.0]));
        let b = DVector::from_vec(vec![4.0, -3.0, 1.0]);
        let mut active = ActiveSet::new(3);
        let s = solve(&a, &b, &[-1.0; 3], &[1.0; 3], &mut active, 1.0, 1e-14).unwrap();
        assert_eq!(s.x.as_slice(), &[1.0, -1.0, 0.25], "clamped minimiser");
        assert_eq!(
            active.sets,
            vec![Bound::Upper, Bound::Lower, Bound::Free],
            "final sets"
        );
    }

    #[test]
    fn coupled_problem_satisfies_the_kkt_conditions_exactly() {
        let n = 12;
        let a = DMatrix::from_fn(n, n, |i, j| 1.0 / (1.0 + (i as f64 - j as f64).abs()));
        let b = DVector::from_fn(n, |i, _| (i as f64 * 1.7).sin() * 3.0);
        let lo: Vec<f64> = (0..n).map(|i| -0.2 - 0.05 * i as f64).collect();
        let hi: Vec<f64> = lo.iter().map(|l| -l).collect();
        let mut active = ActiveSet::new(n);
        let s = solve(&a, &b, &lo, &hi, &mut active, 1.0, 1e-13).unwrap();
        for i in 0..n {
            let inside = s.x[i] > lo[i] + 1e-12 && s.x[i] < hi[i] - 1e-12;
            assert!(
                !inside || s.lambda[i].abs() < 1e-12,
                "interior unknown {i} has slip λ = {}",
                s.lambda[i]
            );
            assert!(
                s.x[i] < hi[i] - 1e-12 || s.lambda[i] >= -1e-12,
                "upper-bound unknown {i} slips the wrong way"
            );
        }
        assert!(!s.fallback, "active set settles without the fallback");
    }
}
