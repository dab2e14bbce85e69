//! A linear piezoelectric crystal: stiffness, piezoelectric stress constants, permittivity, density.
//!
//! Formula: the constitutive law in stress–charge form, T_I = c^E_IJ S_J − e_kI E_k and
//! D_i = e_iJ S_J + ε^S_ik E_k (Voigt indices I, J = 1…6 with engineering shear strains,
//! E = −∇φ). Source: IEEE Std 176-1987 (*Standard on Piezoelectricity*); B. A. Auld, *Acoustic
//! Fields and Waves in Solids*, vol. I (Wiley 1973), ch. 8. The constants must be the
//! constant-field stiffness c^E and the clamped (constant-strain) permittivity ε^S.
//!
//! Range of validity: small-signal linear piezoelectricity of a lossless, homogeneous crystal;
//! stiffness and permittivity symmetric positive definite, density positive (checked by
//! [`Material::validate`]).

use crate::error::WaveError;
use crate::rotation::{EulerAngles, rotate_piezo, rotate_second_rank, rotate_stiffness};
use nalgebra::DMatrix;

/// Vacuum permittivity ε0 (F/m), CODATA 2018.
pub const VACUUM_PERMITTIVITY_F_PER_M: f64 = 8.854_187_812_8e-12;

/// Relative tolerance of the symmetry check of stiffness and permittivity.
const SYMMETRY_TOLERANCE: f64 = 1e-9;

/// A piezoelectric crystal in some frame (crystal axes, or the wave frame after [`Material::rotated`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Material {
    /// Name, with the source of its constants.
    pub name: String,
    /// Elastic stiffness at constant electric field c^E_IJ (Voigt 6×6, Pa).
    pub stiffness_pa: [[f64; 6]; 6],
    /// Piezoelectric stress constants e_iJ (3×6, C/m²).
    pub piezo_c_per_m2: [[f64; 6]; 3],
    /// Permittivity at constant strain ε^S_ij (3×3, F/m).
    pub permittivity_f_per_m: [[f64; 3]; 3],
    /// Mass density (kg/m³).
    pub density_kg_per_m3: f64,
}

impl Material {
    /// A material from its full matrices, validated.
    pub fn new(
        name: impl Into<String>,
        stiffness_pa: [[f64; 6]; 6],
        piezo_c_per_m2: [[f64; 6]; 3],
        permittivity_f_per_m: [[f64; 3]; 3],
        density_kg_per_m3: f64,
    ) -> Result<Self, WaveError> {
        let material = Self {
            name: name.into(),
            stiffness_pa,
            piezo_c_per_m2,
            permittivity_f_per_m,
            density_kg_per_m3,
        };
        material.validate()?;
        Ok(material)
    }

    /// An isotropic, non-piezoelectric solid from its Lamé constants (Pa) and an isotropic
    /// relative permittivity.
    pub fn isotropic(
        name: impl Into<String>,
        lambda_pa: f64,
        shear_modulus_pa: f64,
        density_kg_per_m3: f64,
        relative_permittivity: f64,
    ) -> Result<Self, WaveError> {
        let mut c = [[0.0; 6]; 6];
        for i in 0..3 {
            c[i][..3].fill(lambda_pa);
            c[i][i] = lambda_pa + 2.0 * shear_modulus_pa;
            c[i + 3][i + 3] = shear_modulus_pa;
        }
        let eps = relative_permittivity * VACUUM_PERMITTIVITY_F_PER_M;
        let permittivity = [[eps, 0.0, 0.0], [0.0, eps, 0.0], [0.0, 0.0, eps]];
        Self::new(name, c, [[0.0; 6]; 3], permittivity, density_kg_per_m3)
    }

    /// Trigonal class 3m (LiNbO3, LiTaO3) in the IEEE axes (x1 normal to a mirror plane):
    /// stiffness (c11, c12, c13, c14, c33, c44; c66 = (c11 − c12)/2, Pa), piezoelectric
    /// (e15, e22, e31, e33, C/m²), permittivity (ε11, ε33, F/m).
    pub fn trigonal_3m(
        name: impl Into<String>,
        [c11, c12, c13, c14, c33, c44]: [f64; 6],
        [e15, e22, e31, e33]: [f64; 4],
        [eps11, eps33]: [f64; 2],
        density_kg_per_m3: f64,
    ) -> Result<Self, WaveError> {
        let c = trigonal_stiffness(c11, c12, c13, c14, c33, c44);
        let e = [
            [0.0, 0.0, 0.0, 0.0, e15, -e22],
            [-e22, e22, 0.0, e15, 0.0, 0.0],
            [e31, e31, e33, 0.0, 0.0, 0.0],
        ];
        Self::new(name, c, e, diagonal(eps11, eps33), density_kg_per_m3)
    }

    /// Trigonal class 32 (α-quartz) in the IEEE axes: stiffness as for 3m, piezoelectric
    /// (e11, e14, C/m²), permittivity (ε11, ε33, F/m).
    pub fn trigonal_32(
        name: impl Into<String>,
        [c11, c12, c13, c14, c33, c44]: [f64; 6],
        [e11, e14]: [f64; 2],
        [eps11, eps33]: [f64; 2],
        density_kg_per_m3: f64,
    ) -> Result<Self, WaveError> {
        let c = trigonal_stiffness(c11, c12, c13, c14, c33, c44);
        let e = [
            [e11, -e11, 0.0, e14, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0, -e14, -e11],
            [0.0; 6],
        ];
        Self::new(name, c, e, diagonal(eps11, eps33), density_kg_per_m3)
    }

    /// The same crystal described in the wave frame of the Euler angles.
    pub fn rotated(&self, euler: &EulerAngles) -> Self {
        let a = euler.rotation_matrix();
        Self {
            name: self.name.clone(),
            stiffness_pa: rotate_stiffness(&self.stiffness_pa, &a),
            piezo_c_per_m2: rotate_piezo(&self.piezo_c_per_m2, &a),
            permittivity_f_per_m: rotate_second_rank(&self.permittivity_f_per_m, &a),
            density_kg_per_m3: self.density_kg_per_m3,
        }
    }

    /// Constant-stress permittivity ε^T = ε^S + e·s^E·eᵀ, s^E = (c^E)⁻¹ (F/m, same frame as
    /// `self`; IEEE Std 176-1987); `None` if the stiffness is singular.
    pub fn permittivity_stress_free_f_per_m(&self) -> Option<[[f64; 3]; 3]> {
        let compliance =
            nalgebra::Matrix6::from_fn(|i, j| self.stiffness_pa[i][j]).try_inverse()?;
        let e = nalgebra::Matrix3x6::from_fn(|i, j| self.piezo_c_per_m2[i][j]);
        let added = e * compliance * e.transpose();
        Some(std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                self.permittivity_f_per_m[i][j] + 0.5 * (added[(i, j)] + added[(j, i)])
            })
        }))
    }

    /// Checks finiteness, positive density, symmetry and positive definiteness.
    pub fn validate(&self) -> Result<(), WaveError> {
        self.check_finite()?;
        if self.density_kg_per_m3 <= 0.0 {
            return Err(WaveError::NonPositiveDensity {
                material: self.name.clone(),
                density_kg_per_m3: self.density_kg_per_m3,
            });
        }
        let c = DMatrix::from_fn(6, 6, |i, j| self.stiffness_pa[i][j]);
        let eps = DMatrix::from_fn(3, 3, |i, j| self.permittivity_f_per_m[i][j]);
        self.check_symmetric_positive("stiffness", c)?;
        self.check_symmetric_positive("permittivity", eps)
    }

    fn check_finite(&self) -> Result<(), WaveError> {
        let non_finite = |quantity: String, value: f64| WaveError::NonFinite {
            context: self.name.clone(),
            quantity,
            value,
        };
        for (i, row) in self.stiffness_pa.iter().enumerate() {
            for (j, &value) in row.iter().enumerate() {
                if !value.is_finite() {
                    return Err(non_finite(format!("stiffness c_{}{}", i + 1, j + 1), value));
                }
            }
        }
        for (i, row) in self.piezo_c_per_m2.iter().enumerate() {
            for (j, &value) in row.iter().enumerate() {
                if !value.is_finite() {
                    return Err(non_finite(
                        format!("piezoelectric e_{}{}", i + 1, j + 1),
                        value,
                    ));
                }
            }
        }
        for (i, row) in self.permittivity_f_per_m.iter().enumerate() {
            for (j, &value) in row.iter().enumerate() {
                if !value.is_finite() {
                    return Err(non_finite(
                        format!("permittivity eps_{}{}", i + 1, j + 1),
                        value,
                    ));
                }
            }
        }
        if !self.density_kg_per_m3.is_finite() {
            return Err(non_finite("density".into(), self.density_kg_per_m3));
        }
        Ok(())
    }

    fn check_symmetric_positive(
        &self,
        tensor: &'static str,
        m: DMatrix<f64>,
    ) -> Result<(), WaveError> {
        let scale = m.amax();
        for i in 0..m.nrows() {
            for j in 0..i {
                if (m[(i, j)] - m[(j, i)]).abs() > SYMMETRY_TOLERANCE * scale {
                    return Err(WaveError::NotSymmetric {
                        material: self.name.clone(),
                        tensor,
                        row: i + 1,
                        col: j + 1,
                    });
                }
            }
        }
        let smallest = m.symmetric_eigenvalues().min();
        if smallest <= 0.0 {
            return Err(WaveError::NotPositiveDefinite {
                material: self.name.clone(),
                tensor,
                smallest_eigenvalue: smallest,
            });
        }
        Ok(())
    }
}

/// The trigonal (classes 3m, 32, −3m) stiffness pattern with c66 = (c11 − c12)/2.
fn trigonal_stiffness(c11: f64, c12: f64, c13: f64, c14: f64, c33: f64, c44: f64) -> [[f64; 6]; 6] {
    let c66 = 0.5 * (c11 - c12);
    [
        [c11, c12, c13, c14, 0.0, 0.0],
        [c12, c11, c13, -c14, 0.0, 0.0],
        [c13, c13, c33, 0.0, 0.0, 0.0],
        [c14, -c14, 0.0, c44, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, c44, c14],
        [0.0, 0.0, 0.0, 0.0, c14, c66],
    ]
}

fn diagonal(eps11: f64, eps33: f64) -> [[f64; 3]; 3] {
    [[eps11, 0.0, 0.0], [0.0, eps11, 0.0], [0.0, 0.0, eps33]]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steel_like() -> Material {
        Material::isotropic("test solid", 100e9, 80e9, 7800.0, 1.0).unwrap()
    }

    #[test]
    fn non_positive_density_is_a_named_error() {
        let mut m = steel_like();
        m.density_kg_per_m3 = 0.0;
        let err = m.validate().unwrap_err();
        assert!(matches!(err, WaveError::NonPositiveDensity { .. }), "{err}");
        assert!(err.to_string().contains("test solid"), "{err}");
    }

    #[test]
    fn non_finite_constant_names_its_index() {
        let mut m = steel_like();
        m.piezo_c_per_m2[1][3] = f64::NAN;
        let err = m.validate().unwrap_err();
        assert!(err.to_string().contains("piezoelectric e_24"), "{err}");
    }

    #[test]
    fn asymmetric_and_indefinite_stiffness_are_rejected() {
        let mut m = steel_like();
        m.stiffness_pa[0][4] = 1e9;
        assert!(matches!(
            m.validate(),
            Err(WaveError::NotSymmetric { row: 5, col: 1, .. })
        ));
        let mut m = steel_like();
        m.stiffness_pa[3][3] = -1e9;
        assert!(matches!(
            m.validate(),
            Err(WaveError::NotPositiveDefinite {
                tensor: "stiffness",
                ..
            })
        ));
    }

    #[test]
    fn rotation_preserves_the_isotropic_stiffness() {
        let m = steel_like();
        let r = m.rotated(&EulerAngles::new(12.0, 57.0, -33.0));
        for i in 0..6 {
            for j in 0..6 {
                assert!(
                    (r.stiffness_pa[i][j] - m.stiffness_pa[i][j]).abs() < 1e-13 * 160e9,
                    "c_{}{}",
                    i + 1,
                    j + 1
                );
            }
        }
    }
}
