//! Preconditioning the free-back contact solve: the plate's own factor, through Woodbury.
//!
//! **What slows the free back.** Its compliance is C + G, C the lattice operator (stator
//! half-space + the body's local part) and G = Bᵀ K⁻¹ B the plate's bending at the posts (K the
//! plate stiffness, B the posts' interpolation onto the plate dofs). In Fourier space G is
//! 1/(D k⁴) per unit area: the slider-scale modes are far softer than a post's own compliance
//! C_ii, so (C + G)_AA is ill-conditioned and its condition grows with the slider size.
//!
//! **The preconditioner.** M_A = c I + Bᵀ_A K⁻¹ B_A on the contact set A, with c = C_ii (the
//! lattice's diagonal: its high-wavenumber eigenvalue): exact for the plate, diagonal for the
//! lattice. By the Woodbury identity
//!
//! M_A⁻¹ r = (r − Bᵀ_A (c K + B_A Bᵀ_A)⁻¹ B_A r) / c,
//!
//! a solve with a plate-sized sparse matrix of K's pattern (each post couples only the 16 dofs of
//! its element, which K already couples), factorised with K's symbolic analysis whenever the
//! contact set changes (1 761 unknowns for the default slider).
//!
//! **Measured (default slider, 40 N; validation/whole-slider/README.md, Speed).** Ball: 37–40 →
//! 28–29 iterations per phase, but the refactorisation at almost every contact-set change makes
//! it slower in wall time, so [`crate::SliderModel`] leaves it off by default. Pressure: the
//! preconditioned steps move the whole plate at once and the contact set oscillates (no
//! convergence in 5 000 iterations; preconditioning only once the set is unchanged converges
//! but needs more iterations than the plain CG), so it runs the plain CG. What sets the
//! pressure's 200–400 iterations is not the plate's conditioning on a settled contact set: past
//! a residual of 1e-3 the plain CG gains a decade per ≈ 12 iterations; 70–85 % of them are
//! spent while the contact set still changes. Not resolved here.

use elastic_fem::sparse::{NumericCholesky, SymmetricMatrix};

use crate::plate::FreePlate;

/// A preconditioner of the contact-set block of a compliance, rebuilt when the set changes.
pub trait ContactPreconditioner {
    /// out ≈ (C_AA)⁻¹ r on the contact set A (`mask`), 0 elsewhere: r in m, out in N.
    fn apply(&mut self, mask: &[bool], r_m: &[f64], out_n: &mut [f64]);
}

/// The Woodbury preconditioner c I + Bᵀ K⁻¹ B of a free plate (module doc).
#[derive(Debug)]
pub struct PlatePreconditioner<'a> {
    plate: &'a FreePlate,
    /// c (m/N).
    local_m_per_n: f64,
    /// Per post: the positions in K's upper-triangle values of its 16 × 16 pairs (p ≤ q by
    /// reduced dof), with the two local indices.
    positions: Vec<Vec<(usize, u8, u8)>>,
    mask: Vec<bool>,
    matrix: SymmetricMatrix,
    factor: Option<NumericCholesky>,
    /// Factorisations so far (one per contact-set change).
    pub factorisations: usize,
}

impl<'a> PlatePreconditioner<'a> {
    /// The preconditioner of `plate` with the lattice's diagonal `local_m_per_n` (m/N, > 0).
    pub fn new(plate: &'a FreePlate, local_m_per_n: f64) -> Self {
        let k = plate.stiffness_matrix();
        let (col_ptr, row_idx) = (k.col_ptr(), k.row_idx());
        let position = |r: usize, c: usize| -> usize {
            let (r, c) = (r.min(c), r.max(c));
            let rows = &row_idx[col_ptr[c]..col_ptr[c + 1]];
            col_ptr[c]
                + rows
                    .binary_search(&r)
                    .expect("a post's element pair lies in K's pattern")
        };
        let positions = plate
            .post_weights()
            .iter()
            .map(|w| {
                let mut out = Vec::with_capacity(136);
                for p in 0..16 {
                    for q in p..16 {
                        let (rp, rq) = (w[p].0, w[q].0);
                        if rp != usize::MAX && rq != usize::MAX {
                            out.push((position(rp, rq), p as u8, q as u8));
                        }
                    }
                }
                out
            })
            .collect();
        Self {
            plate,
            local_m_per_n,
            positions,
            mask: Vec::new(),
            matrix: k.clone(),
            factor: None,
            factorisations: 0,
        }
    }

    /// Assembles and factorises c K + B_A Bᵀ_A for the contact set `mask`.
    fn refactor(&mut self, mask: &[bool]) {
        let c = self.local_m_per_n;
        let values = self.matrix.values_mut();
        for (v, k) in values
            .iter_mut()
            .zip(self.plate.stiffness_matrix().values())
        {
            *v = c * k;
        }
        let weights = self.plate.post_weights();
        for (i, pairs) in self.positions.iter().enumerate().filter(|(i, _)| mask[*i]) {
            let w = &weights[i];
            for &(pos, p, q) in pairs {
                // The element's 16 dofs are distinct: each unordered pair is one upper entry.
                values[pos] += w[p as usize].1 * w[q as usize].1;
            }
        }
        let factor = match self.factor.take() {
            Some(mut f) => f.refactor(&self.matrix).map(|()| f),
            None => self.plate.factor().symbolic().factor(&self.matrix),
        }
        .expect("c K + B Bᵀ is positive definite (K is, after the fixed corners)");
        self.factor = Some(factor);
        self.mask = mask.to_vec();
        self.factorisations += 1;
    }
}

impl ContactPreconditioner for PlatePreconditioner<'_> {
    fn apply(&mut self, mask: &[bool], r_m: &[f64], out_n: &mut [f64]) {
        if self.factor.is_none() || self.mask != mask {
            self.refactor(mask);
        }
        let weights = self.plate.post_weights();
        let mut load = vec![0.0; self.plate.reduced_dim()];
        for (i, w) in weights.iter().enumerate().filter(|(i, _)| mask[*i]) {
            for &(r, s) in w.iter().filter(|(r, _)| *r != usize::MAX) {
                load[r] += s * r_m[i];
            }
        }
        self.factor
            .as_ref()
            .expect("factorised above")
            .solve_in_place(&mut load)
            .expect("the factor solves finite loads");
        for (i, w) in weights.iter().enumerate() {
            out_n[i] = if mask[i] {
                let back: f64 = w
                    .iter()
                    .filter(|(r, _)| *r != usize::MAX)
                    .map(|&(r, s)| s * load[r])
                    .sum();
                (r_m[i] - back) / self.local_m_per_n
            } else {
                0.0
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::ComplianceOperator;
    use nalgebra::{DMatrix, DVector};

    struct PlateOp<'a>(&'a FreePlate, usize);
    impl ComplianceOperator for PlateOp<'_> {
        fn len(&self) -> usize {
            self.1
        }
        fn apply(&self, f: &[f64], out: &mut [f64]) {
            out.iter_mut().for_each(|x| *x = 0.0);
            self.0.add_post_deflection(f, out);
        }
        fn diagonal(&self) -> Vec<f64> {
            unreachable!()
        }
    }

    /// The Woodbury form equals the inverse of c I + G_AA formed densely.
    #[test]
    fn the_woodbury_preconditioner_inverts_the_diagonal_plus_plate_block() {
        let si = motor::Motor::paper().slider.material;
        let posts: Vec<(f64, f64)> = (0..8)
            .flat_map(|i| {
                (0..6).map(move |j| (0.3e-3 + 0.2e-3 * i as f64, 0.4e-3 + 0.2e-3 * j as f64))
            })
            .collect();
        let n = posts.len();
        let plate = FreePlate::new(2.0e-3, 1.6e-3, 0.5e-3, &si, &posts).unwrap();
        let op = PlateOp(&plate, n);
        let g = DMatrix::from_fn(n, n, |i, j| {
            let mut e = vec![0.0; n];
            e[j] = 1.0;
            let mut u = vec![0.0; n];
            op.apply(&e, &mut u);
            u[i]
        });
        let c = 0.3 * g.diagonal().max();
        let mask: Vec<bool> = (0..n).map(|i| i % 3 != 1).collect();
        let active: Vec<usize> = (0..n).filter(|&i| mask[i]).collect();
        let m = DMatrix::from_fn(active.len(), active.len(), |a, b| {
            g[(active[a], active[b])] + if a == b { c } else { 0.0 }
        });
        let r: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin() * 1e-9).collect();
        let ra = DVector::from_iterator(active.len(), active.iter().map(|&i| r[i]));
        let exact = m.lu().solve(&ra).unwrap();
        let mut pre = PlatePreconditioner::new(&plate, c);
        let mut out = vec![1.0; n];
        pre.apply(&mask, &r, &mut out);
        for (a, &i) in active.iter().enumerate() {
            assert!(
                (out[i] - exact[a]).abs() < 1e-9 * exact.amax(),
                "preconditioned force at post {i}: {} vs dense {}",
                out[i],
                exact[a]
            );
        }
        assert!(
            (0..n).filter(|&i| !mask[i]).all(|i| out[i] == 0.0),
            "posts out of contact get no force"
        );
    }
}
