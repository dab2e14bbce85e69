//! Scenes and a CPU clock shared by the coupled model's examples and benches (not an example
//! itself: Cargo builds `examples/*.rs` and `examples/*/main.rs` only).
//!
//! - [`analytic_row`]: the default slider's row (posts at 40 µm of a 100 × 100 array of 10 µm
//!   radius), compliance = Johnson post springs on the diagonal plus the half-space normal and
//!   tangential terms of all 100 rows (`static_contact::halfspace`): no meshing, the FEM
//!   strip's matrix sizes and solver work.
//! - [`cached_strip`]: the paper motor on the strip compliance `sawdrive run` caches
//!   (`out/.cache/compliance-<geometry key>.json`: tip positions, normal and tangential
//!   compliances, strip share).
//! - [`cpu_s`]: the process CPU time from /proc/self/stat (Linux; 0 elsewhere).

#![allow(dead_code)] // each example uses the pieces it needs

use contact_springs::{Material, post_springs};
use coupled_dynamics::{CoupledScene, PreloadBalance};
use motor::Motor;
use nalgebra::DMatrix;
use static_contact::halfspace::{
    RowLayout, StripPost, strip_compliance, strip_tangential_compliance,
};
use stick_slip::Wave;

/// Pitch of the default slider's posts (m).
pub const PITCH_M: f64 = 40e-6;
/// Post radius of the default slider (m).
pub const RADIUS_M: f64 = 10e-6;
/// Rows of the default slider.
pub const ROWS: usize = 100;

/// `n` posts of the default slider's row at `preload_n` (the whole slider's preload), 128 steps
/// per period, the preload balanced at every step, strip share n / (100 × 100).
pub fn analytic_row(n: usize, preload_n: f64) -> CoupledScene {
    let si = Material::silicon();
    let ln = Material::lithium_niobate();
    let springs = post_springs(&si, &ln, RADIUS_M).unwrap();
    let posts: Vec<StripPost> = (0..n)
        .map(|i| StripPost {
            x_m: (i as f64 - 0.5 * (n - 1) as f64) * PITCH_M,
            row: 0,
        })
        .collect();
    let layout = RowLayout {
        pitch_m: PITCH_M,
        strip_rows: 1,
        slider_rows: ROWS,
    };
    let (g, nu) = (ln.shear_modulus_pa, ln.poisson_ratio);
    let cn = strip_compliance(g, nu, RADIUS_M, &posts, &layout)
        + DMatrix::identity(n, n) / springs.k_pn_n_per_m;
    let ct = strip_tangential_compliance(g, nu, RADIUS_M, &posts, &layout)
        + DMatrix::identity(n, n) / springs.k_pt_n_per_m;
    let x = posts.iter().map(|p| p.x_m).collect();
    let mut scene =
        CoupledScene::independent_posts(Wave::paper_default(), x, 1.0, 1.0, 0.3, 0.3, preload_n);
    scene.normal_compliance_m_per_n = cn;
    scene.tangential_compliance_m_per_n = ct;
    scene.strip_share = n as f64 / (ROWS * 100) as f64;
    scene.preload_balance = PreloadBalance::Instant;
    scene.steps_per_period = 128;
    scene
}

/// The paper motor on the cached strip compliance at `path`, `steps_per_period` steps per
/// period, the preload balanced at every step; the error names the file and the missing key.
pub fn cached_strip(path: &str, steps_per_period: usize) -> Result<CoupledScene, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let entry: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{path}: {e}"))?;
    let tips = &entry["tips"];
    let numbers = |key: &str| -> Result<Vec<f64>, String> {
        tips[key]
            .as_array()
            .ok_or_else(|| format!("{path}: tips.{key} missing"))?
            .iter()
            .map(|v| {
                v.as_f64()
                    .ok_or_else(|| format!("{path}: tips.{key}: not a number"))
            })
            .collect()
    };
    let x = numbers("post_x_m")?;
    let n = x.len();
    let motor = Motor::paper();
    let mut scene = CoupledScene::independent_posts(
        motor.wave.clone(),
        x,
        1.0,
        1.0,
        motor.friction.mu_static,
        motor.friction.mu_kinetic,
        motor.load.preload_n,
    );
    scene.normal_compliance_m_per_n = DMatrix::from_vec(n, n, numbers("normal_m_per_n")?);
    scene.tangential_compliance_m_per_n = DMatrix::from_vec(n, n, numbers("tangential_m_per_n")?);
    scene.strip_share = tips["strip_share"]
        .as_f64()
        .ok_or_else(|| format!("{path}: tips.strip_share missing"))?;
    scene.preload_balance = PreloadBalance::Instant;
    scene.steps_per_period = steps_per_period;
    scene.validate().map_err(|e| e.to_string())?;
    Ok(scene)
}

/// Process CPU time (user + system, s) from /proc/self/stat (clock ticks of 1/100 s).
pub fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or(vec![], |(_, rest)| rest.split_whitespace().collect());
    let tick = |k: usize| {
        fields
            .get(k)
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (tick(11) + tick(12)) / 100.0
}
