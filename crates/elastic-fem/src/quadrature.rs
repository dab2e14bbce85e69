//! Quadrature rules on the reference tetrahedron {ξ,η,ζ ≥ 0, ξ+η+ζ ≤ 1} (volume 1/6) and the
//! reference triangle {ξ,η ≥ 0, ξ+η ≤ 1} (area 1/2). Weights sum to the reference measure.
//!
//! Which rule is used where:
//! - Tet4 stiffness: [`tet_degree1`] (exact: constant integrand).
//! - Tet10 stiffness, straight-sided (mid-edge nodes at edge midpoints): [`tet_degree2`]; the
//!   integrand ∇N·C·∇N is a degree-2 polynomial, so the 4-point rule is exact.
//! - Tet10 stiffness, curved (any mid-edge node off its edge midpoint), body forces, L2 errors:
//!   [`tet_degree5`], the 14-point positive-weight rule of Walkington (2000, "Quadrature on
//!   simplices of arbitrary dimension"). For a curved Tet10 it integrates adj(J)ᵀ∇N (degree 3)
//!   exactly, which keeps the patch test exact; the stiffness itself is rational there and is
//!   integrated approximately.
//! - Tri3/Tri6 surface loads: [`triangle_degree4`] (Dunavant 1985, 6 points), exact for a
//!   quadratic shape function times a quadratic area-normal of a curved Tri6.

use std::sync::LazyLock;

/// A quadrature rule: reference points and weights.
#[derive(Debug, Clone)]
pub struct QuadratureRule<const D: usize> {
    /// Reference coordinates of the points.
    pub points: Vec<[f64; D]>,
    /// Weights (sum = reference measure).
    pub weights: Vec<f64>,
    /// Polynomial degree integrated exactly.
    pub degree: usize,
}

/// Quadrature rule on the reference tetrahedron.
pub type TetRule = QuadratureRule<3>;
/// Quadrature rule on the reference triangle.
pub type TriangleRule = QuadratureRule<2>;

/// Barycentric orbit (a,a,a,1−3a): 4 points.
fn orbit_aaab(a: f64) -> Vec<[f64; 3]> {
    let b = 1.0 - 3.0 * a;
    vec![[a, a, a], [b, a, a], [a, b, a], [a, a, b]]
}

/// Barycentric orbit (a,a,½−a,½−a): 6 points.
fn orbit_aabb(a: f64) -> Vec<[f64; 3]> {
    let b = 0.5 - a;
    vec![
        [a, a, b],
        [a, b, a],
        [b, a, a],
        [a, b, b],
        [b, a, b],
        [b, b, a],
    ]
}

fn tet_rule(orbits: &[(Vec<[f64; 3]>, f64)], degree: usize) -> TetRule {
    let mut points = Vec::new();
    let mut weights = Vec::new();
    for (orbit, w) in orbits {
        for p in orbit {
            points.push(*p);
            weights.push(*w);
        }
    }
    TetRule {
        points,
        weights,
        degree,
    }
}

static TET_DEGREE1: LazyLock<TetRule> =
    LazyLock::new(|| tet_rule(&[(vec![[0.25; 3]], 1.0 / 6.0)], 1));

static TET_DEGREE2: LazyLock<TetRule> = LazyLock::new(|| {
    // a = (5 − √5)/20.
    let a = (5.0 - 5f64.sqrt()) / 20.0;
    tet_rule(&[(orbit_aaab(a), 1.0 / 24.0)], 2)
});

static TET_DEGREE5: LazyLock<TetRule> = LazyLock::new(|| {
    tet_rule(
        &[
            (
                orbit_aaab(0.310_885_919_263_300_6),
                0.018_781_320_953_002_64,
            ),
            (
                orbit_aaab(0.092_735_250_310_891_23),
                0.012_248_840_519_393_66,
            ),
            (
                orbit_aabb(0.045_503_704_125_649_65),
                0.007_091_003_462_846_911,
            ),
        ],
        5,
    )
});

static TRIANGLE_DEGREE2: LazyLock<TriangleRule> = LazyLock::new(|| TriangleRule {
    points: vec![
        [1.0 / 6.0, 1.0 / 6.0],
        [2.0 / 3.0, 1.0 / 6.0],
        [1.0 / 6.0, 2.0 / 3.0],
    ],
    weights: vec![1.0 / 6.0; 3],
    degree: 2,
});

static TRIANGLE_DEGREE4: LazyLock<TriangleRule> = LazyLock::new(|| {
    let (a, wa) = (0.445_948_490_915_965, 0.223_381_589_678_011 / 2.0);
    let (b, wb) = (0.091_576_213_509_771, 0.109_951_743_655_322 / 2.0);
    TriangleRule {
        points: vec![
            [a, a],
            [1.0 - 2.0 * a, a],
            [a, 1.0 - 2.0 * a],
            [b, b],
            [1.0 - 2.0 * b, b],
            [b, 1.0 - 2.0 * b],
        ],
        weights: vec![wa, wa, wa, wb, wb, wb],
        degree: 4,
    }
});

/// 1-point rule at the centroid, exact for degree 1.
pub fn tet_degree1() -> &'static TetRule {
    &TET_DEGREE1
}

/// 4-point rule, exact for degree 2.
pub fn tet_degree2() -> &'static TetRule {
    &TET_DEGREE2
}

/// 14-point rule with positive weights, exact for degree 5.
pub fn tet_degree5() -> &'static TetRule {
    &TET_DEGREE5
}

/// 3-point triangle rule, exact for degree 2.
pub fn triangle_degree2() -> &'static TriangleRule {
    &TRIANGLE_DEGREE2
}

/// 6-point triangle rule (Dunavant), exact for degree 4.
pub fn triangle_degree4() -> &'static TriangleRule {
    &TRIANGLE_DEGREE4
}

#[cfg(test)]
mod tests {
    use super::*;

    fn factorial(n: u32) -> f64 {
        (1..=n).map(f64::from).product()
    }

    /// ∫ ξ^a η^b ζ^c over the reference tetrahedron = a! b! c! / (a+b+c+3)!.
    #[test]
    fn tet_rules_integrate_monomials_exactly_up_to_their_degree() {
        for rule in [tet_degree1(), tet_degree2(), tet_degree5()] {
            for a in 0..=rule.degree as u32 {
                for b in 0..=(rule.degree as u32 - a) {
                    for c in 0..=(rule.degree as u32 - a - b) {
                        let exact =
                            factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3);
                        let q: f64 = rule
                            .points
                            .iter()
                            .zip(&rule.weights)
                            .map(|(p, w)| {
                                w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32)
                            })
                            .sum();
                        assert!(
                            (q - exact).abs() < 1e-14,
                            "tet rule of degree {}: integral of x^{a} y^{b} z^{c} = {q}, exact {exact}",
                            rule.degree
                        );
                    }
                }
            }
        }
    }

    /// ∫ ξ^a η^b over the reference triangle = a! b! / (a+b+2)!.
    #[test]
    fn triangle_rules_integrate_monomials_exactly_up_to_their_degree() {
        for rule in [triangle_degree2(), triangle_degree4()] {
            for a in 0..=rule.degree as u32 {
                for b in 0..=(rule.degree as u32 - a) {
                    let exact = factorial(a) * factorial(b) / factorial(a + b + 2);
                    let q: f64 = rule
                        .points
                        .iter()
                        .zip(&rule.weights)
                        .map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32))
                        .sum();
                    assert!(
                        (q - exact).abs() < 1e-13,
                        "triangle rule of degree {}: integral of x^{a} y^{b} = {q}, exact {exact}",
                        rule.degree
                    );
                }
            }
        }
    }
}
