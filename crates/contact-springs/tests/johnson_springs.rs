//! The Johnson springs against closed forms, limits and physical orderings.

use contact_springs::{Material, SpringError, k_pn, k_pt, k_sn, k_st, post_springs, series};
use proptest::prelude::*;

const A: f64 = 10e-6;

fn iso(g: f64, nu: f64) -> Material {
    Material::from_shear("test", g, nu, 1000.0).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn springs_match_closed_forms_for_silicon_and_lithium_niobate() {
    let (si, ln) = (Material::silicon(), Material::lithium_niobate());
    let (g, nu) = (66.5e9, 0.22);
    let kpn = 4.0 * g * A * (3.0 - 4.0 * nu as f64).ln() / (1.0 - 2.0 * nu);
    let kappa = (3.0 - 4.0 * nu as f64).ln() / std::f64::consts::PI;
    let kpt = g * A / (1.0 / 8.0 + (1.0 - 2.0 * nu) / (8.0 * std::f64::consts::PI * kappa));
    assert!(rel(k_pn(&si, A).unwrap(), kpn) < 1e-14, "k_pn of Si");
    assert!(rel(k_pt(&si, A).unwrap(), kpt) < 1e-14, "k_pt of Si");
    assert!(
        rel(k_sn(&ln, A).unwrap(), 4.0 * 67e9 * A / 0.75) < 1e-14,
        "k_sn of LiNbO3"
    );
    assert!(
        rel(k_st(&ln, A).unwrap(), 8.0 * 67e9 * A / 1.75) < 1e-14,
        "k_st of LiNbO3"
    );
}

#[test]
fn twenty_micron_post_has_the_documented_order_of_magnitude() {
    // docs/physics.md §3: k_n ≈ 1.8·10⁶ N/m, k_t ≈ 1.5·10⁶ N/m per post of d = 20 µm.
    let s = post_springs(&Material::silicon(), &Material::lithium_niobate(), A).unwrap();
    assert!(rel(s.k_n_n_per_m, 1.8e6) < 0.03, "k_n = {}", s.k_n_n_per_m);
    assert!(rel(s.k_t_n_per_m, 1.5e6) < 0.03, "k_t = {}", s.k_t_n_per_m);
    assert!(
        rel(s.k_n_n_per_m, series(s.k_pn_n_per_m, s.k_sn_n_per_m)) < 1e-15,
        "k_n is the series value"
    );
    assert!(
        rel(s.k_t_n_per_m, series(s.k_pt_n_per_m, s.k_st_n_per_m)) < 1e-15,
        "k_t is the series value"
    );
}

#[test]
fn bonded_springs_reach_their_incompressible_limits_smoothly() {
    let g = 1e9;
    for eps in [1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-15] {
        let m = iso(g, 0.5 - eps);
        let (kpn, kpt) = (k_pn(&m, A).unwrap(), k_pt(&m, A).unwrap());
        assert!(
            kpn.is_finite() && kpt.is_finite(),
            "finite at ν = 0.5 − {eps}"
        );
        // First-order slopes: k_pn ≈ 8Ga(1 − 2ε), k_pt ≈ (16Ga/3)(1 − 2ε/3).
        assert!(
            rel(kpn, 8.0 * g * A) < 3.0 * eps + 1e-15,
            "k_pn → 8Ga at ε = {eps}: {kpn}"
        );
        assert!(
            rel(kpt, 16.0 * g * A / 3.0) < 1.0 * eps + 1e-15,
            "k_pt → 16Ga/3 at ε = {eps}: {kpt}"
        );
    }
    // At the limit the bonded and frictionless values coincide.
    let m = iso(g, 0.5 - 1e-12);
    assert!(
        rel(k_pn(&m, A).unwrap(), k_sn(&m, A).unwrap()) < 1e-10,
        "k_pn = k_sn at ν = 1/2"
    );
    assert!(
        rel(k_pt(&m, A).unwrap(), k_st(&m, A).unwrap()) < 1e-10,
        "k_pt = k_st at ν = 1/2"
    );
}

#[test]
fn series_branch_and_logarithm_branch_agree_at_the_switch() {
    // Either side of x = 2(1−2ν) = 1e-7 the two evaluations must be continuous.
    let below = k_pn(&iso(1e9, 0.5 - 0.99e-7 / 4.0), A).unwrap();
    let above = k_pn(&iso(1e9, 0.5 - 1.01e-7 / 4.0), A).unwrap();
    assert!(
        rel(below, above) < 1e-8,
        "k_pn continuous across the series switch"
    );
}

#[test]
fn invalid_inputs_are_typed_errors_naming_the_parameter() {
    let cases: [(&str, Result<Material, SpringError>); 6] = [
        ("poisson_ratio", Material::from_shear("m", 1e9, 0.5, 1.0)),
        ("poisson_ratio", Material::from_shear("m", 1e9, -1.0, 1.0)),
        (
            "poisson_ratio",
            Material::from_shear("m", 1e9, f64::NAN, 1.0),
        ),
        ("shear_modulus_pa", Material::from_shear("m", 0.0, 0.3, 1.0)),
        (
            "shear_modulus_pa",
            Material::from_shear("m", f64::INFINITY, 0.3, 1.0),
        ),
        (
            "density_kg_per_m3",
            Material::from_shear("m", 1e9, 0.3, -1.0),
        ),
    ];
    for (parameter, result) in cases {
        let err = result.expect_err(parameter);
        assert!(
            err.to_string().starts_with(parameter),
            "error names {parameter}: {err}"
        );
    }
    for radius in [0.0, -1e-6, f64::NAN] {
        let err = k_pn(&Material::silicon(), radius).expect_err("bad radius");
        assert!(
            err.to_string().starts_with("radius_m"),
            "error names radius_m: {err}"
        );
    }
}

#[test]
fn silicon_default_is_the_hill_average_of_its_cubic_constants() {
    let hill = Material::from_cubic_hill("si", 165.7e9, 63.9e9, 79.6e9, 2329.0).unwrap();
    let si = Material::silicon();
    assert!(
        rel(hill.shear_modulus_pa, si.shear_modulus_pa) < 2e-3,
        "G_Si Hill = {}",
        hill.shear_modulus_pa
    );
    assert!(
        (hill.poisson_ratio - si.poisson_ratio).abs() < 5e-3,
        "ν_Si Hill = {}",
        hill.poisson_ratio
    );
}

#[test]
fn young_and_shear_constructors_agree() {
    let m = Material::from_young("steel", 210e9, 0.3, 7850.0).unwrap();
    assert!(
        rel(m.shear_modulus_pa, 210e9 / 2.6) < 1e-15,
        "G = E/(2(1+ν))"
    );
    assert!(rel(m.youngs_modulus_pa(), 210e9) < 1e-15, "E round trip");
    // Tabulated Lamé λ for E = 210 GPa, ν = 0.3: 121.15 GPa.
    assert!(
        rel(m.lame_lambda_pa(), 121.153_846e9) < 1e-6,
        "λ = {}",
        m.lame_lambda_pa()
    );
}

proptest! {
    #[test]
    fn springs_are_linear_in_radius_and_shear_modulus(
        g in 1e8f64..1e12, nu in -0.99f64..0.4999, a in 1e-8f64..1e-2, scale in 0.1f64..10.0,
    ) {
        let m = iso(g, nu);
        let m_scaled = iso(g * scale, nu);
        for f in [k_pn, k_pt, k_sn, k_st] {
            let base = f(&m, a).unwrap();
            prop_assert!(rel(f(&m, a * scale).unwrap(), base * scale) < 1e-12, "linear in a");
            prop_assert!(rel(f(&m_scaled, a).unwrap(), base * scale) < 1e-12, "linear in G");
        }
    }

    #[test]
    fn bonded_springs_are_at_least_as_stiff_as_frictionless(g in 1e8f64..1e12, nu in -0.99f64..0.4999, a in 1e-8f64..1e-2) {
        let m = iso(g, nu);
        let tolerance = 1e-12;
        prop_assert!(k_pn(&m, a).unwrap() >= k_sn(&m, a).unwrap() * (1.0 - tolerance), "k_pn ≥ k_sn");
        prop_assert!(k_pt(&m, a).unwrap() >= k_st(&m, a).unwrap() * (1.0 - tolerance), "k_pt ≥ k_st");
    }
}
