//! A lattice compliance operator **folded by the slider's y-mirror**: for a lattice of n_x × n_y
//! posts (n_y even) whose loads are mirror images across its x-axis, f(i, j) = f(i, n_y − 1 − j),
//! the displacements are mirror images too, and the n_x × n_y/2 posts j < n_y/2 carry the whole
//! problem. On them the operator is
//!
//! (C_m f)(i, j) = Σ_{i', j' < n_y/2} [c(i − i', j − j') + c(i − i', n_y − 1 − j − j')] f(i', j'),
//!
//! the full operator C applied to the mirror-extended f and read on the lower half (C_m = R C E,
//! E the mirror extension, R the restriction). It is symmetric positive definite when C is
//! (Eᵀ = 2R on mirror-symmetric vectors, so C_m = ½ Eᵀ C E), for any kernel c(di, dj) even in
//! each offset separately (the normal and the tangential lattice kernels, [`crate::lattice`],
//! [`crate::tangential`]).
//!
//! **Product**, a Toeplitz (j − j') plus a Hankel (j + j') convolution on the half lattice, both
//! by zero-padded FFTs: along x length P_x ≥ 2n_x − 1 (two real columns per complex transform,
//! unpacked by the Hermitian symmetry of a real column's spectrum, P_x/2 + 1 non-negative
//! wavenumbers kept), along y length P_y ≥ n_y − 1. With F(k_x, k_y) the transform of f, the
//! transform of the Hankel part is Ĥ(k_x, k_y) F(k_x, −k_y), Ĥ the transform of the generator
//! g(m) = ĉ(k_x, n_y − 1 − m), m = 0 … n_y − 2 (ĉ(k_x, dj) the kernel's x-spectrum), since
//! Σ_j ω^{j k} Σ_{j'} g(j + j') f_{j'} = Ĝ_k F_{−k}; the Toeplitz part's T̂ is real (even kernel).
//! Per product n_y/2 transforms of length P_x and P_x + 2 of length P_y, against ≈ 3 n_x + P_x
//! transforms of length ≈ 2 n_y for the full operator's 2D convolution: for the paper's 100 × 100
//! slider 50 × 200-point and 202 × 100-point transforms instead of ≈ 300 × 200-point ones.
//! Exact (the same linear convolution as the full operator, to rounding).
//!
//! Valid where the kernel is (its module) and only for mirror-symmetric loads: the caller
//! checks that its problem has the symmetry (post offsets, wave amplitudes and preload
//! mechanism mirror-symmetric in y) before folding.

use std::sync::Arc;

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

use crate::error::{Result, invalid};
use crate::lattice::{ComplianceOperator, LatticeGeometry, padded_length};
use crate::tangential::TangentialKernel;

/// The folded operator C_m on the lower half (j < n_y/2) of a mirror-symmetric lattice, lattice
/// order i·(n_y/2) + j (module doc).
#[derive(Clone)]
pub struct MirrorOperator {
    nx: usize,
    half: usize,
    px: usize,
    py: usize,
    /// T̂(k_x, k_y)/(P_x P_y), k_x = 0 … P_x/2 (rows of P_y).
    toeplitz: Vec<f64>,
    /// Ĥ(k_x, k_y)/(P_x P_y), the same layout.
    hankel: Vec<Complex<f64>>,
    diagonal_m_per_n: Vec<f64>,
    fft_x: Arc<dyn Fft<f64>>,
    ifft_x: Arc<dyn Fft<f64>>,
    fft_y: Arc<dyn Fft<f64>>,
    ifft_y: Arc<dyn Fft<f64>>,
}

impl std::fmt::Debug for MirrorOperator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MirrorOperator")
            .field("posts_x", &self.nx)
            .field("half_posts_y", &self.half)
            .finish()
    }
}

/// Offset of padded-grid index r on a grid of p points: r, or r − p past the middle.
fn wrap(r: usize, p: usize) -> i64 {
    if 2 * r <= p {
        r as i64
    } else {
        r as i64 - p as i64
    }
}

impl MirrorOperator {
    /// The folded operator of the kernel c(di, dj) (even in each offset; c(0, 0) the diagonal)
    /// on `geometry`'s lattice. Refused for an odd n_y (the middle row is its own image).
    pub fn from_offsets(
        geometry: &LatticeGeometry,
        kernel: impl Fn(i64, i64) -> f64,
    ) -> Result<Self> {
        geometry.validate()?;
        let (nx, ny) = (geometry.posts_x, geometry.posts_y);
        if !ny.is_multiple_of(2) {
            return Err(invalid(
                "posts_y",
                ny as f64,
                "the mirror-folded operator needs an even number of rows",
            ));
        }
        let half = ny / 2;
        let (px, py) = (padded_length(nx), padded_length(half));
        let mut planner = FftPlanner::new();
        let (fft_x, fft_y) = (planner.plan_fft_forward(px), planner.plan_fft_forward(py));
        // x-spectra ĉ(k_x, dj) of the kernel's columns dj = 0 … n_y − 1 (even in di: real), at
        // wrapped offsets as the full operator's grid.
        let mut columns: Vec<Complex<f64>> = (0..ny)
            .flat_map(|dj| (0..px).map(move |r| (r, dj)))
            .map(|(r, dj)| Complex::new(kernel(wrap(r, px), dj as i64), 0.0))
            .collect();
        fft_x.process(&mut columns);
        let scale = 1.0 / (px * py) as f64;
        let c = |k: usize, dj: usize| columns[dj * px + k].re * scale;
        let wavenumbers = px / 2 + 1;
        let zero = Complex::new(0.0, 0.0);
        // Per x-wavenumber: the Toeplitz generator at wrapped offsets (even: real spectrum;
        // offsets ≥ n_y/2 are never read by the linear convolution), the Hankel one g(m).
        let mut t = vec![zero; wavenumbers * py];
        let mut g = vec![zero; wavenumbers * py];
        for k in 0..wavenumbers {
            for r in 0..py {
                t[k * py + r] = Complex::new(c(k, wrap(r, py).unsigned_abs() as usize), 0.0);
            }
            for m in 0..(ny - 1).min(py) {
                g[k * py + m] = Complex::new(c(k, ny - 1 - m), 0.0);
            }
        }
        fft_y.process(&mut t);
        fft_y.process(&mut g);
        let diagonal_m_per_n = (0..nx)
            .flat_map(|_| 0..half)
            .map(|j| kernel(0, 0) + kernel(0, (ny - 1 - 2 * j) as i64))
            .collect();
        Ok(Self {
            nx,
            half,
            px,
            py,
            toeplitz: t.iter().map(|z| z.re).collect(),
            hankel: g,
            diagonal_m_per_n,
            fft_x,
            ifft_x: planner.plan_fft_inverse(px),
            fft_y,
            ifft_y: planner.plan_fft_inverse(py),
        })
    }

    /// Rows of the folded lattice (n_y/2).
    pub fn half_posts_y(&self) -> usize {
        self.half
    }

    /// The x-transforms of the columns' pairs (column 2m + i·column 2m + 1), unpacked to each
    /// column's spectrum at the non-negative x-wavenumbers: rows k_x of P_y, column j at j.
    fn forward_x(&self, force_n: &[f64]) -> Vec<Complex<f64>> {
        let (nx, half, px, py) = (self.nx, self.half, self.px, self.py);
        let zero = Complex::new(0.0, 0.0);
        let pairs = half.div_ceil(2);
        let column = |j: usize, i: usize| if j < half { force_n[i * half + j] } else { 0.0 };
        let mut a = vec![zero; pairs * px];
        for m in 0..pairs {
            for i in 0..nx {
                a[m * px + i] = Complex::new(column(2 * m, i), column(2 * m + 1, i));
            }
        }
        self.fft_x.process(&mut a);
        let mut b = vec![zero; (px / 2 + 1) * py];
        for m in 0..pairs {
            let z = &a[m * px..(m + 1) * px];
            for (k, row) in b.chunks_exact_mut(py).enumerate() {
                let (zk, zc) = (z[k], z[(px - k) % px].conj());
                row[2 * m] = (zk + zc) * 0.5;
                if 2 * m + 1 < half {
                    row[2 * m + 1] = (zk - zc) * Complex::new(0.0, -0.5);
                }
            }
        }
        b
    }

    /// The inverse of [`Self::forward_x`] on the product's spectra `u` (rows k_x ≤ P_x/2, the
    /// others their conjugates), written to `out_m` (unscaled: the kernels carry 1/(P_x P_y)).
    fn inverse_x(&self, u: &[Complex<f64>], out_m: &mut [f64]) {
        let (nx, half, px, py) = (self.nx, self.half, self.px, self.py);
        let zero = Complex::new(0.0, 0.0);
        let pairs = half.div_ceil(2);
        let wavenumbers = px / 2 + 1;
        let at = |k: usize, j: usize| {
            if j >= half {
                zero
            } else if k < wavenumbers {
                u[k * py + j]
            } else {
                u[(px - k) * py + j].conj()
            }
        };
        let mut a = vec![zero; pairs * px];
        for m in 0..pairs {
            for k in 0..px {
                a[m * px + k] = at(k, 2 * m) + Complex::new(0.0, 1.0) * at(k, 2 * m + 1);
            }
        }
        self.ifft_x.process(&mut a);
        for m in 0..pairs {
            for i in 0..nx {
                let z = a[m * px + i];
                out_m[i * half + 2 * m] = z.re;
                if 2 * m + 1 < half {
                    out_m[i * half + 2 * m + 1] = z.im;
                }
            }
        }
    }
}

impl TangentialKernel {
    /// The mirror-folded operator of this kernel ([`MirrorOperator`]).
    pub fn mirror_operator(&self, geometry: &LatticeGeometry) -> Result<MirrorOperator> {
        MirrorOperator::from_offsets(geometry, |di, dj| self.at_offset(di, dj))
    }
}

impl ComplianceOperator for MirrorOperator {
    fn len(&self) -> usize {
        self.nx * self.half
    }

    /// x-transforms, y-transforms of every non-negative x-wavenumber's row, the products
    /// T̂ F(k) + Ĥ F(−k), and back.
    fn apply(&self, force_n: &[f64], out_m: &mut [f64]) {
        let py = self.py;
        let mut b = self.forward_x(force_n);
        self.fft_y.process(&mut b);
        let mut u = vec![Complex::new(0.0, 0.0); b.len()];
        for (row, ((f, t), h)) in u.chunks_exact_mut(py).zip(
            b.chunks_exact(py)
                .zip(self.toeplitz.chunks_exact(py))
                .zip(self.hankel.chunks_exact(py)),
        ) {
            for k in 0..py {
                row[k] = f[k] * t[k] + h[k] * f[(py - k) % py];
            }
        }
        self.ifft_y.process(&mut u);
        self.inverse_x(&u, out_m);
    }

    fn diagonal(&self) -> Vec<f64> {
        self.diagonal_m_per_n.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::NearField;
    use crate::lattice::tests::small_spec as spec;

    #[test]
    fn the_folded_product_is_the_full_product_of_the_mirror_extended_loads() {
        for (nx, ny) in [(7, 6), (6, 4), (1, 8), (5, 2), (12, 10), (9, 14)] {
            let s = spec(nx, ny);
            let kernel = TangentialKernel::new(&s, NearField::Johnson).unwrap();
            let full = kernel.to_dense();
            let folded = kernel.mirror_operator(&s.geometry).unwrap();
            let half = ny / 2;
            let f: Vec<f64> = (0..nx * half)
                .map(|i| ((i * 37 % 11) as f64 - 3.0) * 1e-3)
                .collect();
            let extended: Vec<f64> = (0..nx * ny)
                .map(|p| {
                    let (i, j) = (p / ny, p % ny);
                    f[i * half + j.min(ny - 1 - j)]
                })
                .collect();
            let mut u_full = vec![0.0; nx * ny];
            full.apply(&extended, &mut u_full);
            let mut u = vec![0.0; nx * half];
            folded.apply(&f, &mut u);
            let scale = u_full.iter().map(|u| u.abs()).fold(0.0, f64::max);
            for i in 0..nx {
                for j in 0..ny {
                    let (ours, theirs) = (u[i * half + j.min(ny - 1 - j)], u_full[i * ny + j]);
                    assert!(
                        (ours - theirs).abs() < 1e-12 * scale,
                        "post ({i}, {j}) of {nx} × {ny}: folded {ours} vs full {theirs}"
                    );
                }
            }
            let d = folded.diagonal();
            for j in 0..half {
                let dense = full[(j, j)] + full[(j, ny - 1 - j)];
                assert!((d[j] - dense).abs() < 1e-15 * dense, "diagonal of row {j}");
            }
        }
    }

    #[test]
    fn an_odd_number_of_rows_is_refused_by_name() {
        let s = spec(4, 5);
        let kernel = TangentialKernel::new(&s, NearField::Johnson).unwrap();
        let err = kernel.mirror_operator(&s.geometry).unwrap_err();
        assert!(err.to_string().contains("posts_y"), "{err}");
    }
}
