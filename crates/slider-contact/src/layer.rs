//! The slider body between posts: an elastic layer of thickness t bonded to a rigid back
//! ("rigid" preload mechanism, today's clamp of the strip FEM), loaded by normal point forces
//! on its free face, frictionless there.
//!
//! **Fourier-space influence function.** A surface pressure p̃(q) of wavenumber q = |q| on a
//! layer (shear modulus G, Poisson ratio ν) bonded to a rigid base at depth t displaces the
//! surface by ũ_z(q) = (1−ν)/(G q) · K(qt) p̃(q), with
//!
//! K(s) = [(3−4ν) sinh 2s − 2s] / [(3−4ν) cosh 2s + 2s² + ½(1 + (3−4ν)²)]
//!
//! (plane-strain solution per wavevector, which is exact in 3D because the problem of one
//! Fourier mode is plane strain along q: R. D. Mindlin-type layer solution in the form of
//! K. L. Johnson, *Contact Mechanics* (CUP 1985) §5.9 and O'Sullivan & King, J. Tribol. 110
//! (1988) 235, for the bonded base). Its limits are the checks of the tests: K → 1 for s → ∞ (the
//! half-space, (1−ν)/(Gq) = 2/(E*q)) and K → s(1−2ν)/(2(1−ν)²) for s → 0, i.e. ũ_z = p̃ t/M
//! with the confined (oedometric) modulus M = 2G(1−ν)/(1−2ν) of a thin bonded layer.
//!
//! **The split.** The half-space part is singular (1/r) and is taken in real space with the
//! posts' own shape (rigid disks, [`static_contact::halfspace`]); the rigid back adds the smooth
//! correction
//!
//! ΔK(r) = (1−ν)/(2πG) ∫₀^∞ (K(qt) − 1) J₀(qr) dq = (1−ν)/(2πGt) ∫₀^∞ (K(s) − 1) J₀(s r/t) ds,
//!
//! a Hankel transform whose integrand decays as s² e^{−2s}: ΔK varies on the scale t (0.5 mm,
//! 12.5 pitches), is finite at r = 0 and tends to −(1−ν)/(2πGr) for r ≫ t (the displacement of a
//! layer on a rigid base decays exponentially). It is tabulated once on a uniform radial grid by
//! Simpson's rule and interpolated by 4-point cubic Lagrange polynomials.
//!
//! Valid for a layer much wider than thick with loads farther than ≈ t from its edges (the free
//! edges of the real 5 mm slider, 0.5 mm margins, are not resolved: the layer is unbounded).

use crate::bessel::{j0, j2};

/// Upper end of the Hankel integral in s = qt: the integrand is below 1e-20 of its start there.
/// Dimensionless; default 30.
pub const HANKEL_S_MAX: f64 = 30.0;
/// Simpson step in s = qt. At the largest tabulated r/t (≈ 30 for the default slider) J₀ has a
/// period 2π/30 ≈ 0.21 in s, resolved by ≈ 40 steps. Dimensionless; default 0.005.
pub const HANKEL_S_STEP: f64 = 0.005;
/// Radial table spacing of ΔK in units of t; ΔK varies on the scale t, the cubic interpolation
/// error is ≈ (spacing)⁴ relative. Dimensionless; default 1/32.
pub const TABLE_SPACING_OVER_T: f64 = 1.0 / 32.0;
/// Smallest tabulated range in units of t; beyond the table ΔK is its asymptote
/// −(1−ν)/(2πGr) (the bonded layer's own displacement has decayed as e^{−r/t}). Default 16.
pub const TABLE_MIN_RANGE_OVER_T: f64 = 16.0;

/// K(s) of the module doc: surface compliance of the bonded layer relative to the half-space.
pub fn layer_factor(s: f64, poisson_ratio: f64) -> f64 {
    let k = 3.0 - 4.0 * poisson_ratio;
    let c0 = 0.5 * (1.0 + k * k);
    if s > 300.0 {
        return 1.0;
    }
    (k * (2.0 * s).sinh() - 2.0 * s) / (k * (2.0 * s).cosh() + 2.0 * s * s + c0)
}

/// K(s) − 1 written without cancellation for large s.
fn layer_factor_minus_one(s: f64, poisson_ratio: f64) -> f64 {
    let k = 3.0 - 4.0 * poisson_ratio;
    let c0 = 0.5 * (1.0 + k * k);
    // K − 1 = −[k e^{−2s} + 2s + 2s² + c0] / [k cosh 2s + 2s² + c0]; divide through by e^{2s}.
    let e = (-2.0 * s).exp();
    -(k * e * e + (2.0 * s + 2.0 * s * s + c0) * e)
        / (0.5 * k * (1.0 + e * e) + (2.0 * s * s + c0) * e)
}

/// K_L(s) of [`TangentialLayerCorrection`]: the in-plane (along q) tangential surface
/// compliance of the bonded layer relative to the half-space's (1−ν)/(Gq).
pub fn tangential_layer_factor(s: f64, poisson_ratio: f64) -> f64 {
    let k = 3.0 - 4.0 * poisson_ratio;
    let c0 = 0.5 * (1.0 + k * k);
    if s > 300.0 {
        return 1.0;
    }
    (k * (2.0 * s).sinh() + 2.0 * s) / (k * (2.0 * s).cosh() + 2.0 * s * s + c0)
}

/// K_L(s) − 1 without cancellation for large s.
fn tangential_layer_factor_minus_one(s: f64, poisson_ratio: f64) -> f64 {
    let k = 3.0 - 4.0 * poisson_ratio;
    let c0 = 0.5 * (1.0 + k * k);
    // K_L − 1 = [−k e^{−2s} + 2s − 2s² − c0] / [k cosh 2s + 2s² + c0]; divide through by e^{2s}.
    let e = (-2.0 * s).exp();
    (-k * e * e + (2.0 * s - 2.0 * s * s - c0) * e)
        / (0.5 * k * (1.0 + e * e) + (2.0 * s * s + c0) * e)
}

/// tanh(s) − 1 = −2e^{−2s}/(1 + e^{−2s}): the anti-plane (across q) tangential compliance of the
/// bonded layer, tanh(qt)/(Gq), relative to the half-space's 1/(Gq).
fn antiplane_factor_minus_one(s: f64) -> f64 {
    let e = (-2.0 * s).exp();
    -2.0 * e / (1.0 + e)
}

/// A radial Hankel transform F(r) = scale ∫₀^{s_max} f(s) J_n(s r/t) ds (n = 0 or 2) tabulated
/// on r = i·t/32 (Simpson's rule in s), interpolated by 4-point cubic Lagrange polynomials
/// (F is even in r), and beyond the table its far field −far_m/r (m/N).
#[derive(Debug, Clone)]
struct HankelTable {
    far_m: f64,
    spacing_m: f64,
    values_m_per_n: Vec<f64>,
}

impl HankelTable {
    fn new(
        order: u8,
        integrand: impl Fn(f64) -> f64,
        scale: f64,
        thickness_m: f64,
        r_max_m: f64,
        far_m: f64,
    ) -> Self {
        let steps = (HANKEL_S_MAX / HANKEL_S_STEP).round() as usize & !1;
        let ds = HANKEL_S_MAX / steps as f64;
        // Simpson weights × f(s), computed once for all r.
        let weighted: Vec<(f64, f64)> = (0..=steps)
            .map(|m| {
                let s = m as f64 * ds;
                let w = if m == 0 || m == steps {
                    1.0
                } else if m % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                (s, w * ds / 3.0 * integrand(s))
            })
            .collect();
        let bessel = if order == 0 { j0 } else { j2 };
        let spacing_m = TABLE_SPACING_OVER_T * thickness_m;
        let range_m = r_max_m.max(TABLE_MIN_RANGE_OVER_T * thickness_m);
        let points = (range_m / spacing_m).ceil() as usize + 4;
        let values_m_per_n = (0..points)
            .map(|i| {
                let rho = i as f64 * TABLE_SPACING_OVER_T;
                scale
                    * weighted
                        .iter()
                        .map(|&(s, w)| w * bessel(s * rho))
                        .sum::<f64>()
            })
            .collect();
        Self {
            far_m,
            spacing_m,
            values_m_per_n,
        }
    }

    fn at(&self, r_m: f64) -> f64 {
        let v = &self.values_m_per_n;
        let x = r_m.abs() / self.spacing_m;
        let i = x.floor() as usize;
        if i + 3 >= v.len() {
            return -self.far_m / r_m.abs();
        }
        if i == 0 {
            // Even extension across r = 0: nodes −1, 0, 1, 2 carry F at 1, 0, 1, 2.
            return lagrange4(&[-1.0, 0.0, 1.0, 2.0], &[v[1], v[0], v[1], v[2]], x);
        }
        let i0 = (i - 1).min(v.len() - 4);
        lagrange4(
            &[0.0, 1.0, 2.0, 3.0],
            &[v[i0], v[i0 + 1], v[i0 + 2], v[i0 + 3]],
            x - i0 as f64,
        )
    }
}

/// Tabulated smooth correction ΔK(r) (m/N) of a bonded layer over the half-space.
#[derive(Debug, Clone)]
pub struct LayerCorrection {
    thickness_m: f64,
    table: HankelTable,
}

impl LayerCorrection {
    /// Tabulates ΔK for 0 ≤ r ≤ `r_max_m` (layer of thickness t, shear modulus G, Poisson ν).
    pub fn new(shear_modulus_pa: f64, poisson_ratio: f64, thickness_m: f64, r_max_m: f64) -> Self {
        let scale =
            (1.0 - poisson_ratio) / (2.0 * std::f64::consts::PI * shear_modulus_pa * thickness_m);
        Self {
            thickness_m,
            table: HankelTable::new(
                0,
                |s| layer_factor_minus_one(s, poisson_ratio),
                scale,
                thickness_m,
                r_max_m,
                scale * thickness_m,
            ),
        }
    }

    /// Layer thickness t (m).
    pub fn thickness_m(&self) -> f64 {
        self.thickness_m
    }

    /// ΔK(r) (m/N) by cubic interpolation of the table (ΔK is even in r; beyond the table, its
    /// asymptote −(1−ν)/(2πGr)).
    pub fn at(&self, r_m: f64) -> f64 {
        self.table.at(r_m)
    }
}

/// The rigid-back correction of the **tangential** (x) compliance of the bonded layer:
/// ΔK_t(r, φ) = A(r) + B(r) cos 2φ (m/N), φ the angle of the offset from the x axis.
///
/// Per Fourier mode q = q(cos ψ, sin ψ) a surface shear traction τ̃ along x splits into a part
/// along q (plane strain: compliance (1−ν)/(Gq)·K_L(qt)) and one across q (anti-plane shear:
/// tanh(qt)/(Gq), the layer u = U sinh(q(t − z))/sinh(qt) fixed at the back), so
/// ũ_x = [(1−ν) K_L cos²ψ + tanh(qt) sin²ψ] τ̃/(Gq), with
///
/// K_L(s) = [(3−4ν) sinh 2s + 2s] / [(3−4ν) cosh 2s + 2s² + ½(1 + (3−4ν)²)]
///
/// (the same plane-strain layer solution as [`layer_factor`], tangential load; checked in the
/// tests against a direct solve of the plane-strain layer equations). Its limits: K_L → 1 for
/// s → ∞ (the half-space, whose inverse transform is Cerruti's u_x = [(1−ν) + ν cos²φ]/(2πGr),
/// Johnson eq. (3.86a)), and K_L → s/(1−ν) for s → 0 (ũ_x = τ̃ t/G: a thin bonded layer in
/// simple shear). With cos²ψ = ½(1 + cos 2ψ) and the Jacobi–Anger expansion, the half-space
/// subtracted:
///
/// A(r) = 1/(2πGt) ∫₀^∞ ½[(1−ν)(K_L − 1) + (tanh s − 1)] J₀(s r/t) ds,
/// B(r) = −1/(2πGt) ∫₀^∞ ½[(1−ν)(K_L − 1) − (tanh s − 1)] J₂(s r/t) ds,
///
/// both tabulated as ΔK (integrands ∝ e^{−2s}); far away A → −(2−ν)/(4πGr), B → −ν/(4πGr),
/// i.e. ΔK_t → −Cerruti (the bonded layer's displacement decays exponentially).
#[derive(Debug, Clone)]
pub struct TangentialLayerCorrection {
    isotropic: HankelTable,
    anisotropic: HankelTable,
}

impl TangentialLayerCorrection {
    /// Tabulates A and B for 0 ≤ r ≤ `r_max_m` (layer of thickness t, shear modulus G, ν).
    pub fn new(shear_modulus_pa: f64, poisson_ratio: f64, thickness_m: f64, r_max_m: f64) -> Self {
        let nu = poisson_ratio;
        let scale = 1.0 / (2.0 * std::f64::consts::PI * shear_modulus_pa * thickness_m);
        let plane = move |s: f64| (1.0 - nu) * tangential_layer_factor_minus_one(s, nu);
        Self {
            isotropic: HankelTable::new(
                0,
                |s| 0.5 * (plane(s) + antiplane_factor_minus_one(s)),
                scale,
                thickness_m,
                r_max_m,
                scale * thickness_m * 0.5 * (2.0 - nu),
            ),
            anisotropic: HankelTable::new(
                2,
                |s| -0.5 * (plane(s) - antiplane_factor_minus_one(s)),
                scale,
                thickness_m,
                r_max_m,
                scale * thickness_m * 0.5 * nu,
            ),
        }
    }

    /// ΔK_t at the offset (dx, dy) (m/N); at the origin A(0) (B(0) = 0).
    pub fn at(&self, dx_m: f64, dy_m: f64) -> f64 {
        let r2 = dx_m * dx_m + dy_m * dy_m;
        let r = r2.sqrt();
        let a = self.isotropic.at(r);
        if r2 == 0.0 {
            return a;
        }
        a + self.anisotropic.at(r) * (dx_m * dx_m - dy_m * dy_m) / r2
    }
}

fn lagrange4(nodes: &[f64; 4], vals: &[f64; 4], x: f64) -> f64 {
    (0..4)
        .map(|i| {
            let l: f64 = (0..4)
                .filter(|&j| j != i)
                .map(|j| (x - nodes[j]) / (nodes[i] - nodes[j]))
                .product();
            l * vals[i]
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    const G: f64 = 66.5e9;
    const NU: f64 = 0.22;
    const T: f64 = 0.5e-3;

    /// Surface compliances (u_x/τ, w/p) × Gq of the plane-strain layer (G = 1, q = 1, thickness s,
    /// bonded at z = s) from a direct solve of the layer's equations: state y = (U, W, σ_xz, σ_zz)
    /// of the mode u = U cos x, w = W sin x, y' = M y (Navier in first-order form), y(s) =
    /// exp(M s) y(0) by scaling and squaring, U(s) = W(s) = 0 solved for U(0), W(0).
    fn plane_strain_layer(s: f64, nu: f64, shear: bool) -> f64 {
        use nalgebra::{Matrix2, Matrix4, Vector2};
        let g = 1.0;
        let lambda = 2.0 * g * nu / (1.0 - 2.0 * nu);
        let l2g = lambda + 2.0 * g;
        let m = Matrix4::new(
            0.0,
            -1.0,
            1.0 / g,
            0.0,
            lambda / l2g,
            0.0,
            0.0,
            1.0 / l2g,
            l2g - lambda * lambda / l2g,
            0.0,
            0.0,
            -lambda / l2g,
            0.0,
            0.0,
            1.0,
            0.0,
        ) * s;
        let squarings = (m.norm().log2().ceil().max(0.0) as i32) + 4;
        let a = m / 2f64.powi(squarings);
        let mut e = Matrix4::identity();
        let mut term = Matrix4::identity();
        for k in 1..30 {
            term = term * a / k as f64;
            e += term;
        }
        for _ in 0..squarings {
            e = e * e;
        }
        // Surface tractions: shear τ = 1 (σ_xz(0) = −1) or pressure p = 1 (σ_zz(0) = −1).
        let (t0, s0) = if shear { (-1.0, 0.0) } else { (0.0, -1.0) };
        let lhs = Matrix2::new(e[(0, 0)], e[(0, 1)], e[(1, 0)], e[(1, 1)]);
        let rhs = -Vector2::new(
            e[(0, 2)] * t0 + e[(0, 3)] * s0,
            e[(1, 2)] * t0 + e[(1, 3)] * s0,
        );
        let uw = lhs.lu().solve(&rhs).expect("layer boundary system");
        if shear { uw[0] } else { uw[1] }
    }

    #[test]
    fn the_layer_factors_solve_the_plane_strain_layer_equations() {
        for s in [0.05, 0.3, 1.0, 2.0, 4.0] {
            let normal = plane_strain_layer(s, NU, false);
            let expected = (1.0 - NU) * layer_factor(s, NU);
            assert!(
                (normal / expected - 1.0).abs() < 1e-9,
                "normal layer compliance at s = {s}: ODE {normal} vs (1−ν)K {expected}"
            );
            let shear = plane_strain_layer(s, NU, true);
            let expected = (1.0 - NU) * tangential_layer_factor(s, NU);
            assert!(
                (shear / expected - 1.0).abs() < 1e-9,
                "tangential layer compliance at s = {s}: ODE {shear} vs (1−ν)K_L {expected}"
            );
        }
    }

    #[test]
    fn the_tangential_layer_factor_has_the_half_space_and_thin_shear_limits() {
        assert!(
            (tangential_layer_factor(20.0, NU) - 1.0).abs() < 1e-12,
            "K_L(20) of a thick layer"
        );
        let s = 1e-4;
        assert!(
            (tangential_layer_factor(s, NU) * (1.0 - NU) / s - 1.0).abs() < 1e-3,
            "thin layer in simple shear: (1−ν)K_L/s = {}",
            tangential_layer_factor(s, NU) * (1.0 - NU) / s
        );
        for s in [0.5, 3.0, 9.0] {
            assert!(
                (tangential_layer_factor_minus_one(s, NU) - (tangential_layer_factor(s, NU) - 1.0))
                    .abs()
                    < 1e-12,
                "the cancellation-free K_L − 1 at {s}"
            );
            assert!(
                (antiplane_factor_minus_one(s) - (s.tanh() - 1.0)).abs() < 1e-15,
                "tanh − 1 at {s}"
            );
        }
    }

    #[test]
    fn far_from_the_load_the_tangential_correction_cancels_cerruti() {
        let table = TangentialLayerCorrection::new(G, NU, T, 20.0 * T);
        for (dx, dy) in [(12.0 * T, 0.0), (0.0, 12.0 * T), (9.0 * T, 9.0 * T)] {
            let r = f64::hypot(dx, dy);
            let cerruti =
                ((1.0 - NU) + NU * dx * dx / (r * r)) / (2.0 * std::f64::consts::PI * G * r);
            assert!(
                (table.at(dx, dy) + cerruti).abs() < 1e-3 * cerruti,
                "ΔK_t({dx}, {dy}) = {} vs −Cerruti {}",
                table.at(dx, dy),
                -cerruti
            );
        }
        // At the origin the correction is finite, negative (the back stiffens) and isotropic.
        assert!(table.at(0.0, 0.0) < 0.0, "ΔK_t(0) = {}", table.at(0.0, 0.0));
        let (a, b) = (table.at(1e-3 * T, 0.0), table.at(0.0, 1e-3 * T));
        assert!(
            (a - b).abs() < 1e-6 * a.abs(),
            "ΔK_t near 0 along x {a} and y {b}"
        );
    }

    #[test]
    fn a_thick_layer_is_the_half_space() {
        assert!(
            (layer_factor(20.0, NU) - 1.0).abs() < 1e-12,
            "K(20) for a thick layer"
        );
        assert!(
            (layer_factor_minus_one(3.0, NU) - (layer_factor(3.0, NU) - 1.0)).abs() < 1e-12,
            "the cancellation-free K − 1"
        );
    }

    #[test]
    fn a_thin_layer_is_the_confined_compression_spring() {
        let s = 1e-4;
        let expected = s * (1.0 - 2.0 * NU) / (2.0 * (1.0 - NU).powi(2));
        assert!(
            (layer_factor(s, NU) / expected - 1.0).abs() < 1e-3,
            "thin-layer compliance factor {} vs t/M limit {expected}",
            layer_factor(s, NU)
        );
    }

    #[test]
    fn far_from_the_load_the_correction_cancels_boussinesq() {
        let table = LayerCorrection::new(G, NU, T, 20.0 * T);
        for r in [8.0 * T, 12.0 * T] {
            let boussinesq = (1.0 - NU) / (2.0 * std::f64::consts::PI * G * r);
            assert!(
                (table.at(r) + boussinesq).abs() < 1e-3 * boussinesq,
                "ΔK({r}) = {} vs −Boussinesq {}",
                table.at(r),
                -boussinesq
            );
        }
    }

    #[test]
    fn the_table_interpolates_the_hankel_integral() {
        let table = LayerCorrection::new(G, NU, T, 4.0 * T);
        // The Hankel integral evaluated directly at off-grid radii.
        for r in [0.0, 0.013 * T, 0.37 * T, 1.234 * T, 3.3 * T] {
            let steps = (HANKEL_S_MAX / HANKEL_S_STEP).round() as usize & !1;
            let ds = HANKEL_S_MAX / steps as f64;
            let direct: f64 = (0..=steps)
                .map(|m| {
                    let s = m as f64 * ds;
                    let w = if m == 0 || m == steps {
                        1.0
                    } else if m % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    w * ds / 3.0 * layer_factor_minus_one(s, NU) * j0(s * r / T)
                })
                .sum::<f64>()
                * (1.0 - NU)
                / (2.0 * std::f64::consts::PI * G * T);
            assert!(
                (table.at(r) - direct).abs() < 1e-6 * table.at(0.0).abs(),
                "interpolated ΔK({r}) = {} vs direct {direct}",
                table.at(r)
            );
        }
    }
}
