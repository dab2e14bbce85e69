//! Johnson's post springs (physics.md §3) for tests, benches and examples of this crate only
//! (the workspace's `contact-springs` crate owns the production formulas; this crate must not
//! depend on it).

#![allow(dead_code)]

use std::f64::consts::PI;

/// Shear modulus of Si (Pa), physics.md §2.
pub const G_SI: f64 = 66.5e9;
/// Poisson's ratio of Si.
pub const NU_SI: f64 = 0.22;
/// Shear modulus of LiNbO3 (Pa).
pub const G_LN: f64 = 67.0e9;
/// Poisson's ratio of LiNbO3.
pub const NU_LN: f64 = 0.25;
/// Post height (m).
pub const POST_HEIGHT_M: f64 = 2e-6;

/// (k_n, k_t) in N/m of one rigid post of radius `a` (m): bonded slider springs in series with
/// the stator's frictionless/free springs.
pub fn springs(a: f64) -> (f64, f64) {
    let log = (3.0 - 4.0 * NU_SI).ln();
    let k_pn = 4.0 * G_SI * a * log / (1.0 - 2.0 * NU_SI);
    let kappa = log / PI;
    let k_pt = G_SI * a / (0.125 + (1.0 - 2.0 * NU_SI) / (8.0 * PI * kappa));
    let k_sn = 4.0 * G_LN * a / (1.0 - NU_LN);
    let k_st = 8.0 * G_LN * a / (2.0 - NU_LN);
    let series = |a: f64, b: f64| 1.0 / (1.0 / a + 1.0 / b);
    (series(k_pn, k_sn), series(k_pt, k_st))
}

/// Mass of a Si post of radius `a` (kg), ρπa²h.
pub fn post_mass(a: f64) -> f64 {
    2329.0 * PI * a * a * POST_HEIGHT_M
}
