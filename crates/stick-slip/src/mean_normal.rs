//! Closed-form period-mean normal force of one post and its inverse (docs/physics.md §5.1).
//!
//! With N = k_n⟨A_n sin θ − z_s⟩₊ and c = z_s/A_n, averaging over θ gives
//! ⟨N⟩ = k_n A_n (√(1−c²) − c·arccos c)/π for |c| ≤ 1, ⟨N⟩ = −k_n z_s for c ≤ −1 (always in
//! contact) and 0 for c ≥ 1. Written with the contact half-arc φ = arccos c (contact for
//! |θ − π/2| < φ) this is (sin φ − φ cos φ)/π, evaluated by its Taylor series for small φ to
//! avoid cancellation at light preload.

use std::f64::consts::PI;

/// Below this half-arc (rad), sin φ − φ cos φ is evaluated by its Taylor series (the direct
/// form loses digits to cancellation; at 0.1 the series through φ¹¹ is exact to 1e-17).
const SERIES_HALF_ARC_RAD: f64 = 0.1;
/// Relative tolerance of the Newton solve for the half-arc.
const HALF_ARC_TOLERANCE: f64 = 1e-15;

/// Tip height of a post in units of A_n, with the contact half-arc when the post separates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TipHeight {
    /// c = (z_s + g)/A_n.
    pub c: f64,
    /// φ = arccos c ∈ (0, π) if −1 < c < 1 (post separates each period); `None` if c ≤ −1.
    pub half_arc: Option<f64>,
}

impl TipHeight {
    /// A tip height from c directly.
    pub fn from_c(c: f64) -> Self {
        let half_arc = (c > -1.0).then(|| c.min(1.0).acos());
        Self { c, half_arc }
    }
}

/// sin φ − φ cos φ without cancellation.
fn arc_moment(phi: f64) -> f64 {
    if phi < SERIES_HALF_ARC_RAD {
        let p2 = phi * phi;
        phi * p2
            * (1.0 / 3.0
                + p2 * (-1.0 / 30.0
                    + p2 * (1.0 / 840.0 + p2 * (-1.0 / 45360.0 + p2 / 3_991_680.0))))
    } else {
        phi.sin() - phi * phi.cos()
    }
}

/// Period-mean normal force ⟨N⟩/(k_n A_n) of a post at tip height `h`.
pub(crate) fn mean_normal(h: TipHeight) -> f64 {
    match h.half_arc {
        None => -h.c,
        Some(phi) => arc_moment(phi) / PI,
    }
}

/// The tip height at which ⟨N⟩/(k_n A_n) = `mean` (> 0). Closed form when the post never
/// separates (mean ≥ 1 ⇔ c = −mean ≤ −1); otherwise Newton on the half-arc φ, safeguarded by
/// bisection on [0, π], where sin φ − φ cos φ is increasing with derivative φ sin φ.
pub(crate) fn tip_height_for_mean_normal(mean: f64) -> TipHeight {
    if mean >= 1.0 {
        return TipHeight {
            c: -mean,
            half_arc: None,
        };
    }
    let target = PI * mean;
    let (mut lo, mut hi) = (0.0, PI);
    // Small-arc guess from the leading term φ³/3.
    let mut phi = (3.0 * target).cbrt().min(0.5 * PI);
    for _ in 0..200 {
        let residual = arc_moment(phi) - target;
        if residual > 0.0 {
            hi = phi;
        } else {
            lo = phi;
        }
        let slope = phi * phi.sin();
        let mut next = if slope > 0.0 {
            phi - residual / slope
        } else {
            0.5 * (lo + hi)
        };
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        let converged = (next - phi).abs() <= HALF_ARC_TOLERANCE * phi.max(1e-300);
        phi = next;
        if converged || hi - lo <= HALF_ARC_TOLERANCE * hi {
            break;
        }
    }
    TipHeight {
        c: phi.cos(),
        half_arc: Some(phi),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ⟨N⟩ by brute-force averaging of ⟨sin θ − c⟩₊ over a period.
    fn sampled_mean(c: f64) -> f64 {
        let n = 200_000;
        (0..n)
            .map(|i| ((2.0 * PI * (i as f64 + 0.5) / n as f64).sin() - c).max(0.0))
            .sum::<f64>()
            / n as f64
    }

    #[test]
    fn closed_form_mean_normal_matches_sampled_average() {
        for c in [-1.5, -1.0, -0.6, 0.0, 0.4, 0.9, 0.99] {
            let closed = mean_normal(TipHeight::from_c(c));
            let sampled = sampled_mean(c);
            assert!(
                (closed - sampled).abs() < 1e-8,
                "⟨N⟩ at c = {c}: closed {closed} vs sampled {sampled}"
            );
        }
    }

    #[test]
    fn tip_height_inverts_mean_normal_from_light_to_heavy_preload() {
        for mean in [1e-9, 1e-6, 1e-3, 0.05, 0.3, 0.999, 1.0, 2.5] {
            let h = tip_height_for_mean_normal(mean);
            let back = mean_normal(h);
            assert!(
                (back - mean).abs() <= 1e-13 * mean,
                "mean normal {mean}: recovered {back}"
            );
        }
    }

    #[test]
    fn series_and_direct_arc_moment_agree_at_the_switch() {
        let phi = SERIES_HALF_ARC_RAD * (1.0 - 1e-12);
        let below = arc_moment(phi);
        let direct = phi.sin() - phi * phi.cos();
        assert!(
            (below - direct).abs() < 1e-12 * direct,
            "arc moment series {below} vs direct {direct}"
        );
    }
}
