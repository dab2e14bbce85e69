//! Gauss–Legendre quadrature (nodes by Newton iteration on P_n, Abramowitz & Stegun 25.4.29),
//! composite over equal panels. Used by the checks of the closed forms (pressure and traction
//! integrals, the hysteresis loop's ∮Q dδ); exact for polynomials of degree ≤ 2n − 1 on each
//! panel, so smooth integrands converge to round-off with a few panels.

use std::f64::consts::PI;

/// Nodes and weights of the n-point Gauss–Legendre rule on [−1, 1].
#[derive(Debug, Clone, PartialEq)]
pub struct GaussLegendre {
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

impl GaussLegendre {
    /// The n-point rule (n ≥ 1); nodes found to round-off by Newton's method from
    /// Tricomi's initial guesses cos(π(i − ¼)/(n + ½)).
    pub fn new(n: usize) -> Self {
        let n = n.max(1);
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        for i in 0..n.div_ceil(2) {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre(n, x);
            dp = if d.is_finite() { d } else { dp };
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            nodes[i] = -x;
            nodes[n - 1 - i] = x;
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        Self { nodes, weights }
    }

    /// ∫_a^b f over `panels` equal panels.
    pub fn integrate(&self, a: f64, b: f64, panels: usize, f: impl Fn(f64) -> f64) -> f64 {
        let panels = panels.max(1);
        let h = (b - a) / panels as f64;
        let mut sum = 0.0;
        for p in 0..panels {
            let mid = a + (p as f64 + 0.5) * h;
            let mut s = 0.0;
            for (x, w) in self.nodes.iter().zip(&self.weights) {
                s += w * f(mid + 0.5 * h * x);
            }
            sum += 0.5 * h * s;
        }
        sum
    }
}

/// P_n(x) and P_n'(x) by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let k = k as f64;
        let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    let d = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_is_exact_for_degree_2n_minus_1() {
        let rule = GaussLegendre::new(8);
        let got = rule.integrate(-1.0, 2.0, 1, |x| x.powi(15) - 3.0 * x.powi(4));
        let exact = (2f64.powi(16) - 1.0) / 16.0 - 3.0 * (32.0 + 1.0) / 5.0;
        assert!(
            (got - exact).abs() < 1e-10 * exact.abs(),
            "∫x¹⁵−3x⁴: {got} vs {exact}"
        );
    }

    #[test]
    fn gauss_legendre_integrates_sine_to_round_off() {
        let rule = GaussLegendre::new(16);
        let got = rule.integrate(0.0, PI, 4, f64::sin);
        assert!((got - 2.0).abs() < 1e-14, "∫₀^π sin = {got}");
    }
}
