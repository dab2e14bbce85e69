//! Linear elastic materials and their 6×6 Voigt stiffness.
//!
//! Voigt order used throughout the crate: `[xx, yy, zz, yz, xz, xy]`, with engineering shear
//! strains (γ_yz = 2 ε_yz). Stress σ = C ε.

use nalgebra::{Matrix3, SMatrix};

use crate::error::{FemError, FemResult};

/// 6×6 stiffness in Voigt notation (Pa).
pub type VoigtStiffness = SMatrix<f64, 6, 6>;

/// Largest deviation of `RᵀR` from the identity (and of det R from 1) accepted for a crystal
/// rotation. Dimensionless; default 1e-9.
pub const ROTATION_ORTHONORMALITY_TOLERANCE: f64 = 1e-9;

/// Isotropic Lamé parameters (Pa): σ = λ tr(ε) I + 2 μ ε.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LameParameters {
    /// Shear modulus μ = G (Pa).
    pub mu: f64,
    /// First Lamé parameter λ (Pa).
    pub lambda: f64,
}

fn check_poisson(nu: f64) -> FemResult<()> {
    if !nu.is_finite() {
        return Err(FemError::InvalidMaterialParameter {
            parameter: "poisson_ratio",
            value: nu,
            reason: "not finite",
        });
    }
    if nu <= -1.0 || nu >= 0.5 {
        return Err(FemError::InvalidMaterialParameter {
            parameter: "poisson_ratio",
            value: nu,
            reason: "must lie in the open interval (-1, 0.5)",
        });
    }
    Ok(())
}

fn check_positive_modulus(parameter: &'static str, value: f64) -> FemResult<()> {
    if !value.is_finite() {
        return Err(FemError::InvalidMaterialParameter {
            parameter,
            value,
            reason: "not finite",
        });
    }
    if value <= 0.0 {
        return Err(FemError::InvalidMaterialParameter {
            parameter,
            value,
            reason: "must be positive",
        });
    }
    Ok(())
}

impl LameParameters {
    /// From Young's modulus E (Pa) and Poisson's ratio ν ∈ (−1, ½):
    /// μ = E / (2(1+ν)), λ = E ν / ((1+ν)(1−2ν)).
    pub fn from_young_poisson(young_modulus_pa: f64, poisson_ratio: f64) -> FemResult<Self> {
        check_positive_modulus("young_modulus_pa", young_modulus_pa)?;
        check_poisson(poisson_ratio)?;
        let e = young_modulus_pa;
        let nu = poisson_ratio;
        Ok(Self {
            mu: e / (2.0 * (1.0 + nu)),
            lambda: e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        })
    }

    /// From shear modulus G (Pa) and Poisson's ratio ν ∈ (−1, ½): μ = G, λ = 2 G ν / (1 − 2ν).
    pub fn from_shear_poisson(shear_modulus_pa: f64, poisson_ratio: f64) -> FemResult<Self> {
        check_positive_modulus("shear_modulus_pa", shear_modulus_pa)?;
        check_poisson(poisson_ratio)?;
        let g = shear_modulus_pa;
        let nu = poisson_ratio;
        Ok(Self {
            mu: g,
            lambda: 2.0 * g * nu / (1.0 - 2.0 * nu),
        })
    }

    /// Young's modulus E = μ (3λ + 2μ) / (λ + μ) (Pa).
    pub fn young_modulus_pa(&self) -> f64 {
        self.mu * (3.0 * self.lambda + 2.0 * self.mu) / (self.lambda + self.mu)
    }

    /// Poisson's ratio ν = λ / (2(λ + μ)).
    pub fn poisson_ratio(&self) -> f64 {
        self.lambda / (2.0 * (self.lambda + self.mu))
    }

    /// Bulk modulus K = λ + 2μ/3 (Pa).
    pub fn bulk_modulus_pa(&self) -> f64 {
        self.lambda + 2.0 * self.mu / 3.0
    }

    /// The isotropic Voigt stiffness.
    pub fn voigt_stiffness(&self) -> VoigtStiffness {
        let (l, m) = (self.lambda, self.mu);
        let mut c = VoigtStiffness::zeros();
        for i in 0..3 {
            for j in 0..3 {
                c[(i, j)] = l;
            }
            c[(i, i)] = l + 2.0 * m;
            c[(i + 3, i + 3)] = m;
        }
        c
    }
}

/// A cubic crystal (e.g. silicon) with its crystal axes rotated into the global frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubicCrystal {
    /// C11 in the crystal frame (Pa).
    pub c11_pa: f64,
    /// C12 in the crystal frame (Pa).
    pub c12_pa: f64,
    /// C44 in the crystal frame (Pa).
    pub c44_pa: f64,
    /// Rotation R whose columns are the crystal axes \[100\], \[010\], \[001\] expressed in global
    /// coordinates: v_global = R v_crystal.
    pub rotation: Matrix3<f64>,
}

impl CubicCrystal {
    /// A cubic crystal, validated: C44 > 0, C11 − C12 > 0, C11 + 2 C12 > 0 (positive
    /// definiteness), R orthonormal with det R = +1.
    pub fn new(c11_pa: f64, c12_pa: f64, c44_pa: f64, rotation: Matrix3<f64>) -> FemResult<Self> {
        for (parameter, value) in [("c11_pa", c11_pa), ("c12_pa", c12_pa), ("c44_pa", c44_pa)] {
            if !value.is_finite() {
                return Err(FemError::InvalidMaterialParameter {
                    parameter,
                    value,
                    reason: "not finite",
                });
            }
        }
        check_positive_modulus("c44_pa", c44_pa)?;
        if c11_pa - c12_pa <= 0.0 {
            return Err(FemError::InvalidMaterialParameter {
                parameter: "c12_pa",
                value: c12_pa,
                reason: "C11 - C12 must be positive",
            });
        }
        if c11_pa + 2.0 * c12_pa <= 0.0 {
            return Err(FemError::InvalidMaterialParameter {
                parameter: "c12_pa",
                value: c12_pa,
                reason: "C11 + 2 C12 must be positive",
            });
        }
        if rotation.iter().any(|v| !v.is_finite())
            || (rotation.transpose() * rotation - Matrix3::identity()).amax()
                > ROTATION_ORTHONORMALITY_TOLERANCE
            || (rotation.determinant() - 1.0).abs() > ROTATION_ORTHONORMALITY_TOLERANCE
        {
            return Err(FemError::InvalidMaterialParameter {
                parameter: "rotation",
                value: rotation.determinant(),
                reason: "must be a proper rotation (orthonormal, det = +1); value shown is det R",
            });
        }
        Ok(Self {
            c11_pa,
            c12_pa,
            c44_pa,
            rotation,
        })
    }

    /// Silicon with crystal axes along the global axes (<100> orientation). Constants from
    /// docs/physics.md §2: C11 = 165.7, C12 = 63.9, C44 = 79.6 GPa.
    pub fn silicon_100() -> Self {
        Self {
            c11_pa: 165.7e9,
            c12_pa: 63.9e9,
            c44_pa: 79.6e9,
            rotation: Matrix3::identity(),
        }
    }

    /// Rotation by `angle_rad` about the global z axis (convenience for in-plane orientations).
    pub fn rotation_about_z(angle_rad: f64) -> Matrix3<f64> {
        let (s, c) = angle_rad.sin_cos();
        Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
    }

    /// The Voigt stiffness in the global frame: C'_ijkl = R_ip R_jq R_kr R_ls C_pqrs.
    pub fn voigt_stiffness(&self) -> VoigtStiffness {
        let mut crystal = [[[[0.0f64; 3]; 3]; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                for k in 0..3 {
                    for l in 0..3 {
                        let v = if i == j && k == l {
                            if i == k { self.c11_pa } else { self.c12_pa }
                        } else if (i == k && j == l) || (i == l && j == k) {
                            self.c44_pa
                        } else {
                            0.0
                        };
                        crystal[i][j][k][l] = v;
                    }
                }
            }
        }
        let r = &self.rotation;
        // Rotate one index at a time (4 × 3⁵ operations instead of 3⁸).
        let mut a = crystal;
        for slot in 0..4 {
            let mut b = [[[[0.0f64; 3]; 3]; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    for k in 0..3 {
                        for l in 0..3 {
                            let idx = [i, j, k, l];
                            let mut s = 0.0;
                            for p in 0..3 {
                                let mut src = idx;
                                src[slot] = p;
                                s += r[(idx[slot], p)] * a[src[0]][src[1]][src[2]][src[3]];
                            }
                            b[i][j][k][l] = s;
                        }
                    }
                }
            }
            a = b;
        }
        let mut c = VoigtStiffness::zeros();
        for (m, &(i, j)) in VOIGT_PAIRS.iter().enumerate() {
            for (n, &(k, l)) in VOIGT_PAIRS.iter().enumerate() {
                c[(m, n)] = a[i][j][k][l];
            }
        }
        c
    }
}

/// Tensor index pairs of the Voigt components `[xx, yy, zz, yz, xz, xy]`.
pub const VOIGT_PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];

/// A linear elastic material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// Isotropic, given by its Lamé parameters.
    Isotropic(LameParameters),
    /// Cubic crystal with orientation.
    Cubic(CubicCrystal),
}

impl Material {
    /// Isotropic material from E (Pa) and ν.
    pub fn isotropic(young_modulus_pa: f64, poisson_ratio: f64) -> FemResult<Self> {
        Ok(Self::Isotropic(LameParameters::from_young_poisson(
            young_modulus_pa,
            poisson_ratio,
        )?))
    }

    /// Checks a material whose fields were set directly: finite constants, μ > 0 and bulk
    /// modulus λ + 2μ/3 > 0 (isotropic), or the [`CubicCrystal::new`] conditions.
    pub fn validate(&self) -> FemResult<()> {
        match self {
            Material::Isotropic(l) => {
                check_positive_modulus("mu", l.mu)?;
                if !l.lambda.is_finite() {
                    return Err(FemError::InvalidMaterialParameter {
                        parameter: "lambda",
                        value: l.lambda,
                        reason: "not finite",
                    });
                }
                if l.bulk_modulus_pa() <= 0.0 {
                    return Err(FemError::InvalidMaterialParameter {
                        parameter: "lambda",
                        value: l.lambda,
                        reason: "bulk modulus lambda + 2 mu / 3 must be positive",
                    });
                }
                Ok(())
            }
            Material::Cubic(c) => {
                CubicCrystal::new(c.c11_pa, c.c12_pa, c.c44_pa, c.rotation).map(|_| ())
            }
        }
    }

    /// The 6×6 Voigt stiffness in global coordinates (Pa).
    pub fn voigt_stiffness(&self) -> VoigtStiffness {
        match self {
            Material::Isotropic(l) => l.voigt_stiffness(),
            Material::Cubic(c) => c.voigt_stiffness(),
        }
    }
}

impl From<LameParameters> for Material {
    fn from(value: LameParameters) -> Self {
        Material::Isotropic(value)
    }
}

impl From<CubicCrystal> for Material {
    fn from(value: CubicCrystal) -> Self {
        Material::Cubic(value)
    }
}

/// von Mises equivalent stress of a Voigt stress `[xx, yy, zz, yz, xz, xy]` (Pa):
/// σ_vm = √(½[(σxx−σyy)² + (σyy−σzz)² + (σzz−σxx)²] + 3(σyz² + σxz² + σxy²)).
pub fn von_mises(stress: &[f64; 6]) -> f64 {
    let [xx, yy, zz, yz, xz, xy] = *stress;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2))
        + 3.0 * (yz * yz + xz * xz + xy * xy))
        .sqrt()
}
