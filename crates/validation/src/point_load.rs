//! Displacement fields of a point force on the surface of an elastic half-space: Boussinesq
//! (normal force) and Cerruti (tangential force), Johnson, *Contact Mechanics* (1985) ch. 3,
//! written in this workspace's frame: the solid is z ≤ 0, z points out of it
//! (docs/physics.md §4). With ζ = −z the depth, ρ = |x| and G, ν the shear modulus and Poisson ratio,
//! a unit force pushing **into** the solid (direction −z) gives
//!
//! u_x = [x ζ/ρ³ − (1−2ν) x/(ρ(ρ+ζ))] / (4πG),  u_y likewise with y,
//! u_ζ = [ζ²/ρ³ + 2(1−ν)/ρ] / (4πG),  u_z = −u_ζ,
//!
//! and a unit force along +x on the surface gives
//!
//! u_x = [1/ρ + x²/ρ³ + (1−2ν)(1/(ρ+ζ) − x²/(ρ(ρ+ζ)²))] / (4πG),
//! u_y = [x y/ρ³ − (1−2ν) x y/(ρ(ρ+ζ)²)] / (4πG),
//! u_ζ = [x ζ/ρ³ + (1−2ν) x/(ρ(ρ+ζ))] / (4πG),  u_z = −u_ζ.
//!
//! Valid for ρ > 0. Far from a loaded punch of radius a (ρ ≫ a) the punch's field is the point
//! force field of its resultant plus terms of relative order a/ρ (force dipoles, e.g. the tilting
//! moment of the bonded tangential punch); prescribing this field on the truncation surface
//! ρ = R instead of clamping it cuts the truncation error of the stiffness from O(a/R) to
//! O((a/R)²) (see [`crate::punch`]).

/// Unit force at the origin on the surface z = 0 of the half-space z ≤ 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointForce {
    /// Unit normal force pushing into the solid (along −z): Boussinesq.
    NormalIntoSolid,
    /// Unit tangential force along +x: Cerruti.
    TangentialX,
}

impl PointForce {
    /// The unit vector of the force in the global frame.
    pub fn direction(&self) -> [f64; 3] {
        match self {
            PointForce::NormalIntoSolid => [0.0, 0.0, -1.0],
            PointForce::TangentialX => [1.0, 0.0, 0.0],
        }
    }

    /// Displacement (m per N of force) at `point` (m, z ≤ 0, not the origin) of a half-space with
    /// shear modulus `shear_modulus_pa` and Poisson ratio `poisson_ratio`. Returns `None` at the
    /// origin or above the surface.
    pub fn displacement_m_per_n(
        &self,
        point: [f64; 3],
        shear_modulus_pa: f64,
        poisson_ratio: f64,
    ) -> Option<[f64; 3]> {
        let [x, y, z] = point;
        let zeta = -z;
        let rho = (x * x + y * y + z * z).sqrt();
        // A point above the surface beyond round-off of the mesh coordinates is outside the solid.
        if rho == 0.0 || zeta < -ABOVE_SURFACE_TOLERANCE * rho {
            return None;
        }
        let zeta = zeta.max(0.0);
        let nu = poisson_ratio;
        let c = 1.0 / (4.0 * std::f64::consts::PI * shear_modulus_pa);
        let rho3 = rho * rho * rho;
        let rz = rho + zeta;
        let m = 1.0 - 2.0 * nu;
        Some(match self {
            PointForce::NormalIntoSolid => {
                let radial = zeta / rho3 - m / (rho * rz);
                let u_zeta = zeta * zeta / rho3 + 2.0 * (1.0 - nu) / rho;
                [c * x * radial, c * y * radial, -c * u_zeta]
            }
            PointForce::TangentialX => {
                let u_x = 1.0 / rho + x * x / rho3 + m * (1.0 / rz - x * x / (rho * rz * rz));
                let u_y = x * y / rho3 - m * x * y / (rho * rz * rz);
                let u_zeta = x * zeta / rho3 + m * x / (rho * rz);
                [c * u_x, c * u_y, -c * u_zeta]
            }
        })
    }
}

/// Relative height above the surface z = 0 (in units of ρ) still accepted as "on the surface"
/// (mesh round-off). Dimensionless; default 1e-9.
pub const ABOVE_SURFACE_TOLERANCE: f64 = 1e-9;

#[cfg(test)]
mod tests {
    use super::*;

    const G: f64 = 1.0;
    const NU: f64 = 0.27;
    /// Finite-difference step relative to the distance from the origin.
    const STEP: f64 = 1e-4;

    fn lame_lambda() -> f64 {
        2.0 * G * NU / (1.0 - 2.0 * NU)
    }

    fn gradient(force: PointForce, p: [f64; 3]) -> [[f64; 3]; 3] {
        let rho = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        let h = STEP * rho;
        let mut grad = [[0.0; 3]; 3];
        for j in 0..3 {
            let mut plus = p;
            let mut minus = p;
            plus[j] += h;
            minus[j] -= h;
            let up = force.displacement_m_per_n(plus, G, NU).unwrap();
            let um = force.displacement_m_per_n(minus, G, NU).unwrap();
            for i in 0..3 {
                grad[i][j] = (up[i] - um[i]) / (2.0 * h);
            }
        }
        grad
    }

    fn stress(force: PointForce, p: [f64; 3]) -> [[f64; 3]; 3] {
        let g = gradient(force, p);
        let div = g[0][0] + g[1][1] + g[2][2];
        let mut s = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                s[i][j] = G * (g[i][j] + g[j][i]) + if i == j { lame_lambda() * div } else { 0.0 };
            }
        }
        s
    }

    /// Navier's equation G ∇²u + (λ + G) ∇(∇·u) = 0, checked as div σ = 0 by central differences
    /// of the stress, relative to |σ|/ρ.
    #[test]
    fn point_force_fields_satisfy_navier_equilibrium() {
        for force in [PointForce::NormalIntoSolid, PointForce::TangentialX] {
            for p in [[0.3f64, 0.2, -0.5], [-0.7, 0.4, -0.1], [0.2, -0.9, -1.3]] {
                let rho = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                let h = 1e-3 * rho;
                let mut div = [0.0; 3];
                for j in 0..3 {
                    let mut plus = p;
                    let mut minus = p;
                    plus[j] += h;
                    minus[j] -= h;
                    let sp = stress(force, plus);
                    let sm = stress(force, minus);
                    for i in 0..3 {
                        div[i] += (sp[i][j] - sm[i][j]) / (2.0 * h);
                    }
                }
                let scale = stress(force, p)
                    .iter()
                    .flatten()
                    .map(|v| v.abs())
                    .fold(0.0, f64::max)
                    / rho;
                for (i, d) in div.iter().enumerate() {
                    assert!(
                        d.abs() < 1e-4 * scale,
                        "{force:?}: div σ_{i} = {d} at {p:?} (scale {scale})"
                    );
                }
            }
        }
    }

    /// The surface z = 0 is traction-free away from the load: σ_xz = σ_yz = σ_zz = 0. Checked just
    /// below the surface (the central differences must stay inside the solid), where the
    /// traction is O(depth/ρ) of the stress scale.
    #[test]
    fn point_force_fields_leave_the_surface_traction_free() {
        for force in [PointForce::NormalIntoSolid, PointForce::TangentialX] {
            for (x, y) in [(0.5f64, 0.3f64), (-0.2, 0.8)] {
                let rho = x.hypot(y);
                let p = [x, y, -2.0 * STEP * rho];
                let s = stress(force, p);
                let scale = s.iter().flatten().map(|v| v.abs()).fold(0.0, f64::max);
                for (i, row) in s.iter().enumerate() {
                    assert!(
                        row[2].abs() < 1e-3 * scale,
                        "{force:?}: surface traction σ_{i}z = {} at {p:?} (scale {scale})",
                        row[2]
                    );
                }
            }
        }
    }

    /// The traction on a hemisphere ρ = 1 around the load balances the unit force: the force the
    /// outer material exerts on the inner hemisphere, ∫ σ n dA (n outward), equals −direction.
    #[test]
    fn point_force_fields_carry_a_unit_resultant_along_their_direction() {
        // Gauss–Legendre nodes/weights on [−1, 1] (8 points) for the polar angle, midpoint rule in azimuth.
        let gl: [(f64, f64); 8] = [
            (-0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
            (-0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
            (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
            (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
            (0.183_434_642_495_649_8, 0.362_683_783_378_362),
            (0.525_532_409_916_329, 0.313_706_645_877_887_3),
            (0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
            (0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
        ];
        let n_phi = 64;
        for force in [PointForce::NormalIntoSolid, PointForce::TangentialX] {
            let mut total = [0.0; 3];
            // Polar angle θ from the inward normal −z (θ = 0) to the surface (θ = π/2); composite
            // rule over 4 panels because the integrand varies strongly near the surface.
            let panels = 4;
            for panel in 0..panels {
                let (t0, t1) = (
                    panel as f64 * std::f64::consts::FRAC_PI_2 / panels as f64,
                    (panel + 1) as f64 * std::f64::consts::FRAC_PI_2 / panels as f64,
                );
                for &(xi, w) in &gl {
                    let theta = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * xi;
                    let wt = 0.5 * (t1 - t0) * w;
                    for k in 0..n_phi {
                        let phi = (k as f64 + 0.5) * 2.0 * std::f64::consts::PI / n_phi as f64;
                        let n = [
                            theta.sin() * phi.cos(),
                            theta.sin() * phi.sin(),
                            -theta.cos(),
                        ];
                        let s = stress(force, n);
                        let da = theta.sin() * wt * 2.0 * std::f64::consts::PI / n_phi as f64;
                        for i in 0..3 {
                            total[i] += (s[i][0] * n[0] + s[i][1] * n[1] + s[i][2] * n[2]) * da;
                        }
                    }
                }
            }
            let d = force.direction();
            for i in 0..3 {
                assert!(
                    (total[i] + d[i]).abs() < 2e-3,
                    "{force:?}: hemisphere traction resultant {total:?} should be −{d:?}"
                );
            }
        }
    }

    #[test]
    fn point_force_field_is_undefined_at_the_origin_and_above_the_surface() {
        assert!(
            PointForce::NormalIntoSolid
                .displacement_m_per_n([0.0; 3], G, NU)
                .is_none(),
            "displacement at the load point"
        );
        assert!(
            PointForce::TangentialX
                .displacement_m_per_n([0.0, 0.0, 0.1], G, NU)
                .is_none(),
            "displacement above the surface"
        );
    }
}
