//! Summary statistics of Monte Carlo outputs.
//!
//! * Mean: x₀ + Σ(xᵢ − x₀)/n, exact (bitwise x₀) when every sample equals x₀.
//! * Percentile p: Hyndman & Fan (1996) type 7, x₍ₕ₎ interpolated at h = (n − 1)p on the sorted
//!   sample; equal samples give that value exactly.
//! * Its confidence interval: distribution-free, from order statistics. The number of samples
//!   below the true p-quantile is Binomial(n, p); the ranks l, u = np ∓ z√(np(1 − p)) (normal
//!   approximation, z for [`CONFIDENCE`]) bracket it with ≈ that probability, so
//!   [x₍ₗ₎, x₍ᵤ₎] is the interval (Conover, *Practical Nonparametric Statistics*, §3.2).
//!   Valid for np(1 − p) ≳ 5 (n ≳ 100 for P5/P95); smaller n widens it to the sample range.
//! * Histogram: equal-width bins over the sample range.

use serde::Serialize;

use crate::error::{Result, invalid};

/// Two-sided confidence of the percentile intervals.
pub const CONFIDENCE: f64 = 0.95;
/// Standard normal quantile of (1 + [`CONFIDENCE`])/2.
const Z_CONFIDENCE: f64 = 1.959_963_984_540_054;

/// Mean and percentiles of one output, with 95 % confidence intervals of the percentiles.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Band {
    /// Samples the band is made of.
    pub samples: usize,
    /// Mean.
    pub mean: f64,
    /// 5th percentile.
    pub p5: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// 95 % confidence interval of P5.
    pub p5_ci: [f64; 2],
    /// 95 % confidence interval of P50.
    pub p50_ci: [f64; 2],
    /// 95 % confidence interval of P95.
    pub p95_ci: [f64; 2],
    /// Sample standard deviation (n − 1).
    pub sd: f64,
}

fn sorted(values: &[f64], key: &str) -> Result<Vec<f64>> {
    if values.is_empty() {
        return Err(invalid(key, "no samples"));
    }
    if let Some(v) = values.iter().find(|v| !v.is_finite()) {
        return Err(invalid(key, format!("a sample is {v} (not finite)")));
    }
    let mut s = values.to_vec();
    s.sort_by(f64::total_cmp);
    Ok(s)
}

/// Type-7 percentile `p` ∈ [0, 1] of an ascending sample.
fn percentile_sorted(s: &[f64], p: f64) -> f64 {
    let h = (s.len() - 1) as f64 * p;
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(s.len() - 1);
    s[lo] + (h - lo as f64) * (s[hi] - s[lo])
}

/// Type-7 percentile `p` ∈ [0, 1] of `values`; `key` names the output in errors.
pub fn percentile(values: &[f64], p: f64, key: &str) -> Result<f64> {
    if !(0.0..=1.0).contains(&p) {
        return Err(invalid(key, format!("percentile {p} outside [0, 1]")));
    }
    Ok(percentile_sorted(&sorted(values, key)?, p))
}

/// Order-statistic confidence interval of the p-quantile of an ascending sample.
fn percentile_ci(s: &[f64], p: f64) -> [f64; 2] {
    let n = s.len() as f64;
    let half = Z_CONFIDENCE * (n * p * (1.0 - p)).sqrt();
    // 1-based ranks l = ⌊np − half⌋, u = ⌈np + half⌉ + 1 (Conover's convention), clamped.
    let l = ((n * p - half).floor() as i64).clamp(1, s.len() as i64) as usize;
    let u = ((n * p + half).ceil() as i64 + 1).clamp(1, s.len() as i64) as usize;
    [s[l - 1], s[u - 1]]
}

/// The band of `values`; `key` names the output in errors.
pub fn band(values: &[f64], key: &str) -> Result<Band> {
    let s = sorted(values, key)?;
    let n = s.len();
    let x0 = values[0];
    let mean = x0 + values.iter().map(|x| x - x0).sum::<f64>() / n as f64;
    let sd = if n > 1 {
        (values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt()
    } else {
        0.0
    };
    Ok(Band {
        samples: n,
        mean,
        p5: percentile_sorted(&s, 0.05),
        p50: percentile_sorted(&s, 0.5),
        p95: percentile_sorted(&s, 0.95),
        p5_ci: percentile_ci(&s, 0.05),
        p50_ci: percentile_ci(&s, 0.5),
        p95_ci: percentile_ci(&s, 0.95),
        sd,
    })
}

/// Counts in equal-width bins.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Histogram {
    /// Bin edges, `bins + 1` of them, ascending.
    pub edges: Vec<f64>,
    /// Samples per bin (the last bin includes its upper edge).
    pub counts: Vec<usize>,
}

/// Histogram of `values` in `bins` equal bins over their range (one bin of zero width when all
/// are equal).
pub fn histogram(values: &[f64], bins: usize, key: &str) -> Result<Histogram> {
    if bins == 0 {
        return Err(invalid(key, "histogram needs at least one bin"));
    }
    let s = sorted(values, key)?;
    let (lo, hi) = (s[0], s[s.len() - 1]);
    if lo == hi {
        return Ok(Histogram {
            edges: vec![lo, hi],
            counts: vec![s.len()],
        });
    }
    let width = (hi - lo) / bins as f64;
    let edges = (0..=bins).map(|k| lo + width * k as f64).collect();
    let mut counts = vec![0; bins];
    for x in s {
        counts[(((x - lo) / width) as usize).min(bins - 1)] += 1;
    }
    Ok(Histogram { edges, counts })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distribution::Distribution;
    use motor::rng::SplitMix64;

    #[test]
    fn equal_samples_collapse_the_band_to_that_value_exactly() {
        let x = 0.1 + 0.2; // not representable exactly: the mean must still be bitwise x
        let b = band(&vec![x; 37], "stall_thrust_n").unwrap();
        for (what, v) in [
            ("mean", b.mean),
            ("p5", b.p5),
            ("p50", b.p50),
            ("p95", b.p95),
        ] {
            assert_eq!(v.to_bits(), x.to_bits(), "{what} of equal stall thrusts");
        }
        assert_eq!(b.p5_ci, [x, x], "P5 interval of equal samples");
        assert_eq!(b.sd, 0.0, "spread of equal samples");
    }

    #[test]
    fn type_7_percentiles_match_numpy() {
        // numpy.percentile([1, 2, 3, 4, 10], [5, 50, 95]) = [1.2, 3.0, 8.8]
        let v = [4.0, 1.0, 10.0, 3.0, 2.0];
        assert!(
            (percentile(&v, 0.05, "x").unwrap() - 1.2).abs() < 1e-12,
            "P5"
        );
        assert_eq!(percentile(&v, 0.5, "x").unwrap(), 3.0, "P50");
        assert!(
            (percentile(&v, 0.95, "x").unwrap() - 8.8).abs() < 1e-12,
            "P95"
        );
    }

    /// Percentiles of N(0, 1) samples approach Φ⁻¹(p) with error ∝ 1/√N, and the intervals cover
    /// the true quantile and shrink.
    #[test]
    fn percentiles_converge_as_the_sample_grows() {
        let d = Distribution::Normal { mean: 0.0, sd: 1.0 };
        let truth: [(f64, usize); 3] = [(-1.644_853_6, 0), (0.0, 1), (1.644_853_6, 2)];
        let mut widths = Vec::new();
        for n in [50usize, 200, 1000, 20_000] {
            let mut rng = SplitMix64::new(2026);
            let xs: Vec<f64> = (0..n).map(|_| d.draw(&mut rng)).collect();
            let b = band(&xs, "x").unwrap();
            let est = [b.p5, b.p50, b.p95];
            let ci = [b.p5_ci, b.p50_ci, b.p95_ci];
            for (q, k) in truth {
                // 4 standard errors of a sample quantile: √(p(1−p)/n)/φ(q).
                let p: f64 = [0.05, 0.5, 0.95][k];
                let phi = (-0.5 * q * q).exp() / (2.0 * std::f64::consts::PI).sqrt();
                let se = (p * (1.0 - p) / n as f64).sqrt() / phi;
                assert!(
                    (est[k] - q).abs() < 4.0 * se,
                    "P{} at N = {n}: {}",
                    p * 100.0,
                    est[k]
                );
                assert!(
                    ci[k][0] <= est[k] && est[k] <= ci[k][1],
                    "CI brackets P{}",
                    p * 100.0
                );
            }
            widths.push(b.p95_ci[1] - b.p95_ci[0]);
        }
        assert!(
            widths.windows(2).all(|w| w[1] < w[0]),
            "P95 confidence interval shrinks with N: {widths:?}"
        );
    }

    #[test]
    fn the_histogram_counts_every_sample_once() {
        let v: Vec<f64> = (0..101).map(f64::from).collect();
        let h = histogram(&v, 10, "x").unwrap();
        assert_eq!(
            h.counts.iter().sum::<usize>(),
            101,
            "samples in the histogram"
        );
        assert_eq!(h.edges.len(), 11, "edges");
        assert_eq!(h.counts[9], 11, "the last bin includes the maximum");
    }

    #[test]
    fn empty_or_non_finite_samples_are_refused_naming_the_output() {
        assert!(
            band(&[], "stall_thrust_n")
                .unwrap_err()
                .to_string()
                .starts_with("stall_thrust_n:")
        );
        assert!(
            band(&[1.0, f64::NAN], "efficiency")
                .unwrap_err()
                .to_string()
                .contains("not finite")
        );
    }
}
