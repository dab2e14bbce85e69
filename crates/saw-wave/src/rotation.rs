//! Euler angles of a crystal cut and the rotation of material tensors into the wave frame.
//!
//! Formula: the wave frame x′ is obtained from the crystal frame x by three passive rotations,
//! ZXZ: x′ = a·x with a = R_z(ψ)·R_x(θ)·R_z(φ), where R_z(α) = [[cos α, sin α, 0], [−sin α, cos α, 0],
//! [0, 0, 1]] and R_x(α) = [[1, 0, 0], [0, cos α, sin α], [0, −sin α, cos α]]. Tensors transform as
//! c′_ijkl = a_ip a_jq a_kr a_ls c_pqrs, e′_ijk = a_ip a_jq a_kr e_pqr, ε′_ij = a_ip a_jq ε_pq.
//! In the wave frame x′₁ is the propagation direction and x′₃ the outward surface normal (the
//! crystal fills x′₃ < 0).
//!
//! Source: the standard SAW Euler-angle convention (A. J. Slobodnik, E. D. Conway, R. T. Delmonico,
//! *Microwave Acoustics Handbook* vol. 1A, AFCRL 1973; IEEE Std 176-1987 for the crystal axes). In
//! it a θ-rotated Y-cut with X propagation is (0°, θ − 90°, 0°): 128° Y-X is (0°, 38°, 0°), ST-X
//! quartz (0°, 132.75°, 0°), Y-cut Z-propagating (0°, 90°, 90°).
//!
//! Range of validity: any finite angles (degrees).

/// Voigt index of the symmetric tensor index pair (i, j), 0-based: 11→0, 22→1, 33→2, 23→3, 13→4, 12→5.
pub(crate) const fn voigt(i: usize, j: usize) -> usize {
    match (i, j) {
        (0, 0) => 0,
        (1, 1) => 1,
        (2, 2) => 2,
        (1, 2) | (2, 1) => 3,
        (0, 2) | (2, 0) => 4,
        _ => 5,
    }
}

/// Euler angles (ZXZ, degrees) of the wave frame relative to the crystal axes.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct EulerAngles {
    /// First rotation, about the crystal Z axis (degrees).
    pub phi_deg: f64,
    /// Second rotation, about the new X axis (degrees).
    pub theta_deg: f64,
    /// Third rotation, about the new Z axis, i.e. the surface normal (degrees).
    pub psi_deg: f64,
}

impl EulerAngles {
    /// Euler angles (φ, θ, ψ) in degrees.
    pub const fn new(phi_deg: f64, theta_deg: f64, psi_deg: f64) -> Self {
        Self {
            phi_deg,
            theta_deg,
            psi_deg,
        }
    }

    /// The rotation matrix `a` with x′_i = a_ij x_j (rows: wave-frame axes in crystal coordinates).
    pub fn rotation_matrix(&self) -> [[f64; 3]; 3] {
        let rz = |deg: f64| {
            let (s, c) = deg.to_radians().sin_cos();
            [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]
        };
        let (s, c) = self.theta_deg.to_radians().sin_cos();
        let rx = [[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]];
        mat_mul(&mat_mul(&rz(self.psi_deg), &rx), &rz(self.phi_deg))
    }
}

fn mat_mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, value) in row.iter_mut().enumerate() {
            *value = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    out
}

/// c′ = a⊗a⊗a⊗a : c for a Voigt stiffness (6×6).
pub(crate) fn rotate_stiffness(c: &[[f64; 6]; 6], a: &[[f64; 3]; 3]) -> [[f64; 6]; 6] {
    let full = |i, j, k, l| c[voigt(i, j)][voigt(k, l)];
    let mut out = [[0.0; 6]; 6];
    for (i, j) in VOIGT_PAIRS {
        for (k, l) in VOIGT_PAIRS {
            let mut sum = 0.0;
            for p in 0..3 {
                for q in 0..3 {
                    let apq = a[i][p] * a[j][q];
                    for r in 0..3 {
                        for s in 0..3 {
                            sum += apq * a[k][r] * a[l][s] * full(p, q, r, s);
                        }
                    }
                }
            }
            out[voigt(i, j)][voigt(k, l)] = sum;
        }
    }
    out
}

/// e′ = a⊗a⊗a : e for a Voigt piezoelectric matrix (3×6, e_iJ with J the strain pair).
pub(crate) fn rotate_piezo(e: &[[f64; 6]; 3], a: &[[f64; 3]; 3]) -> [[f64; 6]; 3] {
    let mut out = [[0.0; 6]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, k) in VOIGT_PAIRS {
            let mut sum = 0.0;
            for p in 0..3 {
                for q in 0..3 {
                    for r in 0..3 {
                        sum += a[i][p] * a[j][q] * a[k][r] * e[p][voigt(q, r)];
                    }
                }
            }
            row[voigt(j, k)] = sum;
        }
    }
    out
}

/// ε′ = a·ε·aᵀ.
pub(crate) fn rotate_second_rank(eps: &[[f64; 3]; 3], a: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, value) in row.iter_mut().enumerate() {
            *value = (0..3)
                .flat_map(|p| (0..3).map(move |q| (p, q)))
                .map(|(p, q)| a[i][p] * a[j][q] * eps[p][q])
                .sum();
        }
    }
    out
}

/// The six index pairs (i ≤ j) in Voigt order.
const VOIGT_PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_matrix_is_orthonormal_with_unit_determinant() {
        let a = EulerAngles::new(17.0, 38.0, -71.0).rotation_matrix();
        for i in 0..3 {
            for j in 0..3 {
                let dot: f64 = (0..3).map(|k| a[i][k] * a[j][k]).sum();
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((dot - expected).abs() < 1e-15, "row {i}·row {j} = {dot}");
            }
        }
        let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        assert!((det - 1.0).abs() < 1e-15, "determinant {det}");
    }

    #[test]
    fn rotated_y_cut_normal_is_y_turned_toward_z() {
        // 128° Y-X: the outward normal x′₃ is Y rotated by 128° about X toward Z.
        let a = EulerAngles::new(0.0, 38.0, 0.0).rotation_matrix();
        let (s, c) = 128f64.to_radians().sin_cos();
        let normal = a[2];
        assert!(
            (normal[0]).abs() < 1e-15
                && (normal[1] - c).abs() < 1e-15
                && (normal[2] - s).abs() < 1e-15,
            "normal {normal:?}"
        );
        assert_eq!(a[0], [1.0, 0.0, 0.0], "propagation direction must stay X");
    }

    #[test]
    fn quarter_turn_about_z_swaps_c11_and_c22_and_keeps_c66() {
        let mut c = [[0.0; 6]; 6];
        for (i, row) in c.iter_mut().enumerate() {
            row[i] = 1.0 + i as f64;
        }
        c[0][1] = 0.3;
        c[1][0] = 0.3;
        let rotated = rotate_stiffness(&c, &EulerAngles::new(90.0, 0.0, 0.0).rotation_matrix());
        assert!(
            (rotated[0][0] - 2.0).abs() < 1e-14 && (rotated[1][1] - 1.0).abs() < 1e-14,
            "c11/c22 {rotated:?}"
        );
        assert!(
            (rotated[5][5] - 6.0).abs() < 1e-14 && (rotated[3][3] - 5.0).abs() < 1e-14,
            "c66/c44 {rotated:?}"
        );
    }
}
