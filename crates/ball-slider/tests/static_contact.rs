//! The Hertz and Cattaneo–Mindlin closed forms against independent numerical integrals.

use std::f64::consts::PI;

use ball_slider::hertz::{self, HertzContact};
use ball_slider::mindlin::{MindlinContact, effective_shear_modulus_pa};
use ball_slider::quadrature::GaussLegendre;
use ball_slider::{BallError, bearing_steel};
use contact_springs::Material;

/// A 2 mm steel ball on LiNbO3 at 0.5 N, μ = 0.3.
fn contact() -> MindlinContact {
    let (ball, flat) = (bearing_steel(), Material::lithium_niobate());
    let h = HertzContact::new(1e-3, hertz::effective_modulus_pa(&ball, &flat), 0.5).unwrap();
    MindlinContact::new(h, 0.3, effective_shear_modulus_pa(&ball, &flat)).unwrap()
}

#[test]
fn hertz_pressure_integrates_to_the_normal_force() {
    let h = contact().hertz;
    let a = h.contact_radius_m;
    // r = a sin φ removes the square-root edge: p(r) 2πr dr = p₀ cos φ · 2π a sin φ · a cos φ dφ.
    let rule = GaussLegendre::new(16);
    let force = rule.integrate(0.0, PI / 2.0, 4, |phi| {
        let r = a * phi.sin();
        h.pressure_pa(r) * 2.0 * PI * r * a * phi.cos()
    });
    let err = (force - h.normal_force_n).abs() / h.normal_force_n;
    assert!(
        err < 1e-10,
        "∫p dA = {force} N vs N = {} N (rel. {err:e})",
        h.normal_force_n
    );
}

#[test]
fn hertz_contact_radius_approach_and_stiffness_match_closed_forms() {
    let h = contact().hertz;
    let (r, e) = (h.radius_m, h.effective_modulus_pa);
    let a = (3.0 * h.normal_force_n * r / (4.0 * e)).cbrt();
    assert!(
        (h.contact_radius_m - a).abs() < 1e-15 * a,
        "contact radius a"
    );
    assert!(
        (h.approach_m - a * a / r).abs() < 1e-15 * h.approach_m,
        "approach δ = a²/R"
    );
    let back = hertz::force_at_approach_n(r, e, h.approach_m);
    assert!((back - h.normal_force_n).abs() < 1e-13, "N(δ(N)) = {back}");
    let d = h.approach_m;
    let step = 1e-4 * d;
    let k_fd = (hertz::force_at_approach_n(r, e, d + step)
        - hertz::force_at_approach_n(r, e, d - step))
        / (2.0 * step);
    assert!(
        (k_fd - h.normal_stiffness_n_per_m).abs() < 1e-7 * k_fd,
        "k_n = 2aE* vs dN/dδ {k_fd}"
    );
    let p0 = 2.0 * a * e / (PI * r);
    assert!(
        (h.peak_pressure_pa - p0).abs() < 1e-12 * p0,
        "p₀ = 3N/2πa² = 2aE*/πR"
    );
    // δ = d t² makes N(δ) dδ a polynomial in t (∝ t⁴): Gauss–Legendre is exact.
    let rule = GaussLegendre::new(12);
    let energy = rule.integrate(0.0, 1.0, 1, |t| {
        hertz::force_at_approach_n(r, e, d * t * t) * 2.0 * d * t
    });
    assert!(
        (energy - h.energy_j()).abs() < 1e-10 * energy,
        "U = ∫N dδ: {energy} vs {}",
        h.energy_j()
    );
}

/// ∫₀ᵃ q(r) w(r) dr of the Cattaneo traction at load Q, split at the stick radius c with
/// r = c sin φ on [0, c] and r = c + (a − c) sin²φ on [c, a], which smooth both square-root
/// edges. (√(1 − r²/a²) stays analytic on [0, c] but comes close to its branch point as
/// c → a: many panels there.)
fn traction_integral(m: &MindlinContact, load: f64, w: impl Fn(f64) -> f64) -> f64 {
    let a = m.hertz.contact_radius_m;
    let c = m.stick_radius_m(load).unwrap();
    let rule = GaussLegendre::new(16);
    let inner = rule.integrate(0.0, PI / 2.0, 64, |phi| {
        let r = c * phi.sin();
        m.traction_pa(r, load).unwrap() * w(r) * c * phi.cos()
    });
    let outer = rule.integrate(0.0, PI / 2.0, 16, |phi| {
        let r = c + (a - c) * phi.sin().powi(2);
        m.traction_pa(r, load).unwrap() * w(r) * 2.0 * (a - c) * phi.sin() * phi.cos()
    });
    inner + outer
}

#[test]
fn mindlin_compliance_matches_integral_of_the_traction_distribution() {
    let m = contact();
    for q in [0.05, 0.3, 0.7, 0.95] {
        let load = q * m.friction_limit_n();
        // Cerruti: the centre's displacement under an axisymmetric traction q(r) is
        // (2 − ν)/(2G) ∫₀ᵃ q(r) dr per body, i.e. 1/(2G*) ∫₀ᵃ q dr for both bodies.
        let delta = traction_integral(&m, load, |_| 1.0) / (2.0 * m.effective_shear_modulus_pa);
        let closed = m.compliance_m(load).unwrap();
        let err = (delta - closed).abs() / closed;
        assert!(
            err < 1e-10,
            "δ_t at Q/μN = {q}: Cerruti integral {delta} vs closed form {closed} (rel. {err:e})"
        );
        let resultant = traction_integral(&m, load, |r| 2.0 * PI * r);
        let err = (resultant - load).abs() / load;
        assert!(
            err < 1e-10,
            "∫q dA = {resultant} vs Q = {load} (rel. {err:e})"
        );
    }
}

/// ∮Q dδ around the loop of amplitude Q* by quadrature along the reloading branch (the
/// unloading branch is its image under (Q, δ) → (−Q, −δ), which leaves Q dδ unchanged).
/// With y = (Q* + Q)/2μN: Q = 2μNy − Q*, δ_L = −δ(Q*) + 2C[1 − (1 − y)^{2/3}]. Small loops in
/// y directly (no cancellation in Q); large ones in τ with 1 − y = τ³ (smooth at Q* = μN).
fn loop_integral(m: &MindlinContact, q_star: f64) -> f64 {
    let s = m.friction_limit_n();
    let c = m.full_slip_displacement_m();
    let q = q_star / s;
    let rule = GaussLegendre::new(16);
    let reload = if q <= 0.5 {
        rule.integrate(0.0, q, 16, |y| {
            (2.0 * s * y - q_star) * (4.0 * c / 3.0) * (1.0 - y).powf(-1.0 / 3.0)
        })
    } else {
        // dδ_L/dτ = −4Cτ; τ runs from 1 (Q = −Q*) to (1 − q)^{1/3} (Q = Q*).
        rule.integrate(1.0, (1.0 - q).cbrt(), 16, |tau| {
            (2.0 * s * (1.0 - tau.powi(3)) - q_star) * (-4.0 * c * tau)
        })
    };
    2.0 * reload
}

#[test]
fn loop_energy_matches_integral_of_q_d_delta_around_the_loop() {
    let m = contact();
    for q in [1e-4, 0.01, 0.2, 0.5, 0.9, 0.999, 1.0] {
        let q_star = q * m.friction_limit_n();
        let closed = m.loop_energy_j(q_star).unwrap();
        let numeric = loop_integral(&m, q_star);
        let err = (closed - numeric).abs() / numeric.abs();
        assert!(
            err < 1e-8,
            "loop energy at Q*/μN = {q}: closed {closed:e} vs ∮Q dδ {numeric:e} (rel. {err:e})"
        );
    }
}

#[test]
fn loop_branches_close_at_the_reversal_points_and_follow_masing() {
    let m = contact();
    let q_star = 0.6 * m.friction_limit_n();
    let top = m.compliance_m(q_star).unwrap();
    assert!(
        (m.unloading_m(q_star, q_star).unwrap() - top).abs() < 1e-20,
        "unloading starts at (Q*, δ(Q*))"
    );
    assert!(
        (m.unloading_m(q_star, -q_star).unwrap() + top).abs() < 1e-20,
        "unloading ends at (−Q*, −δ(Q*))"
    );
    assert!(
        (m.reloading_m(q_star, q_star).unwrap() - top).abs() < 1e-20,
        "reloading closes the loop"
    );
    // Masing: the unloading branch is the virgin curve scaled by 2 about the reversal point.
    let q = 0.1 * m.friction_limit_n();
    let masing = top - 2.0 * m.compliance_m((q_star - q) / 2.0).unwrap();
    assert!((m.unloading_m(q_star, q).unwrap() - masing).abs() < 1e-22);
}

#[test]
fn loop_energy_small_amplitude_follows_mindlins_cubic_law() {
    let m = contact();
    let s = m.friction_limit_n();
    for q in [1e-5, 1e-4, 5e-4, 2e-3] {
        let q_star = q * s;
        let cubic =
            q_star.powi(3) / (36.0 * s * m.hertz.contact_radius_m * m.effective_shear_modulus_pa);
        let w = m.loop_energy_j(q_star).unwrap();
        assert!(
            (w / cubic - 1.0).abs() < 2.0 * q,
            "W/(Q*³/36μNaG*) at q = {q}: {}",
            w / cubic
        );
    }
}

#[test]
fn full_slip_limit_reaches_zero_stick_radius_and_zero_tangent_stiffness() {
    let m = contact();
    let s = m.friction_limit_n();
    let c = m.stick_radius_m(s * (1.0 - 1e-12)).unwrap();
    assert!(
        c < 1e-4 * m.hertz.contact_radius_m,
        "stick radius near full slip: {c}"
    );
    assert_eq!(
        m.tangent_stiffness_n_per_m(s).unwrap(),
        0.0,
        "tangent stiffness at Q = μN"
    );
    assert!((m.compliance_m(s).unwrap() - m.full_slip_displacement_m()).abs() < 1e-22);
    assert!(
        (m.tangent_stiffness_n_per_m(0.0).unwrap()
            - 8.0 * m.effective_shear_modulus_pa * m.hertz.contact_radius_m)
            .abs()
            < 1e-6,
        "initial stiffness 8G*a"
    );
    match m.stick_radius_m(s) {
        Err(BallError::TangentialLoadBeyondFriction { limit_n, .. }) => assert_eq!(limit_n, s),
        other => panic!("Q = μN must be refused by the partial-slip stick radius, got {other:?}"),
    }
    assert!(m.compliance_m(1.01 * s).is_err(), "Q > μN refused");
    assert!(
        (m.loop_energy_j(s).unwrap() - 0.8 * s * m.full_slip_displacement_m()).abs()
            < 1e-12 * s * m.full_slip_displacement_m(),
        "full-slip loop energy 4μN·C/5"
    );
}

#[test]
fn dundurs_beta_is_small_for_steel_on_linbo3_and_zero_for_like_bodies() {
    let (steel, ln) = (bearing_steel(), Material::lithium_niobate());
    let beta = hertz::dundurs_beta(&steel, &ln);
    assert!((beta + 0.0632).abs() < 5e-4, "β steel/LiNbO3 = {beta}");
    assert_eq!(
        hertz::dundurs_beta(&steel, &steel),
        0.0,
        "β of identical bodies"
    );
    let si = Material::silicon();
    assert!(
        (hertz::dundurs_beta(&si, &ln).abs() - 0.021).abs() < 1e-3,
        "β Si/LiNbO3 as docs/physics.md §5.2"
    );
}
