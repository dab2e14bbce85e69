//! The effective contact ratio η (docs/physics.md §6): the factor on the Johnson post stiffness k_n
//! for which independent posts (the lumped model, [`crate::lumped`]) pressed with the same load
//! on the same surface reproduce the FEM post forces best in least squares, pooled over several
//! snapshot phases so that the fit sees the whole force-versus-phase profile:
//!
//! η = argmin_η Σ_phases Σ_i (f_i^FEM − f_i^lumped(η k_n))².
//!
//! Minimised over ln η: a grid scan of [`ETA_SEARCH_MIN`, `ETA_SEARCH_MAX`] followed by a
//! golden-section refinement around the best grid point. On a flat stator (no wave, no height
//! scatter) every post carries P/N whatever η is: η is then not identifiable and is reported as
//! `None` with the reason.

use serde::{Deserialize, Serialize};

use crate::lumped::independent_posts;

/// Lower end of the η search interval. Dimensionless; default 1e-3.
pub const ETA_SEARCH_MIN: f64 = 1e-3;
/// Upper end of the η search interval. Dimensionless; default 10.
pub const ETA_SEARCH_MAX: f64 = 10.0;
/// Grid points of the initial scan over ln η. Default 97.
pub const ETA_GRID_POINTS: usize = 97;
/// Relative width in η at which the golden-section search stops. Default 1e-7.
pub const ETA_RELATIVE_TOLERANCE: f64 = 1e-7;
/// A misfit that varies by less than this fraction of Σ f² over the search interval means η is
/// not identifiable. Dimensionless; default 1e-10.
pub const IDENTIFIABILITY_THRESHOLD: f64 = 1e-10;

/// One snapshot: obstacle heights and the FEM forces under the same load.
#[derive(Debug, Clone, PartialEq)]
pub struct FitSample {
    /// Obstacle height h_i (m) of every post (wave height minus initial gap).
    pub height_m: Vec<f64>,
    /// FEM post forces (N).
    pub force_n: Vec<f64>,
    /// Total load (N).
    pub preload_n: f64,
}

/// Result of the η fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EtaFit {
    /// Effective contact ratio η, or `None` if not identifiable.
    pub eta: Option<f64>,
    /// Why η is `None`.
    pub reason: Option<String>,
    /// Johnson series stiffness k_n the ratio refers to (N/m).
    pub k_n_n_per_m: f64,
    /// √(misfit / Σ f²) at the optimum: 0 for a perfect fit.
    pub relative_rms_residual: f64,
    /// Whether the optimum sits at an end of the search interval (then η is a bound, not a fit).
    pub at_search_bound: bool,
    /// Snapshots pooled.
    pub samples: usize,
}

/// Σ over samples and posts of (f^FEM − f^lumped(η k_n))².
pub fn misfit(samples: &[FitSample], k_n_n_per_m: f64, eta: f64) -> f64 {
    samples
        .iter()
        .map(|s| {
            let (f, _) = independent_posts(&s.height_m, eta * k_n_n_per_m, s.preload_n);
            f.iter()
                .zip(&s.force_n)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
        })
        .sum()
}

/// Fits η to the pooled samples (see the module doc).
pub fn fit_eta(samples: &[FitSample], k_n_n_per_m: f64) -> EtaFit {
    let norm: f64 = samples
        .iter()
        .flat_map(|s| s.force_n.iter())
        .map(|f| f * f)
        .sum();
    let empty = |reason: &str| EtaFit {
        eta: None,
        reason: Some(reason.to_string()),
        k_n_n_per_m,
        relative_rms_residual: f64::NAN,
        at_search_bound: false,
        samples: samples.len(),
    };
    if samples.is_empty() || norm <= 0.0 {
        return empty("no snapshot with a non-zero post force to fit");
    }
    let (lo, hi) = (ETA_SEARCH_MIN.ln(), ETA_SEARCH_MAX.ln());
    let step = (hi - lo) / (ETA_GRID_POINTS - 1) as f64;
    let s_of = |t: f64| misfit(samples, k_n_n_per_m, t.exp());
    let grid: Vec<f64> = (0..ETA_GRID_POINTS)
        .map(|k| s_of(lo + step * k as f64))
        .collect();
    let (best, &s_best) = grid
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .expect("grid is not empty");
    let s_worst = grid.iter().copied().fold(0.0, f64::max);
    if s_worst - s_best <= IDENTIFIABILITY_THRESHOLD * norm {
        return EtaFit {
            relative_rms_residual: (s_best / norm).sqrt(),
            ..empty(
                "not identifiable: the lumped post forces do not depend on the post stiffness here \
                 (flat stator without height scatter: every post carries P/N)",
            )
        };
    }
    // Golden-section search on [best − 1, best + 1] grid steps (clamped to the interval).
    let mut a = lo + step * best.saturating_sub(1) as f64;
    let mut b = lo + step * (best + 1).min(ETA_GRID_POINTS - 1) as f64;
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let mut x1 = b - ratio * (b - a);
    let mut x2 = a + ratio * (b - a);
    let (mut s1, mut s2) = (s_of(x1), s_of(x2));
    while b - a > ETA_RELATIVE_TOLERANCE {
        if s1 <= s2 {
            b = x2;
            x2 = x1;
            s2 = s1;
            x1 = b - ratio * (b - a);
            s1 = s_of(x1);
        } else {
            a = x1;
            x1 = x2;
            s1 = s2;
            x2 = a + ratio * (b - a);
            s2 = s_of(x2);
        }
    }
    let (t, s) = if s1 <= s2 { (x1, s1) } else { (x2, s2) };
    let (t, s) = if s_best < s {
        (lo + step * best as f64, s_best)
    } else {
        (t, s)
    };
    let at_search_bound = best == 0 || best == ETA_GRID_POINTS - 1;
    EtaFit {
        eta: Some(t.exp()),
        reason: at_search_bound.then(|| {
            format!(
                "optimum at the end of the search interval [{ETA_SEARCH_MIN}, {ETA_SEARCH_MAX}]"
            )
        }),
        k_n_n_per_m,
        relative_rms_residual: (s / norm).sqrt(),
        at_search_bound,
        samples: samples.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wave_heights(n: usize, phase: f64) -> Vec<f64> {
        (0..n)
            .map(|i| 20e-9 * (phase - 2.0 * std::f64::consts::PI * i as f64 / 9.7).sin())
            .collect()
    }

    #[test]
    fn forces_made_by_the_lumped_model_give_back_its_eta() {
        for true_eta in [0.37, 1.03, 1.6] {
            forces_made_with_eta_give_it_back(true_eta);
        }
    }

    /// η above 1 (a stiffer contact than k_n, e.g. the FEM at low preload) is reported as
    /// fitted, never clamped.
    fn forces_made_with_eta_give_it_back(true_eta: f64) {
        let k_n = 1.8e6;
        let samples: Vec<FitSample> = (0..4)
            .map(|p| {
                let h = wave_heights(100, p as f64 * std::f64::consts::FRAC_PI_2);
                let (f, _) = independent_posts(&h, true_eta * k_n, 0.4);
                FitSample {
                    height_m: h,
                    force_n: f,
                    preload_n: 0.4,
                }
            })
            .collect();
        let fit = fit_eta(&samples, k_n);
        let eta = fit.eta.expect("η identifiable on a wave");
        assert!(
            (eta / true_eta - 1.0).abs() < 1e-5,
            "fitted η {eta} vs the η {true_eta} that made the forces"
        );
        assert!(
            fit.relative_rms_residual < 1e-5,
            "residual of an exact fit: {}",
            fit.relative_rms_residual
        );
    }

    #[test]
    fn a_flat_stator_makes_eta_unidentifiable() {
        let samples = vec![FitSample {
            height_m: vec![0.0; 10],
            force_n: vec![0.1; 10],
            preload_n: 1.0,
        }];
        let fit = fit_eta(&samples, 1.8e6);
        assert!(
            fit.eta.is_none(),
            "η on a flat stator must be None, got {:?}",
            fit.eta
        );
        assert!(
            fit.reason.unwrap().contains("not identifiable"),
            "reason names the identifiability problem"
        );
    }
}
