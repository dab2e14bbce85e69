//! Partial waves of a piezoelectric half-space: the 8×8 Stroh eigenproblem in scaled units.
//!
//! Formula: in the wave frame (x₁ propagation, x₃ outward normal) the generalized displacement
//! U = (u₁, u₂, u₃, φ) of one partial wave is A·exp(j(ωt − k x₁ − k p x₃)). With the generalized
//! stiffness C_iJKl (c_ijkl for J, K ≤ 3; e_lij for K = 4; e_ikl for J = 4; −ε_il for J = K = 4) and
//! Q_JK = C_1JK1, R_JK = C_1JK3, T_JK = C_3JK3, Ĩ = diag(1, 1, 1, 0), the equations of motion and
//! Gauss's law read [Q − ρv²Ĩ + p(R + Rᵀ) + p²T]·A = 0. With L = (Rᵀ + pT)·A (the traction
//! (T₃₁, T₃₂, T₃₃, D₃) on x₃ planes divided by −jk) this is the linear eigenproblem
//! p·[A; L] = N·[A; L], N = [[−T⁻¹Rᵀ, T⁻¹], [R T⁻¹ Rᵀ − Q + ρv²Ĩ, −R T⁻¹]]. Below the limiting
//! velocity the 8 roots p form 4 conjugate pairs; the 4 with Im p > 0 decay into the crystal
//! (x₃ → −∞). Their polarizations A are the null vectors of the 4×4 Christoffel-type matrix, taken
//! from its SVD (a cluster of m equal roots, e.g. the two shear waves of an isotropic solid,
//! takes the m smallest singular vectors).
//!
//! Source: A. N. Stroh, *J. Math. Phys.* 41, 77 (1962); G. W. Farnell, E. L. Adler, "Elastic wave
//! propagation in thin layers", *Physical Acoustics* IX (1972) and J. J. Campbell, W. R. Jones,
//! *IEEE Trans. Sonics Ultrason.* SU-15, 209 (1968) for the piezoelectric partial waves.
//!
//! Scaling: stiffness by c_ref (the mean of the rotated c_II), permittivity by ε_ref (the mean of
//! the rotated ε_ii), piezoelectric constants by √(c_ref ε_ref), the potential by c_ref/√(c_ref ε_ref)
//! (so that φ has the unit of a length), velocity by √(c_ref/ρ). Every matrix entry is then O(1).
//!
//! Range of validity: lossless crystal, quasi-static electric field (v ≪ speed of light), phase
//! velocity below the limiting velocity (otherwise some partial wave does not decay: the wave is
//! leaky and [`StrohSystem::partial_waves`] refuses).

use crate::material::{Material, VACUUM_PERMITTIVITY_F_PER_M};
use crate::rotation::voigt;
use nalgebra::{Complex, Matrix3, Matrix4, SMatrix, Schur};

/// Complex double.
pub type C64 = Complex<f64>;

/// |Im p| below this (relative to 1 + |p|) counts as a non-decaying, bulk-like partial wave.
const BOUND_TOLERANCE: f64 = 1e-7;
/// Roots closer than this (relative to 1 + |p|) are one degenerate cluster.
const CLUSTER_TOLERANCE: f64 = 1e-9;
/// Convergence threshold and iteration cap of the real Schur decomposition of N.
const SCHUR_EPSILON: f64 = 1e-15;
const SCHUR_MAX_ITERATIONS: usize = 10_000;

/// Reference scales of the scaled problem (SI).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Scales {
    pub stiffness_pa: f64,
    pub permittivity_f_per_m: f64,
    pub velocity_m_per_s: f64,
}

impl Scales {
    /// Piezoelectric constant scale √(c_ref ε_ref) (C/m²).
    pub fn piezo_c_per_m2(&self) -> f64 {
        (self.stiffness_pa * self.permittivity_f_per_m).sqrt()
    }

    /// Physical potential per scaled potential (V/m): c_ref / e_ref.
    pub fn potential_v_per_m(&self) -> f64 {
        self.stiffness_pa / self.piezo_c_per_m2()
    }
}

/// The scaled Q, R, T of one rotated material.
#[derive(Debug, Clone)]
pub(crate) struct StrohSystem {
    pub q: Matrix4<f64>,
    pub r: Matrix4<f64>,
    pub t: Matrix4<f64>,
    t_inv: Matrix4<f64>,
    /// ε0 / ε_ref.
    pub vacuum_permittivity: f64,
    pub scales: Scales,
}

/// The four decaying partial waves at one velocity (columns of `a`, `l`, `f`).
#[derive(Debug, Clone)]
pub(crate) struct PartialWaves {
    /// Depth ratios p (Im p > 0).
    pub p: [C64; 4],
    /// Generalized displacements A = (u₁, u₂, u₃, φ), scaled.
    pub a: Matrix4<C64>,
    /// L = (Rᵀ + pT)A: traction on x₃ planes over −jk.
    pub l: Matrix4<C64>,
    /// F = (Q + pR)A: traction (T₁₁, T₁₂, T₁₃, D₁) on x₁ planes over −jk.
    pub f: Matrix4<C64>,
}

impl StrohSystem {
    /// Scales and assembles Q, R, T of a material given in the wave frame; `None` if T is singular.
    pub fn new(rotated: &Material) -> Option<Self> {
        let c = &rotated.stiffness_pa;
        let eps = &rotated.permittivity_f_per_m;
        let c_ref = (0..6).map(|i| c[i][i]).sum::<f64>() / 6.0;
        let eps_ref = (0..3).map(|i| eps[i][i]).sum::<f64>() / 3.0;
        let scales = Scales {
            stiffness_pa: c_ref,
            permittivity_f_per_m: eps_ref,
            velocity_m_per_s: (c_ref / rotated.density_kg_per_m3).sqrt(),
        };
        let e_ref = scales.piezo_c_per_m2();
        let block = |i: usize, l: usize| {
            Matrix4::from_fn(|j, k| match (j, k) {
                (3, 3) => -eps[i][l] / eps_ref,
                (3, k) => rotated.piezo_c_per_m2[i][voigt(k, l)] / e_ref,
                (j, 3) => rotated.piezo_c_per_m2[l][voigt(i, j)] / e_ref,
                (j, k) => c[voigt(i, j)][voigt(k, l)] / c_ref,
            })
        };
        let t = block(2, 2);
        Some(Self {
            q: block(0, 0),
            r: block(0, 2),
            t_inv: t.try_inverse()?,
            t,
            vacuum_permittivity: VACUUM_PERMITTIVITY_F_PER_M / eps_ref,
            scales,
        })
    }

    /// Q − v²Ĩ at scaled velocity v.
    fn q_inertial(&self, v: f64) -> Matrix4<f64> {
        let mut q = self.q;
        for i in 0..3 {
            q[(i, i)] -= v * v;
        }
        q
    }

    /// The slowest bulk wave along x₁ (p = 0), piezoelectrically stiffened (scaled velocity).
    /// The limiting velocity is at most this.
    pub fn slowest_bulk_velocity_along_x1(&self) -> f64 {
        let m = Matrix3::from_fn(|i, j| {
            self.q[(i, j)] - self.q[(i, 3)] * self.q[(3, j)] / self.q[(3, 3)]
        });
        m.symmetric_eigenvalues().min().max(0.0).sqrt()
    }

    /// The 8 roots p at scaled velocity v; `None` if the Schur iteration fails.
    pub fn roots(&self, v: f64) -> Option<[C64; 8]> {
        let rt = self.r.transpose();
        let mut n = SMatrix::<f64, 8, 8>::zeros();
        n.fixed_view_mut::<4, 4>(0, 0)
            .copy_from(&(-self.t_inv * rt));
        n.fixed_view_mut::<4, 4>(0, 4).copy_from(&self.t_inv);
        n.fixed_view_mut::<4, 4>(4, 0)
            .copy_from(&(self.r * self.t_inv * rt - self.q_inertial(v)));
        n.fixed_view_mut::<4, 4>(4, 4)
            .copy_from(&(-self.r * self.t_inv));
        let eigenvalues =
            Schur::try_new(n, SCHUR_EPSILON, SCHUR_MAX_ITERATIONS)?.complex_eigenvalues();
        let mut out = [C64::new(0.0, 0.0); 8];
        out.iter_mut()
            .zip(eigenvalues.iter())
            .for_each(|(o, e)| *o = *e);
        Some(out)
    }

    /// The decaying roots if exactly four decay and four grow; `Ok(None)` above the limiting
    /// velocity (some root is real).
    pub fn decaying_roots(&self, v: f64) -> Result<Option<[C64; 4]>, &'static str> {
        let roots = self
            .roots(v)
            .ok_or("the Schur decomposition of the Stroh matrix did not converge")?;
        let bound = |p: &C64| p.im.abs() > BOUND_TOLERANCE * (1.0 + p.norm());
        if !roots.iter().all(bound) {
            return Ok(None);
        }
        let mut decaying: Vec<C64> = roots.into_iter().filter(|p| p.im > 0.0).collect();
        if decaying.len() != 4 {
            return Err("the Stroh roots are not four conjugate pairs");
        }
        decaying.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
        Ok(Some([decaying[0], decaying[1], decaying[2], decaying[3]]))
    }

    /// The four decaying partial waves at scaled velocity v; `Ok(None)` above the limiting velocity.
    pub fn partial_waves(&self, v: f64) -> Result<Option<PartialWaves>, &'static str> {
        let Some(p) = self.decaying_roots(v)? else {
            return Ok(None);
        };
        let mut waves = PartialWaves {
            p,
            a: Matrix4::zeros(),
            l: Matrix4::zeros(),
            f: Matrix4::zeros(),
        };
        for cluster in clusters(&p) {
            let mean = cluster.iter().map(|&i| p[i]).sum::<C64>() / cluster.len() as f64;
            let null = self.null_vectors(v, mean, cluster.len())?;
            for (column, &i) in cluster.iter().enumerate() {
                waves.p[i] = mean;
                waves.a.set_column(i, &null.column(column));
            }
        }
        let (q, r, t) = (
            self.q.cast::<C64>(),
            self.r.cast::<C64>(),
            self.t.cast::<C64>(),
        );
        for i in 0..4 {
            let a = waves.a.column(i).into_owned();
            waves
                .l
                .set_column(i, &((r.transpose() + t * waves.p[i]) * a));
            waves.f.set_column(i, &((q + r * waves.p[i]) * a));
        }
        Ok(Some(waves))
    }

    /// The `count` right singular vectors of the smallest singular values of
    /// Q − v²Ĩ + p(R + Rᵀ) + p²T (columns 0..count of the result).
    fn null_vectors(&self, v: f64, p: C64, count: usize) -> Result<Matrix4<C64>, &'static str> {
        let m = self.q_inertial(v).cast::<C64>()
            + (self.r + self.r.transpose()).cast::<C64>() * p
            + self.t.cast::<C64>() * (p * p);
        let svd = m.svd(false, true);
        let v_t = svd
            .v_t
            .ok_or("the SVD of the Christoffel matrix returned no singular vectors")?;
        let mut out = Matrix4::zeros();
        for column in 0..count {
            out.set_column(column, &v_t.row(3 - column).adjoint());
        }
        Ok(out)
    }
}

/// Groups indices of (nearly) equal roots.
fn clusters(p: &[C64; 4]) -> Vec<Vec<usize>> {
    let mut assigned = [false; 4];
    let mut out = Vec::new();
    for i in 0..4 {
        if assigned[i] {
            continue;
        }
        let group: Vec<usize> = (i..4)
            .filter(|&j| {
                !assigned[j] && (p[j] - p[i]).norm() < CLUSTER_TOLERANCE * (1.0 + p[i].norm())
            })
            .collect();
        group.iter().for_each(|&j| assigned[j] = true);
        out.push(group);
    }
    out
}
