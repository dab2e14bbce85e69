//! The `stick-slip` case: the integrators of the stick/slip post model
//! ([`crate::stick_slip::run_validation`], inputs from the scene: `sawdrive validate`) and
//! its checks: the transient model against the period average (stall thrust, no-load speed,
//! speeds along the speed–thrust curve) within [`TRANSIENT_AGREEMENT`], and the observed order
//! of the return mapping against its theoretical 2.

use super::{Check, Level};
use crate::stick_slip::{ValidationLevel, ValidationReport};

const CASE: &str = "stick-slip";

/// Largest relative difference transient vs period average (the 1 %,
/// validation/stick-slip/README.md). Dimensionless; 0.01.
pub const TRANSIENT_AGREEMENT: f64 = 0.01;

/// Smallest observed order of the return mapping (theory 2; measured 2.1–2.3). 1.8.
pub const RETURN_MAPPING_ORDER: f64 = 1.8;

/// The study's level.
pub fn study_level(level: Level) -> ValidationLevel {
    match level {
        Level::Smoke => ValidationLevel::Smoke,
        Level::Quick => ValidationLevel::Quick,
        Level::Full => ValidationLevel::Full,
    }
}

/// The checks of a finished study.
pub fn checks(report: &ValidationReport, level: Level) -> Vec<Check> {
    let a = &report.agreement;
    let source = "transient vs period average within 1 % (validation/stick-slip/README.md)";
    let mut checks = vec![
        Check::relative(
            CASE,
            "stall thrust (N): transient over period average",
            a.stall_thrust_n.1,
            a.stall_thrust_n.0,
            TRANSIENT_AGREEMENT,
            source,
        ),
        Check::relative(
            CASE,
            "no-load speed (m/s): transient over period average",
            a.no_load_speed_m_per_s.1,
            a.no_load_speed_m_per_s.0,
            TRANSIENT_AGREEMENT,
            source,
        ),
        Check::at_most(
            CASE,
            "largest relative speed difference transient vs period average along the curve",
            a.max_speed_difference,
            TRANSIENT_AGREEMENT,
            source,
        ),
    ];
    if level != Level::Smoke {
        let (stall, no_load) = report.return_mapping_order;
        for (what, order) in [("stall thrust", stall), ("no-load speed", no_load)] {
            checks.push(Check::at_least(
                CASE,
                format!("observed order of the return mapping ({what})"),
                order,
                RETURN_MAPPING_ORDER,
                "second-order scheme (validation/stick-slip/README.md, work-precision)",
            ));
        }
    }
    checks
}
