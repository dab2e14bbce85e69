//! The energy-conserving wave at the ball's contact: the ball draws the stator power it takes
//! from the wave, so the amplitude it sees is below the incoming A₀.
//!
//! **Model** (the post array's, docs/physics.md §5.5, for one contact): the wave power that
//! crosses the contact, P_in (W; the pipeline's power per beam width × the contact's width 2a,
//! capped by the aperture), flows along +x; the ball draws P_d(α) at the amplitude αA₀ it
//! sees, and by the midpoint rule it sees the power P_in − ½P_d, so
//! α = √(max(0, 1 − ½P_d(α)/P_in)), P_out = P_in − P_d. At each imposed speed the ball's
//! periodic state is solved at the amplitude of that fixed point; the books P_in − P_out =
//! stator power close exactly (P_out is defined by them), and the ball's own books close as at
//! constant amplitude.
//!
//! **Solution.** With P_d growing with α, g(α) = α − √(max(0, 1 − ½P_d(α)/P_in)) is increasing
//! and changes sign on [T(1), 1] (T(1) = the amplitude for the draw at A₀; halved until g < 0
//! where the draw at A₀ exceeds 2P_in); secant steps kept
//! inside the bracket (bisection where a step leaves it) until |g| < `tolerance`. A secant of a
//! dozen lines rather than a root-finding crate: the bracket is known and the function monotone.
//!
//! **Validity.** The contact's strip of width 2a is the narrowest share of the beam the ball can
//! draw from: diffraction refills the strip behind a contact this narrow (ka ≪ 1), so the
//! amplitude drop is an upper bound of the effect (the whole beam's share, P_d/P_beam, is the
//! lower bound; the pipeline reports both). The wave's velocity and shape unchanged; steady
//! state; the contact's own reflection neglected.

use crate::error::{BallError, Result};

/// Default tolerance on |g(α)| of the amplitude's fixed point (of A₀). Default 1e-10.
pub const DEFAULT_AMPLITUDE_TOLERANCE: f64 = 1e-10;
/// Evaluations of the draw at most per fixed point. Default 60.
const MAX_EVALUATIONS: usize = 60;

/// The wave power crossing the contact and the fixed point's tolerance.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WaveShare {
    /// Wave power crossing the contact's width (W).
    pub power_in_w: f64,
    /// Tolerance on |g(α)| (of A₀).
    pub tolerance: f64,
}

impl WaveShare {
    /// The share `power_in_w` (W) with the default tolerance.
    pub fn new(power_in_w: f64) -> Result<Self> {
        crate::error::positive("wave_share.power_in_w", power_in_w)?;
        Ok(Self {
            power_in_w,
            tolerance: DEFAULT_AMPLITUDE_TOLERANCE,
        })
    }

    /// The amplitude the ball sees for the draw `draw_w` (W) at its contact.
    pub fn target(&self, draw_w: f64) -> f64 {
        (1.0 - 0.5 * draw_w / self.power_in_w).max(0.0).sqrt()
    }

    /// The self-consistent α and what `at` returned there; `at(α)` solves the ball at αA₀ and
    /// returns its draw (W) and a value the caller keeps. Starts from `warm` (a neighbouring
    /// speed's α) when it lies in the bracket.
    pub fn settle<T>(
        &self,
        warm: Option<f64>,
        mut at: impl FnMut(f64) -> Result<(f64, T)>,
    ) -> Result<(f64, T)> {
        let (d1, v1) = at(1.0)?;
        let g1 = 1.0 - self.target(d1);
        if g1 < 0.0 && g1.abs() >= self.tolerance {
            return Err(BallError::NoSteadyState {
                what: format!(
                    "the ball returns {:.4e} W to the wave at the full amplitude: the \
                     energy-conserving wave describes a ball that draws power",
                    -d1
                ),
            });
        }
        let mut search = Search {
            lo: (0.0, -1.0),
            hi: (1.0, g1),
            best: (g1.abs(), 1.0, v1),
        };
        if search.best.0 < self.tolerance || self.bracket(&mut at, self.target(d1), &mut search)? {
            return Ok((search.best.1, search.best.2));
        }
        self.refine(&mut at, warm, search)
    }

    /// The lower end of the bracket, g < 0 (α → 0 draws nothing, so g → −1): from T(1),
    /// halving (0.5 where T(1) = 0). `true` when a point settled on the way.
    fn bracket<T>(
        &self,
        at: &mut impl FnMut(f64) -> Result<(f64, T)>,
        start: f64,
        search: &mut Search<T>,
    ) -> Result<bool> {
        let mut x = if start > 0.0 { start } else { 0.5 };
        loop {
            let (d, v) = at(x)?;
            let g = x - self.target(d);
            if search.record(x, g, v, self.tolerance) {
                return Ok(true);
            }
            if g < 0.0 {
                return Ok(false);
            }
            if x < 1e-3 {
                return Err(self.not_bracketed(x, g));
            }
            x *= 0.5;
        }
    }

    /// Secant steps inside the bracket (bisection where a step leaves it or the bracket is
    /// down to a few tolerances), from `warm` when it lies inside.
    fn refine<T>(
        &self,
        at: &mut impl FnMut(f64) -> Result<(f64, T)>,
        warm: Option<f64>,
        mut search: Search<T>,
    ) -> Result<(f64, T)> {
        let mut x = warm
            .filter(|&w| w > search.lo.0 && w < search.hi.0)
            .unwrap_or_else(|| search.secant());
        for _ in 0..MAX_EVALUATIONS {
            let (d, v) = at(x)?;
            let g = x - self.target(d);
            if search.record(x, g, v, self.tolerance) || search.width() < self.tolerance {
                return Ok((search.best.1, search.best.2));
            }
            let secant = search.secant();
            x = if secant > search.lo.0
                && secant < search.hi.0
                && search.width() > 4.0 * self.tolerance
            {
                secant
            } else {
                0.5 * (search.lo.0 + search.hi.0)
            };
        }
        Err(BallError::NoSteadyState {
            what: format!(
                "the amplitude at the ball did not settle to {:e} in {MAX_EVALUATIONS} \
                 evaluations (best |α − T(α)| = {:.3e})",
                self.tolerance, search.best.0
            ),
        })
    }

    fn not_bracketed(&self, alpha: f64, g: f64) -> BallError {
        BallError::NoSteadyState {
            what: format!(
                "the amplitude at the ball is not bracketed: α − T(α) = {g:.3e} > 0 down to \
                 α = {alpha:.3e} (the draw does not fall with the amplitude)"
            ),
        }
    }
}

/// The bracket [lo, hi] of g(α) = α − T(α) (g(lo) < 0 ≤ g(hi)) and the best point so far
/// (|g|, α, the caller's value there).
struct Search<T> {
    lo: (f64, f64),
    hi: (f64, f64),
    best: (f64, f64, T),
}

impl<T> Search<T> {
    /// Records g(x) = g with the caller's value; `true` once |g| < `tolerance` somewhere.
    fn record(&mut self, x: f64, g: f64, value: T, tolerance: f64) -> bool {
        if g.abs() < self.best.0 {
            self.best = (g.abs(), x, value);
        }
        if g < 0.0 {
            self.lo = (x, g);
        } else {
            self.hi = (x, g);
        }
        self.best.0 < tolerance
    }

    fn secant(&self) -> f64 {
        let (lo, hi) = (self.lo, self.hi);
        lo.0 - lo.1 * (hi.0 - lo.0) / (hi.1 - lo.1)
    }

    fn width(&self) -> f64 {
        self.hi.0 - self.lo.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A draw ∝ α² has the closed-form fixed point α² = 1/(1 + ½c/P_in).
    #[test]
    fn settles_to_the_closed_form_of_a_quadratic_draw() {
        let share = WaveShare::new(2.0).unwrap();
        let c = 0.7;
        let (alpha, draw) = share.settle(None, |a| Ok((c * a * a, c * a * a))).unwrap();
        let exact = (1.0 / (1.0 + 0.5 * c / 2.0)).sqrt();
        assert!((alpha - exact).abs() < 1e-9, "{alpha} vs {exact}");
        assert!((share.target(draw) - alpha).abs() < 1e-9);
    }

    #[test]
    fn a_weak_draw_keeps_the_full_amplitude_to_the_tolerance() {
        let share = WaveShare::new(1.0).unwrap();
        let (alpha, _) = share.settle(None, |a| Ok((1e-12 * a * a, ()))).unwrap();
        assert!((alpha - 1.0).abs() < 1e-10);
    }

    /// Beyond twice the power at A₀ (T(1) = 0) the fixed point still exists and is found.
    #[test]
    fn a_draw_beyond_twice_the_power_settles_to_its_closed_form() {
        let share = WaveShare::new(1.0).unwrap();
        let (alpha, _) = share.settle(None, |a| Ok((3.0 * a * a, ()))).unwrap();
        assert!((alpha - 0.4f64.sqrt()).abs() < 1e-9, "{alpha}");
    }

    #[test]
    fn a_ball_returning_power_is_refused_by_name() {
        let share = WaveShare::new(1.0).unwrap();
        let e = share.settle(None, |a| Ok((-0.1 * a * a, ()))).unwrap_err();
        assert!(e.to_string().contains("returns"), "{e}");
    }

    #[test]
    fn a_non_positive_power_is_refused() {
        assert!(WaveShare::new(0.0).is_err());
        assert!(WaveShare::new(f64::NAN).is_err());
    }
}
