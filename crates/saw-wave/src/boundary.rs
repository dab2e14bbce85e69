//! Boundary conditions at the crystal surface x₃ = 0 and the real boundary determinant.
//!
//! Formula: with the decaying partial waves (columns of A and L, see [`crate::stroh`]) the surface
//! values of a guided field are U₀ = A·a and L₀ = L·a, so L₀ = G·U₀ with G = L·A⁻¹ (G is basis
//! independent: it does not depend on how the partial waves are normalised or, for degenerate
//! roots, chosen). Conservation of energy makes the time-averaged flux through the surface vanish
//! for every U₀, so jG is Hermitian below the limiting velocity (the surface impedance of
//! Barnett & Lothe). The conditions are
//! - electrically free: T₃ⱼ = 0 and D₃ = ε0·k·φ (the vacuum potential φ e^{−k x₃} above), i.e.
//!   (G − jε0 e₄e₄ᵀ)·U₀ = 0, and det H_free = 0 with H_free = −j(G − jε0 e₄e₄ᵀ) Hermitian;
//! - metallized: T₃ⱼ = 0 and φ = 0, i.e. the upper-left 3×3 block G₃ annihilates (u₁, u₂, u₃),
//!   det H_met = 0 with H_met = −jG₃ Hermitian.
//!
//! Both determinants are real, so the surface-wave velocity is a sign change that can be
//! bracketed and refined (no search for minima of |det|). Source: D. M. Barnett, J. Lothe,
//! *Phys. Status Solidi (b)* 131, 615 (1985) (surface impedance, piezoelectric case);
//! J. Lothe, D. M. Barnett, *J. Appl. Phys.* 47, 428 (1976). Range of validity: velocities below
//! the limiting velocity, where all four partial waves decay.

use crate::stroh::{C64, PartialWaves};
use nalgebra::{Matrix3, Matrix4, Vector3, Vector4};

/// The Hermitian boundary matrices of one velocity.
#[derive(Debug, Clone)]
pub(crate) struct BoundaryMatrices {
    /// −j(G − jε0 e₄e₄ᵀ).
    pub free: Matrix4<C64>,
    /// −jG₃.
    pub metallized: Matrix3<C64>,
}

impl BoundaryMatrices {
    /// From the partial waves and the scaled vacuum permittivity; `None` if A is singular.
    pub fn new(waves: &PartialWaves, vacuum_permittivity: f64) -> Option<Self> {
        let g = waves.l * waves.a.try_inverse()?;
        let minus_j = C64::new(0.0, -1.0);
        let mut free = g * minus_j;
        free[(3, 3)] -= C64::new(vacuum_permittivity, 0.0);
        let metallized = g.fixed_view::<3, 3>(0, 0).into_owned() * minus_j;
        Some(Self { free, metallized })
    }

    /// det H_free (real up to round-off).
    pub fn free_determinant(&self) -> f64 {
        self.free.determinant().re
    }

    /// det H_met (real up to round-off).
    pub fn metallized_determinant(&self) -> f64 {
        self.metallized.determinant().re
    }

    /// The surface vector U₀ of the free surface: the null vector of H_free.
    pub fn free_surface_vector(&self) -> Option<Vector4<C64>> {
        let v_t = self.free.svd(false, true).v_t?;
        Some(v_t.row(3).adjoint())
    }

    /// The surface vector U₀ = (u, 0) of the metallized surface.
    pub fn metallized_surface_vector(&self) -> Option<Vector4<C64>> {
        let v_t = self.metallized.svd(false, true).v_t?;
        let u: Vector3<C64> = v_t.row(2).adjoint();
        Some(Vector4::new(u[0], u[1], u[2], C64::new(0.0, 0.0)))
    }
}
