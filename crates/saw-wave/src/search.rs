//! Velocity search: the limiting velocity, a bracketing scan of the real boundary determinants,
//! and Brent's root refinement.
//!
//! Formula: the limiting velocity v_L is the lowest velocity at which one of the eight Stroh roots
//! becomes real (a partial wave stops decaying); it lies at or below the slowest bulk wave along
//! x₁. It is found by a scan from 0.2·v_bulk upward and bisection of "all roots complex". A
//! surface wave is a sign change of det H(v) (see [`crate::boundary`]) on [0.2·v_L, v_L); the scan
//! is denser near v_L, where most surface waves of piezoelectric cuts lie, and the first (slowest)
//! sign change is refined by Brent's method to machine precision. Source: R. P. Brent,
//! *Algorithms for Minimization without Derivatives* (Prentice-Hall 1973), ch. 4 (zeroin).
//!
//! Range of validity: one sign change per root, i.e. roots that are not double and are farther
//! apart than the scan step near them (≈ 0.002·v_L just below v_L). A cut whose only surface waves
//! are leaky has no sign change below v_L (the caller reports it).

use crate::stroh::StrohSystem;

/// Lowest scanned velocity, as a fraction of the bound it is scanned to.
const SCAN_START_FRACTION: f64 = 0.2;
/// Points of the limiting-velocity scan and of the determinant scan.
const LIMIT_SCAN_POINTS: usize = 24;
const DETERMINANT_SCAN_POINTS: usize = 48;
/// Relative bracket width at which bisection of v_L and Brent's method stop.
const RELATIVE_TOLERANCE: f64 = 1e-14;
/// The determinant scan stops this far (relative) below v_L, where all roots still decay.
const TOP_GAP: f64 = 1e-9;

/// Scaled limiting velocity.
pub(crate) fn limiting_velocity(system: &StrohSystem) -> Result<f64, &'static str> {
    let bulk = system.slowest_bulk_velocity_along_x1();
    let bound = |v: f64| system.decaying_roots(v).map(|r| r.is_some());
    let mut lo = SCAN_START_FRACTION * bulk;
    if !bound(lo)? {
        return Err("partial waves do not decay even at 0.2 times the slowest bulk velocity");
    }
    let mut hi = bulk;
    for i in 1..=LIMIT_SCAN_POINTS {
        let v = bulk
            * (SCAN_START_FRACTION
                + (1.0 - SCAN_START_FRACTION) * i as f64 / LIMIT_SCAN_POINTS as f64);
        if !bound(v)? {
            hi = v;
            break;
        }
        lo = v;
    }
    while hi - lo > RELATIVE_TOLERANCE * hi {
        let mid = 0.5 * (lo + hi);
        if bound(mid)? { lo = mid } else { hi = mid }
    }
    Ok(lo)
}

/// A bracket [a, b] of a sign change with the function values at its ends.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Bracket {
    pub a: f64,
    pub b: f64,
    pub fa: f64,
    pub fb: f64,
}

/// The scan velocities on [0.2 v_L, v_L(1 − 10⁻⁹)], denser toward v_L (cubic spacing).
pub(crate) fn scan_velocities(limiting: f64) -> impl Iterator<Item = f64> {
    let top = limiting * (1.0 - TOP_GAP);
    let span = top * (1.0 - SCAN_START_FRACTION);
    (0..=DETERMINANT_SCAN_POINTS).map(move |i| {
        let s = 1.0 - i as f64 / DETERMINANT_SCAN_POINTS as f64;
        top - span * s * s * s
    })
}

/// Tracks the first sign change of a sequence of samples.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SignChange {
    previous: Option<(f64, f64)>,
    pub bracket: Option<Bracket>,
}

impl SignChange {
    /// Feeds one sample (v, f(v)).
    pub fn push(&mut self, v: f64, f: f64) {
        if self.bracket.is_some() {
            return;
        }
        if let Some((a, fa)) = self.previous
            && (fa < 0.0) != (f < 0.0)
        {
            self.bracket = Some(Bracket { a, b: v, fa, fb: f });
        }
        self.previous = Some((v, f));
    }
}

/// Brent's root finder on a sign-change bracket.
pub(crate) fn brent<E>(
    mut f: impl FnMut(f64) -> Result<f64, E>,
    bracket: Bracket,
) -> Result<f64, E> {
    let Bracket {
        mut a,
        mut b,
        mut fa,
        mut fb,
    } = bracket;
    if fa.abs() < fb.abs() {
        (a, b, fa, fb) = (b, a, fb, fa);
    }
    let (mut c, mut fc, mut d) = (a, fa, b - a);
    let mut bisected = true;
    for _ in 0..200 {
        if fb == 0.0 || (b - a).abs() <= RELATIVE_TOLERANCE * b.abs() {
            break;
        }
        let mut s = if fa != fc && fb != fc {
            a * fb * fc / ((fa - fb) * (fa - fc))
                + b * fa * fc / ((fb - fa) * (fb - fc))
                + c * fa * fb / ((fc - fa) * (fc - fb))
        } else {
            b - fb * (b - a) / (fb - fa)
        };
        let outside = (s - (3.0 * a + b) / 4.0) * (s - b) >= 0.0;
        let slow = if bisected {
            (s - b).abs() >= 0.5 * (b - c).abs()
        } else {
            (s - b).abs() >= 0.5 * (c - d).abs()
        };
        bisected = outside || slow;
        if bisected {
            s = 0.5 * (a + b);
        }
        let fs = f(s)?;
        (d, c, fc) = (c, b, fb);
        if (fa < 0.0) != (fs < 0.0) {
            (b, fb) = (s, fs);
        } else {
            (a, fa) = (s, fs);
        }
        if fa.abs() < fb.abs() {
            (a, b, fa, fb) = (b, a, fb, fa);
        }
    }
    Ok(b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_the_root_of_a_cubic_to_machine_precision() {
        let f = |x: f64| Ok::<_, ()>((x - 1.234_567_890_123) * (x * x + 1.0));
        let root = brent(
            f,
            Bracket {
                a: 0.0,
                b: 3.0,
                fa: f(0.0).unwrap(),
                fb: f(3.0).unwrap(),
            },
        )
        .unwrap();
        assert!((root - 1.234_567_890_123).abs() < 1e-13, "root {root}");
    }

    #[test]
    fn sign_change_keeps_the_first_bracket() {
        let mut s = SignChange::default();
        for (v, f) in [(1.0, 2.0), (2.0, 1.0), (3.0, -1.0), (4.0, 1.0)] {
            s.push(v, f);
        }
        let b = s.bracket.unwrap();
        assert_eq!((b.a, b.b), (2.0, 3.0));
    }
}
