//! The four half-space springs of a rigid circular post of radius a (Johnson 1985, §3.8 and
//! §5.1–5.2 for the punch problems; formulas as in Shigematsu & Kurosawa eqs (1)–(4)).
//!
//! The bonded springs contain (1−2ν)/ln(3−4ν), a 0/0 as ν → 1/2. Writing x = 2(1−2ν) so that
//! 3−4ν = 1 + x, both are evaluated through r(x) = ln(1+x)/x, computed with `ln_1p` and a Taylor
//! branch near x = 0; the limits k_pn → 8Ga and k_pt → 16Ga/3 are reached smoothly.

use serde::{Deserialize, Serialize};

use crate::Material;
use crate::error::{SpringError, positive};

/// Below this |x| = |2(1−2ν)|, r(x) = ln(1+x)/x is evaluated by its Taylor series
/// (dimensionless; truncation error < x⁴/5 ≈ 2·10⁻²⁹ relative at the switch).
const LOG_RATIO_SERIES_BELOW: f64 = 1e-7;

/// r(x) = ln(1+x)/x, finite and smooth through x = 0 (r(0) = 1).
fn log_ratio(x: f64) -> f64 {
    if x.abs() < LOG_RATIO_SERIES_BELOW {
        1.0 - x / 2.0 + x * x / 3.0 - x * x * x / 4.0
    } else {
        x.ln_1p() / x
    }
}

/// x = 2(1−2ν), so that 3 − 4ν = 1 + x.
fn bonded_argument(nu: f64) -> f64 {
    2.0 * (1.0 - 2.0 * nu)
}

fn checked(material: &Material, radius_m: f64) -> Result<(f64, f64, f64), SpringError> {
    material.validate()?;
    let a = positive("radius_m", radius_m)?;
    Ok((material.shear_modulus_pa, material.poisson_ratio, a))
}

/// Bonded normal stiffness of a rigid flat punch (slider side), eq. (1):
/// k_pn = 4 G a · ln(3−4ν)/(1−2ν) = 8 G a · r(2(1−2ν)); → 8Ga as ν → 1/2.
pub fn k_pn(material: &Material, radius_m: f64) -> Result<f64, SpringError> {
    let (g, nu, a) = checked(material, radius_m)?;
    Ok(8.0 * g * a * log_ratio(bonded_argument(nu)))
}

/// Bonded tangential stiffness of a rigid flat punch (slider side), eq. (2):
/// k_pt = G a / (1/8 + (1−2ν)/(8πκ)), κ = ln(3−4ν)/π; with r as above,
/// (1−2ν)/(8πκ) = 1/(16 r), so k_pt → 16Ga/3 as ν → 1/2.
pub fn k_pt(material: &Material, radius_m: f64) -> Result<f64, SpringError> {
    let (g, nu, a) = checked(material, radius_m)?;
    let r = log_ratio(bonded_argument(nu));
    Ok(g * a / (1.0 / 8.0 + 1.0 / (16.0 * r)))
}

/// Frictionless normal stiffness of a rigid flat punch (stator side), eq. (3):
/// k_sn = 4 G a/(1−ν) = 2 E* a with E* = E/(1−ν²).
pub fn k_sn(material: &Material, radius_m: f64) -> Result<f64, SpringError> {
    let (g, nu, a) = checked(material, radius_m)?;
    Ok(4.0 * g * a / (1.0 - nu))
}

/// Tangential stiffness of a rigid flat punch with the normal displacement free (stator side),
/// eq. (4): k_st = 8 G a/(2−ν).
pub fn k_st(material: &Material, radius_m: f64) -> Result<f64, SpringError> {
    let (g, nu, a) = checked(material, radius_m)?;
    Ok(8.0 * g * a / (2.0 - nu))
}

/// Two springs in series: (1/k₁ + 1/k₂)⁻¹.
pub fn series(k1: f64, k2: f64) -> f64 {
    k1 * k2 / (k1 + k2)
}

/// All springs of one post (N/m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PostSprings {
    /// Slider side, bonded normal.
    pub k_pn_n_per_m: f64,
    /// Slider side, bonded tangential.
    pub k_pt_n_per_m: f64,
    /// Stator side, frictionless normal.
    pub k_sn_n_per_m: f64,
    /// Stator side, tangential with u_z free.
    pub k_st_n_per_m: f64,
    /// Normal springs in series, k_n = (1/k_pn + 1/k_sn)⁻¹.
    pub k_n_n_per_m: f64,
    /// Tangential springs in series, k_t = (1/k_pt + 1/k_st)⁻¹.
    pub k_t_n_per_m: f64,
}

/// The four springs of a post of radius `radius_m` bonded to `slider`, touching `stator`.
pub fn post_springs(
    slider: &Material,
    stator: &Material,
    radius_m: f64,
) -> Result<PostSprings, SpringError> {
    let k_pn_n_per_m = k_pn(slider, radius_m)?;
    let k_pt_n_per_m = k_pt(slider, radius_m)?;
    let k_sn_n_per_m = k_sn(stator, radius_m)?;
    let k_st_n_per_m = k_st(stator, radius_m)?;
    Ok(PostSprings {
        k_pn_n_per_m,
        k_pt_n_per_m,
        k_sn_n_per_m,
        k_st_n_per_m,
        k_n_n_per_m: series(k_pn_n_per_m, k_sn_n_per_m),
        k_t_n_per_m: series(k_pt_n_per_m, k_st_n_per_m),
    })
}
