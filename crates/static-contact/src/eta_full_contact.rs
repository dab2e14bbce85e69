//! η at full contact: the high-preload asymptote of the fitted η, read off the condensed post
//! compliance C (m/N) of the strip.
//!
//! Once every post touches, the contact problem is linear: C f = δ 1 + h with Σf = P, h the
//! surface heights. The part of f that follows the wave is the load-neutral response to h,
//! f_h = C⁻¹h − (1ᵀC⁻¹h / 1ᵀC⁻¹1) C⁻¹1 (the common approach δ adjusted so that it adds no net
//! load); independent posts of stiffness η k_n respond with η k_n (h − h̄). The least-squares
//! η between the two, pooled over the phases θ₀ = 0 and π/2 of h = A sin(θ₀ − kx), is
//!
//! η_full = Σ_θ Σ_i f_h,i (h_i − h̄) / (k_n Σ_θ Σ_i (h_i − h̄)²).
//!
//! The part of f set by the mean load (the strip's ends carry more: the flat-stator load
//! sharing) is nearly orthogonal to the wave and is left out; the fitted η at full contact agrees
//! with η_full to 5 digits on the default slider and to 1e-7 on the committed 10-post strip
//! (validation/static-contact). An infinite lattice gives
//! η_full = 1/(k_n c(k)), c(k) = Σ_j C_ij cos(k(x_j − x_i)); the finite strip's slowly decaying
//! stator terms make that sum a poor estimate, hence the solve.

use nalgebra::DVector;

use crate::scene::StripModel;

/// η at full contact for `model`, Johnson stiffness `k_n_n_per_m` (N/m) and wavelength
/// `wavelength_m` (m); `None` if C is singular.
pub fn full_contact_eta(model: &StripModel, k_n_n_per_m: f64, wavelength_m: f64) -> Option<f64> {
    let c = &model.compliance_m_per_n;
    let n = c.nrows();
    let lu = c.clone().lu();
    let unit_response = lu.solve(&DVector::from_element(n, 1.0))?;
    let wavenumber = 2.0 * std::f64::consts::PI / wavelength_m;
    let (mut covariance, mut variance) = (0.0, 0.0);
    for phase in [0.0, std::f64::consts::FRAC_PI_2] {
        let heights = DVector::from_iterator(
            n,
            model
                .posts
                .iter()
                .map(|p| (phase - wavenumber * p.x_m).sin()),
        );
        let response = lu.solve(&heights)?;
        let neutral = &response - &unit_response * (response.sum() / unit_response.sum());
        let mean = heights.mean();
        for i in 0..n {
            covariance += neutral[i] * (heights[i] - mean);
            variance += (heights[i] - mean).powi(2);
        }
    }
    Some(covariance / (k_n_n_per_m * variance))
}
