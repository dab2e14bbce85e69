//! Stated input distributions and their seeded, reproducible draws.
//!
//! Each Monte Carlo sample k gets its own generator, seeded with [`sample_seed`]`(seed, k)`
//! (a SplitMix64 step of `seed + k·φ`, φ the 64-bit golden ratio), so sample k is the same for
//! any N ≥ k + 1 and any thread count, and the draws are bitwise identical for one seed.
//! Normal deviates: Box–Muller ([`motor::rng`]). Truncated normal: rejection from the
//! parent normal (exact; refused when the interval holds less than
//! [`MIN_TRUNCATED_MASS`] of the parent's probability, where rejection would stall).

use motor::rng::SplitMix64;
use serde::Serialize;

use crate::error::{Result, invalid};

/// Smallest probability of the parent normal inside a truncation interval (dimensionless).
/// Rejection sampling needs ≈ 1/mass tries per draw; 1e-3 caps that at ≈ 1000.
pub const MIN_TRUNCATED_MASS: f64 = 1e-3;

/// Tries of the rejection sampler before it reports failure (never reached when the mass check
/// passed: the chance is (1 − 1e-3)^100 000 ≈ 4e-44).
const MAX_REJECTION_TRIES: usize = 100_000;

/// 2⁶⁴/φ, the SplitMix64 increment: spreads consecutive sample indices over the seed space.
const GOLDEN_GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// A distribution of one scalar input, in the input's SI unit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Distribution {
    /// Always `value`.
    Fixed {
        /// The value.
        value: f64,
    },
    /// N(mean, sd²), sd ≥ 0.
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation (≥ 0; 0 gives `mean` exactly).
        sd: f64,
    },
    /// Uniform on [low, high].
    Uniform {
        /// Lower end.
        low: f64,
        /// Upper end (≥ low; equal gives `low` exactly).
        high: f64,
    },
    /// N(mean, sd²) conditioned on [low, high].
    TruncatedNormal {
        /// Parent mean.
        mean: f64,
        /// Parent standard deviation (≥ 0).
        sd: f64,
        /// Lower end.
        low: f64,
        /// Upper end.
        high: f64,
    },
}

/// Standard normal CDF Φ(x) = erfc(−x/√2)/2 (used only for the truncation-mass check).
fn normal_cdf(x: f64) -> f64 {
    0.5 * erfc_approx(-x / std::f64::consts::SQRT_2)
}

/// erfc(z) by Numerical Recipes' `erfcc` (Chebyshev fit, fractional error < 1.2e-7 everywhere).
fn erfc_approx(z: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.5 * z.abs());
    let poly = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * poly.exp();
    if z >= 0.0 { r } else { 2.0 - r }
}

impl Distribution {
    /// The nominal value: the mean (normal), the midpoint (uniform), the parent mean clamped
    /// into the interval (truncated normal).
    pub fn nominal(&self) -> f64 {
        match *self {
            Self::Fixed { value } => value,
            Self::Normal { mean, .. } => mean,
            Self::Uniform { low, high } => 0.5 * (low + high),
            Self::TruncatedNormal {
                mean, low, high, ..
            } => mean.clamp(low, high),
        }
    }

    /// Whether a draw can differ from the nominal value.
    pub fn is_degenerate(&self) -> bool {
        match *self {
            Self::Fixed { .. } => true,
            Self::Normal { sd, .. } | Self::TruncatedNormal { sd, .. } => sd == 0.0,
            Self::Uniform { low, high } => low == high,
        }
    }

    /// Checks the parameters; errors name `key`.
    pub fn validate(&self, key: &str) -> Result<()> {
        let finite = |v: f64, what: &str| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(invalid(key, format!("{what} is {v}, must be finite")))
            }
        };
        match *self {
            Self::Fixed { value } => finite(value, "value"),
            Self::Normal { mean, sd } => {
                finite(mean, "mean")?;
                check_sd(key, sd)
            }
            Self::Uniform { low, high } => {
                finite(low, "low")?;
                finite(high, "high")?;
                if low > high {
                    return Err(invalid(
                        key,
                        format!("bounds reversed: low {low} > high {high}"),
                    ));
                }
                Ok(())
            }
            Self::TruncatedNormal {
                mean,
                sd,
                low,
                high,
            } => {
                finite(mean, "mean")?;
                check_sd(key, sd)?;
                finite(low, "low")?;
                finite(high, "high")?;
                if low > high {
                    return Err(invalid(
                        key,
                        format!("bounds reversed: low {low} > high {high}"),
                    ));
                }
                if sd == 0.0 {
                    if !(low..=high).contains(&mean) {
                        return Err(invalid(
                            key,
                            format!("mean {mean} outside [{low}, {high}] with zero spread"),
                        ));
                    }
                    return Ok(());
                }
                let mass = normal_cdf((high - mean) / sd) - normal_cdf((low - mean) / sd);
                if mass < MIN_TRUNCATED_MASS {
                    return Err(invalid(
                        key,
                        format!(
                            "[{low}, {high}] holds {mass:.2e} of N({mean}, {sd}²), below {MIN_TRUNCATED_MASS}: \
                             widen the interval or move the mean"
                        ),
                    ));
                }
                Ok(())
            }
        }
    }

    /// One draw from `rng` (validate first). Zero spread returns the nominal value exactly
    /// without consuming the generator, so a degenerate input never shifts another's stream.
    pub fn draw(&self, rng: &mut SplitMix64) -> f64 {
        if self.is_degenerate() {
            return self.nominal();
        }
        match *self {
            Self::Fixed { value } => value,
            Self::Normal { mean, sd } => mean + sd * standard_normal(rng),
            Self::Uniform { low, high } => low + (high - low) * (1.0 - rng.next_open01()),
            Self::TruncatedNormal {
                mean,
                sd,
                low,
                high,
            } => {
                for _ in 0..MAX_REJECTION_TRIES {
                    let x = mean + sd * standard_normal(rng);
                    if (low..=high).contains(&x) {
                        return x;
                    }
                }
                mean.clamp(low, high)
            }
        }
    }
}

fn check_sd(key: &str, sd: f64) -> Result<()> {
    if sd >= 0.0 && sd.is_finite() {
        Ok(())
    } else {
        Err(invalid(
            key,
            format!("standard deviation {sd} must be ≥ 0 and finite"),
        ))
    }
}

/// One N(0, 1) deviate (the first Box–Muller output).
fn standard_normal(rng: &mut SplitMix64) -> f64 {
    rng.normals(1)[0]
}

/// The seed of sample `index` of a run seeded with `seed`.
pub fn sample_seed(seed: u64, index: u64) -> u64 {
    SplitMix64::new(seed.wrapping_add(index.wrapping_mul(GOLDEN_GAMMA))).next_u64()
}

/// A named scattered input (`name` carries the unit, e.g. `preload_n`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ScatterInput {
    /// Name with unit.
    pub name: String,
    /// Its distribution.
    pub distribution: Distribution,
}

/// The input values of sample `index`: one draw per input, in order, from the sample's own
/// generator (seeded by [`sample_seed`]); also returns that generator's next 64 bits as a seed
/// for the sample's own fields (e.g. the post-height scatter).
pub fn draw_inputs(inputs: &[ScatterInput], seed: u64, index: u64) -> (Vec<f64>, u64) {
    let mut rng = SplitMix64::new(sample_seed(seed, index));
    let values = inputs
        .iter()
        .map(|i| i.distribution.draw(&mut rng))
        .collect();
    (values, rng.next_u64())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_spread_draws_the_nominal_value_exactly() {
        let mut rng = SplitMix64::new(3);
        for d in [
            Distribution::Normal { mean: 0.3, sd: 0.0 },
            Distribution::Uniform {
                low: 0.3,
                high: 0.3,
            },
            Distribution::TruncatedNormal {
                mean: 0.3,
                sd: 0.0,
                low: 0.0,
                high: 1.0,
            },
        ] {
            assert_eq!(d.draw(&mut rng), 0.3, "draw of a zero-spread {d:?}");
        }
    }

    #[test]
    fn the_same_seed_draws_bitwise_identical_inputs() {
        let inputs = vec![
            ScatterInput {
                name: "mu".into(),
                distribution: Distribution::Normal {
                    mean: 0.3,
                    sd: 0.03,
                },
            },
            ScatterInput {
                name: "preload_n".into(),
                distribution: Distribution::TruncatedNormal {
                    mean: 40.0,
                    sd: 5.0,
                    low: 30.0,
                    high: 50.0,
                },
            },
        ];
        for k in 0..50 {
            let (a, sa) = draw_inputs(&inputs, 42, k);
            let (b, sb) = draw_inputs(&inputs, 42, k);
            assert_eq!(
                a.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                b.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                "inputs of sample {k}"
            );
            assert_eq!(sa, sb, "field seed of sample {k}");
            assert!((30.0..=50.0).contains(&a[1]), "truncated preload {}", a[1]);
        }
        assert_ne!(draw_inputs(&inputs, 42, 0).0, draw_inputs(&inputs, 43, 0).0);
    }

    #[test]
    fn uniform_and_truncated_draws_have_their_stated_moments() {
        let mut rng = SplitMix64::new(11);
        let u = Distribution::Uniform {
            low: 1.0,
            high: 3.0,
        };
        let n = 100_000;
        let xs: Vec<f64> = (0..n).map(|_| u.draw(&mut rng)).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!((mean - 2.0).abs() < 0.01, "uniform mean {mean}");
        assert!((var - 1.0 / 3.0).abs() < 0.01, "uniform variance {var}");
        // N(0,1) truncated to [0, ∞): mean √(2/π).
        let t = Distribution::TruncatedNormal {
            mean: 0.0,
            sd: 1.0,
            low: 0.0,
            high: 1e300,
        };
        let m = (0..n).map(|_| t.draw(&mut rng)).sum::<f64>() / n as f64;
        assert!(
            (m - (2.0 / std::f64::consts::PI).sqrt()).abs() < 0.01,
            "half-normal mean {m}"
        );
    }

    #[test]
    fn negative_spread_and_reversed_bounds_are_refused_naming_the_key() {
        let e = Distribution::Normal {
            mean: 0.0,
            sd: -1.0,
        }
        .validate("scatter.height_scatter")
        .unwrap_err();
        assert!(e.to_string().starts_with("scatter.height_scatter:"), "{e}");
        let e = Distribution::Uniform {
            low: 2.0,
            high: 1.0,
        }
        .validate("scatter.preload")
        .unwrap_err();
        assert!(e.to_string().contains("bounds reversed"), "{e}");
        let e = Distribution::TruncatedNormal {
            mean: 0.0,
            sd: 1.0,
            low: 10.0,
            high: 11.0,
        }
        .validate("scatter.mu")
        .unwrap_err();
        assert!(e.to_string().starts_with("scatter.mu:"), "{e}");
    }

    #[test]
    fn the_normal_cdf_matches_tabulated_values() {
        assert!((normal_cdf(0.0) - 0.5).abs() < 1e-7, "Φ(0)");
        assert!((normal_cdf(1.959_964) - 0.975).abs() < 1e-6, "Φ(1.96)");
        assert!((normal_cdf(-3.0) - 0.001_349_898).abs() < 1e-7, "Φ(−3)");
    }
}
