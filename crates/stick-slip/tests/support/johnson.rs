//! Post springs for tests, benches and examples of this crate, taken from the workspace's
//! `contact-springs` crate (a dev-dependency: the library itself takes k_n, k_t as inputs).

#![allow(dead_code)]

use std::f64::consts::PI;

use contact_springs::{Material, post_springs};

/// Post height (m), docs/physics.md §1.
pub const POST_HEIGHT_M: f64 = 2e-6;

/// (k_n, k_t) in N/m of one rigid post of radius `a` (m) of Si on LiNbO3: bonded slider springs
/// in series with the stator's frictionless/free springs.
pub fn springs(a: f64) -> (f64, f64) {
    let s = post_springs(&Material::silicon(), &Material::lithium_niobate(), a)
        .expect("valid post radius");
    (s.k_n_n_per_m, s.k_t_n_per_m)
}

/// Mass of a Si post of radius `a` (kg), ρπa²h.
pub fn post_mass(a: f64) -> f64 {
    Material::silicon().density_kg_per_m3 * PI * a * a * POST_HEIGHT_M
}
