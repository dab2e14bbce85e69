//! Small numerical tools: Gauss–Legendre quadrature, a bracketing root finder, and exact first
//! crossings of f(θ) = a cos θ + b sin θ + g θ + d (the form of every stick/slip event function
//! of one post at constant speed).

use std::f64::consts::PI;

/// 8-point Gauss–Legendre nodes on [−1, 1] (positive half; the rule is symmetric).
const GL8_NODES: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_2,
];
/// 8-point Gauss–Legendre weights matching [`GL8_NODES`].
const GL8_WEIGHTS: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];
/// Longest sub-interval (rad) per 8-point Gauss–Legendre panel: the integrands are
/// trigonometric polynomials of low degree, so panels of 0.4 rad integrate them to ≈ 1e-16.
const QUADRATURE_PANEL_RAD: f64 = 0.4;

/// ∫_a^b f, composite 8-point Gauss–Legendre with panels ≤ [`QUADRATURE_PANEL_RAD`].
/// `f` may return several integrands at once (`N` of them).
pub(crate) fn integrate<const N: usize>(
    a: f64,
    b: f64,
    mut f: impl FnMut(f64) -> [f64; N],
) -> [f64; N] {
    let mut total = [0.0; N];
    if b <= a {
        return total;
    }
    let panels = ((b - a) / QUADRATURE_PANEL_RAD).ceil().max(1.0) as usize;
    let width = (b - a) / panels as f64;
    for p in 0..panels {
        let mid = a + (p as f64 + 0.5) * width;
        let half = 0.5 * width;
        for (node, weight) in GL8_NODES.iter().zip(GL8_WEIGHTS) {
            for x in [mid - half * node, mid + half * node] {
                let values = f(x);
                for (t, v) in total.iter_mut().zip(values) {
                    *t += weight * half * v;
                }
            }
        }
    }
    total
}

/// Root of `f` in [a, b] given f(a)·f(b) ≤ 0: Illinois-modified regula falsi with bisection
/// safeguard, to |b − a| ≤ `x_tol` or an exact zero. Returns the point on the `f(b)` side
/// (so the event has happened at the returned point).
pub(crate) fn bracketed_root(
    mut f: impl FnMut(f64) -> f64,
    mut a: f64,
    mut b: f64,
    x_tol: f64,
) -> f64 {
    let mut fa = f(a);
    let mut fb = f(b);
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 || fa.signum() == fb.signum() {
        return b;
    }
    let mut side = 0i8;
    for iteration in 0..200 {
        if (b - a).abs() <= x_tol {
            break;
        }
        // Alternate a secant step with a bisection step every few iterations to guarantee
        // shrinking even for badly scaled functions.
        let mut x = if iteration % 4 == 3 {
            0.5 * (a + b)
        } else {
            (a * fb - b * fa) / (fb - fa)
        };
        if !(x > a.min(b) && x < a.max(b)) {
            x = 0.5 * (a + b);
        }
        let fx = f(x);
        if fx == 0.0 {
            return x;
        }
        if fx.signum() == fb.signum() {
            b = x;
            fb = fx;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        } else {
            a = x;
            fa = fx;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        }
    }
    b
}

/// Monotone-decreasing scalar root: the x in [lo, hi] where `f` changes from > 0 to ≤ 0, by
/// Brent-like regula falsi; `f(lo) > 0 ≥ f(hi)` is assumed.
pub(crate) fn decreasing_root(f: impl FnMut(f64) -> f64, lo: f64, hi: f64, x_tol: f64) -> f64 {
    bracketed_root(f, lo, hi, x_tol)
}

/// f(θ) = a cos θ + b sin θ + g θ + d.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TrigLinear {
    pub a: f64,
    pub b: f64,
    pub g: f64,
    pub d: f64,
}

/// Which way an event function crosses zero.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Crossing {
    /// From < 0 to ≥ 0.
    Upward,
    /// From > 0 to ≤ 0.
    Downward,
}

impl TrigLinear {
    pub fn value(&self, theta: f64) -> f64 {
        let (s, c) = theta.sin_cos();
        self.a * c + self.b * s + self.g * theta + self.d
    }

    pub fn derivative(&self, theta: f64) -> f64 {
        let (s, c) = theta.sin_cos();
        -self.a * s + self.b * c + self.g
    }

    pub fn second_derivative(&self, theta: f64) -> f64 {
        let (s, c) = theta.sin_cos();
        -self.a * c - self.b * s
    }

    /// Critical points (f' = 0) strictly inside (lo, hi), sorted. f' = R cos(θ + ψ) + g with
    /// R = hypot(a, b), ψ = atan2(a, b).
    fn critical_points(&self, lo: f64, hi: f64, out: &mut Vec<f64>) {
        out.clear();
        let r = self.a.hypot(self.b);
        if r == 0.0 || self.g.abs() >= r {
            return;
        }
        let psi = self.a.atan2(self.b);
        let base = (-self.g / r).acos();
        for root in [base - psi, -base - psi] {
            // All θ = root + 2πn inside (lo, hi).
            let mut theta = root + 2.0 * PI * ((lo - root) / (2.0 * PI)).ceil();
            while theta < hi {
                if theta > lo {
                    out.push(theta);
                }
                theta += 2.0 * PI;
            }
        }
        out.sort_by(f64::total_cmp);
    }

    /// Minimum of f on [lo, hi] (at an end or a critical point).
    pub fn min_on(&self, lo: f64, hi: f64, scratch: &mut Vec<f64>) -> f64 {
        self.critical_points(lo, hi, scratch);
        scratch
            .iter()
            .chain([lo, hi].iter())
            .map(|&t| self.value(t))
            .fold(f64::INFINITY, f64::min)
    }

    /// First θ in (lo, hi] where f crosses zero in direction `dir`, located to `x_tol`.
    /// A start already on the far side (f(lo) ≥ 0 for `Upward`) while still moving further
    /// counts as an immediate event at `lo`; a start on the line moving back is not an event.
    pub fn first_crossing(
        &self,
        lo: f64,
        hi: f64,
        dir: Crossing,
        x_tol: f64,
        scratch: &mut Vec<f64>,
    ) -> Option<f64> {
        if hi <= lo {
            return None;
        }
        let sign = match dir {
            Crossing::Upward => 1.0,
            Crossing::Downward => -1.0,
        };
        // Work with h = sign·f, looking for h crossing upward through 0.
        let h = |theta: f64| sign * self.value(theta);
        self.critical_points(lo, hi, scratch);
        let mut start = lo;
        let mut h_start = h(lo);
        // Drop critical points within round-off of the start (a start on a tangency).
        let skip = scratch.iter().take_while(|&&c| c - lo <= x_tol).count();
        for index in skip..=scratch.len() {
            let end = scratch.get(index).copied().unwrap_or(hi);
            let h_end = h(end);
            if index == skip && h_start >= 0.0 {
                // Starting on (or numerically past) the line: an event only if moving further,
                // judged by the first non-vanishing derivative at the start.
                let scale = self.a.abs() + self.b.abs() + self.g.abs();
                let slope = sign * self.derivative(start);
                let moving_on = if slope.abs() > 1e-12 * scale {
                    slope > 0.0
                } else {
                    sign * self.second_derivative(start) > 0.0
                };
                if moving_on {
                    return Some(start);
                }
            } else if h_start < 0.0 && h_end >= 0.0 {
                return Some(bracketed_root(h, start, end, x_tol));
            }
            start = end;
            h_start = h_end;
        }
        None
    }
}

/// Wrap an angle to (−π, π].
pub(crate) fn wrap_angle(theta: f64) -> f64 {
    let wrapped = theta.rem_euclid(2.0 * PI);
    if wrapped > PI {
        wrapped - 2.0 * PI
    } else {
        wrapped
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrature_integrates_trigonometric_polynomials_to_machine_precision() {
        let [sin2, poly] = integrate(0.3, 5.0, |x| [x.sin().powi(2), x * x.cos()]);
        let exact_sin2 = 0.5 * (5.0 - 0.3) - 0.25 * ((10.0f64).sin() - (0.6f64).sin());
        let exact_poly = (5.0 * 5.0f64.sin() + 5.0f64.cos()) - (0.3 * 0.3f64.sin() + 0.3f64.cos());
        assert!(
            (sin2 - exact_sin2).abs() < 1e-14,
            "∫sin² error {}",
            sin2 - exact_sin2
        );
        assert!(
            (poly - exact_poly).abs() < 1e-14,
            "∫x cos x error {}",
            poly - exact_poly
        );
    }

    #[test]
    fn first_crossing_finds_the_earliest_of_several_roots() {
        // f = sin θ − 0.5 crosses upward at π/6 and 13π/6, downward at 5π/6.
        let f = TrigLinear {
            a: 0.0,
            b: 1.0,
            g: 0.0,
            d: -0.5,
        };
        let mut scratch = Vec::new();
        let up = f
            .first_crossing(0.0, 4.0 * PI, Crossing::Upward, 1e-15, &mut scratch)
            .unwrap();
        assert!((up - PI / 6.0).abs() < 1e-13, "upward crossing at {up}");
        let down = f
            .first_crossing(0.0, 4.0 * PI, Crossing::Downward, 1e-15, &mut scratch)
            .unwrap();
        assert!(
            (down - 5.0 * PI / 6.0).abs() < 1e-13,
            "downward crossing at {down}"
        );
        let later = f
            .first_crossing(3.0, 4.0 * PI, Crossing::Upward, 1e-15, &mut scratch)
            .unwrap();
        assert!(
            (later - 13.0 * PI / 6.0).abs() < 1e-12,
            "next upward crossing at {later}"
        );
    }

    #[test]
    fn first_crossing_sees_a_root_between_close_critical_points() {
        // f = cos θ − 0.2 θ + 0.1: has a shallow dip; check against dense sampling.
        let f = TrigLinear {
            a: 1.0,
            b: 0.0,
            g: -0.2,
            d: 0.1,
        };
        let mut scratch = Vec::new();
        let root = f
            .first_crossing(0.0, 20.0, Crossing::Downward, 1e-15, &mut scratch)
            .unwrap();
        let sampled = (0..200_000)
            .map(|i| i as f64 * 1e-4)
            .find(|&x| f.value(x) <= 0.0)
            .unwrap();
        assert!(
            (root - sampled).abs() < 2e-4,
            "root {root} vs sampled {sampled}"
        );
        assert!(
            f.value(root).abs() < 1e-13,
            "residual at root {}",
            f.value(root)
        );
    }

    #[test]
    fn start_on_the_line_moving_away_is_not_an_event() {
        // f = sin θ starts at 0 and rises: a downward search must not fire at 0.
        let f = TrigLinear {
            a: 0.0,
            b: 1.0,
            g: 0.0,
            d: 0.0,
        };
        let mut scratch = Vec::new();
        let down = f.first_crossing(0.0, 2.0, Crossing::Downward, 1e-15, &mut scratch);
        assert!(
            down.is_none(),
            "no downward crossing in (0, 2], got {down:?}"
        );
        let up = f.first_crossing(0.0, 2.0, Crossing::Upward, 1e-15, &mut scratch);
        assert_eq!(
            up,
            Some(0.0),
            "a start on the line moving up is an immediate upward event"
        );
    }
}

/// Solve the small dense system A x = b by Gaussian elimination with partial pivoting; `None`
/// if A is singular to round-off. For the few-unknown least-squares steps of the Anderson
/// acceleration (`crate::attenuation`).
pub(crate) fn solve_small(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    let scale = a
        .iter()
        .flatten()
        .fold(0.0, |m: f64, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    for col in 0..n {
        let pivot = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[pivot][col].abs() <= 1e-14 * scale {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        for row in col + 1..n {
            let factor = a[row][col] / a[col][col];
            for k in col..n {
                a[row][k] -= factor * a[col][k];
            }
            b[row] -= factor * b[col];
        }
    }
    let mut x = vec![0.0; n];
    for row in (0..n).rev() {
        let tail: f64 = (row + 1..n).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - tail) / a[row][row];
    }
    Some(x)
}
