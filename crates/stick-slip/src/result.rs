//! Results of a dynamic run (serde `Serialize` for `sawdrive dynamic --json`) and the CSV
//! writer of the speed–thrust curve.
//!
//! Signs: speeds and thrusts are reported along the drive direction (−x for the +x wave), so a
//! working motor has positive speed and positive thrust (docs/physics.md §4).

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use crate::error::{Result, StickSlipError, Warning};
use crate::scene::ModelKind;

/// One point of the speed–thrust curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CurvePoint {
    /// Mean slider speed along the drive direction (m/s).
    pub speed_m_per_s: f64,
    /// Mean thrust along the drive direction (N) = the load carried at this speed.
    pub thrust_n: f64,
    /// Output power thrust × speed (W).
    pub output_power_w: f64,
    /// Output power over the mechanical power the stator delivers through the contacts.
    pub efficiency: f64,
    /// Time stuck over time in contact, averaged over posts.
    pub stick_fraction: f64,
}

/// The steady operating point at the slider's external load.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OperatingPoint {
    /// External load opposing the drive (N).
    pub load_n: f64,
    /// Mean speed along the drive direction (m/s).
    pub speed_m_per_s: f64,
    /// Mean thrust (N); equals the load in a steady state.
    pub thrust_n: f64,
    /// Output power (W).
    pub output_power_w: f64,
    /// Mechanical power delivered by the stator surface through the tangential contacts (W).
    pub stator_power_w: f64,
    /// Friction dissipation (W).
    pub friction_dissipation_w: f64,
    /// Output over stator power.
    pub efficiency: f64,
    /// Time stuck over time in contact.
    pub stick_fraction: f64,
    /// Time in contact over time.
    pub contact_fraction: f64,
    /// (stator − output − dissipation − stored-energy change)/stator power over the averaging
    /// window: a check of the integration.
    pub energy_balance_residual: f64,
}

/// Transient-only diagnostics.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransientSummary {
    /// Phase groups integrated (posts sharing x mod λ, or x with decay/burst, and gap).
    pub phase_groups: usize,
    /// Wave periods simulated per run.
    pub periods_per_run: f64,
    /// Runs made (curve loads and stall search).
    pub runs: usize,
    /// Whether the operating-point run reached a steady state (speed drift over the averaging
    /// window below tolerance).
    pub steady: bool,
    /// Peak-to-peak slider speed ripple over the averaging window at the operating point (m/s).
    pub speed_ripple_m_per_s: f64,
    /// Peak-to-peak vertical slider motion over the averaging window (m); 0 if quasi-static.
    pub vertical_bounce_m: f64,
    /// Integration steps of the operating-point run.
    pub steps: u64,
    /// Displacement along the drive direction caused by a finite burst (m), if the drive is one.
    pub burst_displacement_m: Option<f64>,
    /// Largest speed reached during a finite burst (m/s), if the drive is one.
    pub burst_peak_speed_m_per_s: Option<f64>,
}

/// Result of a dynamic run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DynamicResult {
    /// Model that ran.
    pub model: ModelKind,
    /// Why this model (auto choice or request).
    pub model_reason: String,
    /// Integrator name.
    pub integrator: String,
    /// Stall thrust, the v → 0⁺ limit of the thrust (N).
    pub stall_thrust_n: f64,
    /// No-load speed, thrust(v₀) = 0 (m/s).
    pub no_load_speed_m_per_s: f64,
    /// Speed–thrust curve from stall to no load.
    pub curve: Vec<CurvePoint>,
    /// Stick fraction at the operating point (at stall if the load exceeds the stall thrust).
    pub stick_fraction: f64,
    /// Contact fraction at the operating point.
    pub contact_fraction: f64,
    /// Largest efficiency along the curve.
    pub efficiency: f64,
    /// Largest output power along the curve (W).
    pub max_output_power_w: f64,
    /// Steady state at the external load; `None` if the load exceeds the stall thrust.
    pub operating_point: Option<OperatingPoint>,
    /// N_eff = η·N.
    pub effective_post_count: f64,
    /// P/N_eff (N).
    pub mean_normal_force_per_post_n: f64,
    /// Post-tip reference height z_s above the stator's mean plane (m); negative: pressed in.
    pub tip_height_m: f64,
    /// Friction limit μ_k·P (N), the stall thrust's bound at low preload.
    pub friction_limit_n: f64,
    /// Crest speed A_t ω (m/s), the no-load speed's bound.
    pub crest_speed_m_per_s: f64,
    /// Wall-clock time of the run (s).
    pub wall_time_s: f64,
    /// Non-fatal findings.
    pub warnings: Vec<Warning>,
    /// Transient diagnostics (transient model only).
    pub transient: Option<TransientSummary>,
}

/// The curve as CSV text: header `speed_m_per_s,thrust_n,output_power_w,efficiency,stick_fraction`.
pub fn curve_csv(curve: &[CurvePoint]) -> String {
    let mut text =
        String::from("speed_m_per_s,thrust_n,output_power_w,efficiency,stick_fraction\n");
    for p in curve {
        let _ = writeln!(
            text,
            "{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}",
            p.speed_m_per_s, p.thrust_n, p.output_power_w, p.efficiency, p.stick_fraction
        );
    }
    text
}

/// Write the curve as CSV to `path`.
pub fn write_curve_csv(curve: &[CurvePoint], path: &Path) -> Result<()> {
    std::fs::write(path, curve_csv(curve)).map_err(|source| StickSlipError::Io {
        path: path.to_path_buf(),
        source,
    })
}
