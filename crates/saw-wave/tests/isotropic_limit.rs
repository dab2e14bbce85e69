//! The isotropic, non-piezoelectric limit against the Rayleigh equation solved independently:
//! (2 − ξ²)² = 4 √(1 − ξ²) √(1 − ξ² v_t²/v_l²), ξ = v/v_t (Lord Rayleigh 1885; K. F. Graff,
//! *Wave Motion in Elastic Solids*, §6.3), and the closed-form two-partial-wave depth profile.

use saw_wave::{C64, Cut, EulerAngles, Material};

const LAMBDA_PA: f64 = 45e9;
const MU_PA: f64 = 30e9;
const DENSITY: f64 = 2700.0;

fn solid() -> Material {
    Material::isotropic("isotropic test solid", LAMBDA_PA, MU_PA, DENSITY, 4.0).unwrap()
}

fn bulk_velocities() -> (f64, f64) {
    (
        (MU_PA / DENSITY).sqrt(),
        ((LAMBDA_PA + 2.0 * MU_PA) / DENSITY).sqrt(),
    )
}

/// Rayleigh velocity by bisection of the secular function on ξ ∈ [0.5, 1].
fn rayleigh_velocity() -> f64 {
    let (vt, vl) = bulk_velocities();
    let kappa2 = (vt / vl).powi(2);
    let f = |xi: f64| {
        let x2 = xi * xi;
        (2.0 - x2).powi(2) - 4.0 * (1.0 - x2).sqrt() * (1.0 - x2 * kappa2).sqrt()
    };
    let (mut lo, mut hi) = (0.5, 1.0);
    assert!(
        f(lo) < 0.0 && f(hi) > 0.0,
        "Rayleigh secular function must change sign on [0.5, 1]"
    );
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi) * vt
}

/// (u_x, u_z)(depth) / u_z(0) of the closed-form Rayleigh wave, fields ∝ exp(j(ωt − kx + kpd)).
fn closed_form_profile(v: f64, depth_wavelengths: f64) -> (C64, C64) {
    let (vt, vl) = bulk_velocities();
    let j = C64::new(0.0, 1.0);
    let p_l = j * (1.0 - (v / vl).powi(2)).sqrt();
    let p_t = j * (1.0 - (v / vt).powi(2)).sqrt();
    let b_l = C64::new(1.0, 0.0);
    let b_t = -2.0 * p_l * b_l / (1.0 - p_t * p_t);
    let kd = 2.0 * std::f64::consts::PI * depth_wavelengths;
    let (el, et) = ((j * p_l * kd).exp(), (j * p_t * kd).exp());
    let uz0 = p_l * b_l + b_t;
    (
        (b_l * el - p_t * b_t * et) / uz0,
        (p_l * b_l * el + b_t * et) / uz0,
    )
}

#[test]
fn isotropic_velocity_matches_the_rayleigh_equation_to_1e_10() {
    let wave = Cut::new("isotropic", solid(), EulerAngles::new(0.0, 0.0, 0.0))
        .solve()
        .unwrap();
    let expected = rayleigh_velocity();
    let rel = (wave.phase_velocity_free_m_per_s / expected - 1.0).abs();
    assert!(
        rel < 1e-10,
        "free velocity {} vs Rayleigh {expected}: rel {rel:e}",
        wave.phase_velocity_free_m_per_s
    );
    let rel_met = (wave.phase_velocity_metallized_m_per_s / expected - 1.0).abs();
    assert!(
        rel_met < 1e-10,
        "metallized velocity {} vs Rayleigh {expected}",
        wave.phase_velocity_metallized_m_per_s
    );
    assert!(
        wave.coupling_k2.abs() < 1e-10,
        "a non-piezoelectric solid has K² = 0, got {}",
        wave.coupling_k2
    );
}

#[test]
fn isotropic_velocity_does_not_depend_on_the_euler_angles() {
    let expected = rayleigh_velocity();
    for euler in [
        EulerAngles::new(17.0, 38.0, -71.0),
        EulerAngles::new(90.0, 90.0, 90.0),
    ] {
        let wave = Cut::new("isotropic rotated", solid(), euler)
            .solve()
            .unwrap();
        let rel = (wave.phase_velocity_free_m_per_s / expected - 1.0).abs();
        assert!(
            rel < 1e-10,
            "velocity at {euler:?}: {} vs {expected}",
            wave.phase_velocity_free_m_per_s
        );
    }
}

#[test]
fn isotropic_depth_profile_matches_the_closed_form_to_1e_10() {
    let wave = Cut::new("isotropic", solid(), EulerAngles::new(0.0, 0.0, 0.0))
        .solve()
        .unwrap();
    let v = rayleigh_velocity();
    for depth in [0.0, 0.05, 0.1, 0.2, 0.35, 0.5, 0.8, 1.2, 2.0] {
        let fields = wave.free.fields_at_depth(depth);
        let (ux, uz) = closed_form_profile(v, depth);
        assert!(
            (fields.ux - ux).norm() < 1e-10,
            "u_x at {depth} λ: {} vs {ux}",
            fields.ux
        );
        assert!(
            (fields.uz - uz).norm() < 1e-10,
            "u_z at {depth} λ: {} vs {uz}",
            fields.uz
        );
        assert!(
            fields.uy.norm() < 1e-10,
            "u_y at {depth} λ must vanish, got {}",
            fields.uy
        );
        assert!(
            fields.phi_v_per_m.norm() < 1e-10,
            "φ at {depth} λ must vanish without piezoelectricity"
        );
    }
}

#[test]
fn isotropic_surface_orbit_is_retrograde_with_the_closed_form_ratio() {
    let wave = Cut::new("isotropic", solid(), EulerAngles::new(0.0, 0.0, 0.0))
        .solve()
        .unwrap();
    let (ux, _) = closed_form_profile(rayleigh_velocity(), 0.0);
    assert!(
        (wave.surface_ux_over_uz_abs - ux.norm()).abs() < 1e-10,
        "|u_x/u_z| {} vs {}",
        wave.surface_ux_over_uz_abs,
        ux.norm()
    );
    assert!(
        (wave.surface_ux_over_uz_phase_deg - 90.0).abs() < 1e-8,
        "phase {}° must be +90° (retrograde)",
        wave.surface_ux_over_uz_phase_deg
    );
}
