//! The whole-slider case's band study (validation/whole-slider/bands): `sawdrive uq`'s bands of
//! the lumped model against the whole slider's coupled model on the same samples, σ = 0, 2, 5,
//! 10 nm of post-height scatter on 20 × 20 posts. The study runs through the `sawdrive` library
//! (`cargo run --release -p sawdrive --example uq_bands`), which this crate does not link, so
//! its checks read the committed `bands.csv` (compiled in) at every level and check the
//! README's claims:
//!
//! * ideal posts (σ = 0): the lumped stall thrust within [`IDEAL_STALL_TOLERANCE`] and the
//!   lumped no-load speed within [`IDEAL_NO_LOAD_TOLERANCE`] of the coupled ones (measured
//!   0.5 % and 3.0 %);
//! * σ ≥ 2 nm: the coupled no-load P50 lies below the lumped band's P5 by at least
//!   [`SCATTERED_NO_LOAD_GAP`] (measured 5.2 / 12.7 / 26.5 % at 2 / 5 / 10 nm), and by at least
//!   [`WIDE_SCATTER_NO_LOAD_GAP`] at 10 nm: the lumped bands miss the coupled median;
//! * the coupled stall thrust's band widens with σ: its P95 − P5 at 10 nm at least
//!   [`BAND_WIDENING`] × its width at 2 nm (measured 9.9×).

use super::Check;
use crate::error::ValidationError;

const CASE: &str = "whole-slider";
const SOURCE: &str = "validation/whole-slider/bands/README.md (committed bands.csv)";
const BANDS_CSV: &str = include_str!("../../../../validation/whole-slider/bands/bands.csv");

/// Largest |lumped / coupled − 1| of the stall thrust with ideal posts. 0.01.
pub const IDEAL_STALL_TOLERANCE: f64 = 0.01;
/// Largest |lumped / coupled − 1| of the no-load speed with ideal posts. 0.05.
pub const IDEAL_NO_LOAD_TOLERANCE: f64 = 0.05;
/// Smallest lumped no-load P5 / coupled no-load P50 − 1 for σ ≥ 2 nm. 0.04.
pub const SCATTERED_NO_LOAD_GAP: f64 = 0.04;
/// Smallest lumped no-load P5 / coupled no-load P50 − 1 at σ = 10 nm. 0.2.
pub const WIDE_SCATTER_NO_LOAD_GAP: f64 = 0.2;
/// Smallest ratio of the coupled stall band's width at 10 nm to its width at 2 nm. 5.
pub const BAND_WIDENING: f64 = 5.0;

/// One row of `bands.csv`.
#[derive(Debug, Clone, PartialEq)]
struct Row {
    sigma_nm: f64,
    model: String,
    stall: [f64; 3],
    no_load: [f64; 3],
}

fn parse(text: &str) -> Result<Vec<Row>, ValidationError> {
    let bad = |line: &str| ValidationError::InvalidOption {
        option: "validation/whole-slider/bands/bands.csv",
        value: line.to_owned(),
        reason: "a row of posts_per_side, sigma_nm, model, samples, coupled_samples, \
                 3 stall quantiles, mean, 3 no-load quantiles, mean, wall_s",
    };
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|line| {
            let cells: Vec<&str> = line.split(',').collect();
            let number = |k: usize| -> Result<f64, ValidationError> {
                cells
                    .get(k)
                    .and_then(|c| c.parse().ok())
                    .ok_or_else(|| bad(line))
            };
            Ok(Row {
                sigma_nm: number(1)?,
                model: cells.get(2).ok_or_else(|| bad(line))?.to_string(),
                stall: [number(5)?, number(6)?, number(7)?],
                no_load: [number(9)?, number(10)?, number(11)?],
            })
        })
        .collect()
}

/// The checks of the committed band study.
pub fn checks() -> Result<Vec<Check>, ValidationError> {
    let rows = parse(BANDS_CSV)?;
    let find = |sigma: f64, model: &str| {
        rows.iter()
            .find(|r| r.sigma_nm == sigma && r.model == model)
            .ok_or(ValidationError::InvalidOption {
                option: "validation/whole-slider/bands/bands.csv",
                value: format!("σ = {sigma} nm, {model}"),
                reason: "the study's row is missing",
            })
    };
    let (l0, c0) = (find(0.0, "lumped")?, find(0.0, "coupled")?);
    let mut checks = vec![
        Check::relative(
            CASE,
            "bands, 20 × 20, σ = 0: lumped stall thrust against the coupled one",
            l0.stall[1],
            c0.stall[1],
            IDEAL_STALL_TOLERANCE,
            SOURCE,
        ),
        Check::relative(
            CASE,
            "bands, 20 × 20, σ = 0: lumped no-load speed against the coupled one",
            l0.no_load[1],
            c0.no_load[1],
            IDEAL_NO_LOAD_TOLERANCE,
            SOURCE,
        ),
    ];
    for sigma in [2.0, 5.0, 10.0] {
        let (l, c) = (find(sigma, "lumped")?, find(sigma, "coupled")?);
        let gap = if sigma == 10.0 {
            WIDE_SCATTER_NO_LOAD_GAP
        } else {
            SCATTERED_NO_LOAD_GAP
        };
        checks.push(Check::at_least(
            CASE,
            format!(
                "bands, 20 × 20, σ = {sigma} nm: lumped no-load P5 / coupled P50 − 1 (the \
                 lumped band misses the coupled median)"
            ),
            l.no_load[0] / c.no_load[1] - 1.0,
            gap,
            SOURCE,
        ));
    }
    let width = |r: &Row| r.stall[2] - r.stall[0];
    checks.push(Check::at_least(
        CASE,
        "bands, 20 × 20: coupled stall band width at 10 nm over its width at 2 nm",
        width(find(10.0, "coupled")?) / width(find(2.0, "coupled")?),
        BAND_WIDENING,
        SOURCE,
    ));
    Ok(checks)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_committed_band_study_holds_its_claims() {
        let checks = checks().expect("the committed bands.csv parses");
        assert_eq!(checks.len(), 6, "checks of the band study");
        for c in &checks {
            assert!(c.pass, "{}", c.line());
        }
    }

    #[test]
    fn a_damaged_band_row_is_named() {
        let e = parse("header\n20,x,lumped\n").unwrap_err().to_string();
        assert!(e.contains("20,x,lumped"), "{e}");
    }
}
