//! Element geometry: signed volumes and Jacobians of Tet4/Tet10, areas of Tri3/Tri6, and the
//! radius-ratio shape measure.
//!
//! Reference elements follow gmsh: the tetrahedron has corners (0,0,0), (1,0,0), (0,1,0),
//! (0,0,1) and, in gmsh node order, midside nodes 4:(0,1) 5:(1,2) 6:(2,0) 7:(3,0) 8:(3,2) 9:(3,1);
//! the triangle has corners (0,0), (1,0), (0,1) and midside nodes 3:(0,1) 4:(1,2) 5:(2,0).

/// Point in space (m).
pub type Point = [f64; 3];

/// Corner pairs of the six Tet10 edges in gmsh order (midside node 4 + index).
pub const TET10_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [3, 0], [3, 2], [3, 1]];

/// Local index (4..=9) of the gmsh Tet10 midside node on the edge between corners `a` and `b`.
pub fn tet10_edge_node(a: usize, b: usize) -> Option<usize> {
    TET10_EDGES
        .iter()
        .position(|e| (e[0] == a && e[1] == b) || (e[0] == b && e[1] == a))
        .map(|i| 4 + i)
}

pub(crate) fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn cross(a: Point, b: Point) -> Point {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn norm(a: Point) -> f64 {
    dot(a, a).sqrt()
}

/// Signed volume of the straight tetrahedron with corners `p`:
/// V = det[p1 − p0, p2 − p0, p3 − p0] / 6, positive for gmsh's (right-handed) corner order.
pub fn tet4_signed_volume(p: [Point; 4]) -> f64 {
    let a = sub(p[1], p[0]);
    let b = sub(p[2], p[0]);
    let c = sub(p[3], p[0]);
    dot(a, cross(b, c)) / 6.0
}

/// Gradients of the ten Tet10 shape functions with respect to the reference coordinates
/// (ξ, η, ζ) at barycentric point `l` = (λ0, λ1, λ2, λ3): corners N_k = λk(2λk − 1),
/// midside nodes N = 4 λi λj.
fn tet10_shape_gradients(l: [f64; 4]) -> [[f64; 3]; 10] {
    const BARYCENTRIC_GRADIENTS: [[f64; 3]; 4] = [
        [-1.0, -1.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let g = BARYCENTRIC_GRADIENTS;
    let mut out = [[0.0; 3]; 10];
    for k in 0..4 {
        for d in 0..3 {
            out[k][d] = (4.0 * l[k] - 1.0) * g[k][d];
        }
    }
    for (e, [i, j]) in TET10_EDGES.iter().copied().enumerate() {
        for d in 0..3 {
            out[4 + e][d] = 4.0 * (l[j] * g[i][d] + l[i] * g[j][d]);
        }
    }
    out
}

/// det(∂x/∂ξ) of a Tet10 at barycentric point `l`; equals 6 V for a straight-sided tet.
pub fn tet10_jacobian_det(p: &[Point; 10], l: [f64; 4]) -> f64 {
    let grads = tet10_shape_gradients(l);
    let mut jac = [[0.0; 3]; 3];
    for (node, grad) in p.iter().zip(grads.iter()) {
        for r in 0..3 {
            for c in 0..3 {
                jac[r][c] += node[r] * grad[c];
            }
        }
    }
    dot(jac[0], cross(jac[1], jac[2]))
}

/// Barycentric points of a degree-3 exact tetrahedron rule (Stroud T3:3-1 / Keast 5-point):
/// the centroid with weight −4/5 and four points (1/2, 1/6, 1/6, 1/6) with weight 9/20
/// (weights sum to 1, to be multiplied by the reference volume 1/6).
const TET_DEGREE3_RULE: [([f64; 4], f64); 5] = [
    ([0.25, 0.25, 0.25, 0.25], -0.8),
    ([0.5, 1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0], 0.45),
    ([1.0 / 6.0, 0.5, 1.0 / 6.0, 1.0 / 6.0], 0.45),
    ([1.0 / 6.0, 1.0 / 6.0, 0.5, 1.0 / 6.0], 0.45),
    ([1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0, 0.5], 0.45),
];

/// Volume of a (possibly curved) Tet10: ∫ det J dξ over the reference tet. det J is a cubic
/// polynomial in ξ, so the degree-3 rule is exact.
pub fn tet10_volume(p: &[Point; 10]) -> f64 {
    TET_DEGREE3_RULE
        .iter()
        .map(|(l, w)| w * tet10_jacobian_det(p, *l))
        .sum::<f64>()
        / 6.0
}

/// Barycentric points where the Tet10 Jacobian is sampled for inversion checks: corners, edge
/// midpoints, centroid and the quadrature points.
fn tet10_sample_points() -> Vec<[f64; 4]> {
    let mut points = Vec::with_capacity(15);
    for k in 0..4 {
        let mut l = [0.0; 4];
        l[k] = 1.0;
        points.push(l);
    }
    for [i, j] in TET10_EDGES {
        let mut l = [0.0; 4];
        l[i] = 0.5;
        l[j] = 0.5;
        points.push(l);
    }
    points.extend(TET_DEGREE3_RULE.iter().map(|(l, _)| *l));
    points
}

/// Minimum and maximum of det J over the Tet10 sample points.
pub fn tet10_jacobian_range(p: &[Point; 10]) -> (f64, f64) {
    tet10_sample_points()
        .into_iter()
        .map(|l| tet10_jacobian_det(p, l))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| {
            (lo.min(d), hi.max(d))
        })
}

/// Normalised radius ratio ρ = 3 r_in / R_circ of the straight tet with corners `p`:
/// 1 for the regular tetrahedron, → 0 for slivers and needles (Shewchuk 2002, "What is a good
/// linear element?"). r_in = 3|V| / ΣA_faces; R_circ = |a²(b×c) + b²(c×a) + c²(a×b)| / (12|V|)
/// with a, b, c the edge vectors from corner 0.
pub fn radius_ratio(p: [Point; 4]) -> f64 {
    let volume = tet4_signed_volume(p).abs();
    let faces = [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]];
    let face_area_sum: f64 = faces
        .iter()
        .map(|f| triangle_area([p[f[0]], p[f[1]], p[f[2]]]))
        .sum();
    let a = sub(p[1], p[0]);
    let b = sub(p[2], p[0]);
    let c = sub(p[3], p[0]);
    let numerator = {
        let (bc, ca, ab) = (cross(b, c), cross(c, a), cross(a, b));
        let (a2, b2, c2) = (dot(a, a), dot(b, b), dot(c, c));
        [
            a2 * bc[0] + b2 * ca[0] + c2 * ab[0],
            a2 * bc[1] + b2 * ca[1] + c2 * ab[1],
            a2 * bc[2] + b2 * ca[2] + c2 * ab[2],
        ]
    };
    let denominator = face_area_sum * norm(numerator);
    if volume <= 0.0 || denominator <= 0.0 || !denominator.is_finite() {
        return 0.0;
    }
    // 3 r_in / R = 3 (3V/ΣA) / (|num| / 12V) = 108 V² / (ΣA |num|)
    (108.0 * volume * volume / denominator).clamp(0.0, 1.0)
}

/// Root-mean-square edge length of the straight tet with corners `p`.
pub fn rms_edge_length(p: [Point; 4]) -> f64 {
    let pairs = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];
    let sum: f64 = pairs
        .iter()
        .map(|[i, j]| dot(sub(p[*i], p[*j]), sub(p[*i], p[*j])))
        .sum();
    (sum / 6.0).sqrt()
}

/// Area of the straight triangle with corners `p`.
pub fn triangle_area(p: [Point; 3]) -> f64 {
    0.5 * norm(cross(sub(p[1], p[0]), sub(p[2], p[0])))
}

/// Unnormalised normal (p1 − p0) × (p2 − p0) of a triangle; right-hand rule over the corners.
pub fn triangle_normal(p: [Point; 3]) -> Point {
    cross(sub(p[1], p[0]), sub(p[2], p[0]))
}

/// Area of a (possibly curved) Tri6: ∫ |∂x/∂u × ∂x/∂v| du dv with the 7-point degree-5 rule of
/// Radon (Strang & Fix, table 4.2). The integrand is not polynomial for curved triangles; the
/// rule's error is far below the geometric discretisation error of the mesh.
pub fn tri6_area(p: &[Point; 6]) -> f64 {
    let sqrt15 = 15.0_f64.sqrt();
    let a1 = (6.0 - sqrt15) / 21.0;
    let a2 = (6.0 + sqrt15) / 21.0;
    let w1 = (155.0 - sqrt15) / 1200.0;
    let w2 = (155.0 + sqrt15) / 1200.0;
    let rule: [([f64; 2], f64); 7] = [
        ([1.0 / 3.0, 1.0 / 3.0], 9.0 / 40.0),
        ([a1, a1], w1),
        ([1.0 - 2.0 * a1, a1], w1),
        ([a1, 1.0 - 2.0 * a1], w1),
        ([a2, a2], w2),
        ([1.0 - 2.0 * a2, a2], w2),
        ([a2, 1.0 - 2.0 * a2], w2),
    ];
    rule.iter()
        .map(|([u, v], w)| {
            let l = [1.0 - u - v, *u, *v];
            // d(λ0, λ1, λ2)/du = (−1, 1, 0), /dv = (−1, 0, 1)
            let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
            let edges = [[0, 1], [1, 2], [2, 0]];
            let mut du = [0.0; 3];
            let mut dv = [0.0; 3];
            for k in 0..3 {
                let gu = (4.0 * l[k] - 1.0) * dl[k][0];
                let gv = (4.0 * l[k] - 1.0) * dl[k][1];
                for d in 0..3 {
                    du[d] += gu * p[k][d];
                    dv[d] += gv * p[k][d];
                }
            }
            for (e, [i, j]) in edges.iter().enumerate() {
                let gu = 4.0 * (l[*j] * dl[*i][0] + l[*i] * dl[*j][0]);
                let gv = 4.0 * (l[*j] * dl[*i][1] + l[*i] * dl[*j][1]);
                for d in 0..3 {
                    du[d] += gu * p[3 + e][d];
                    dv[d] += gv * p[3 + e][d];
                }
            }
            w * norm(cross(du, dv))
        })
        .sum::<f64>()
        * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;

    const UNIT_TET: [Point; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];

    fn straight_tet10(c: [Point; 4]) -> [Point; 10] {
        let mut p = [[0.0; 3]; 10];
        p[..4].copy_from_slice(&c);
        for (e, [i, j]) in TET10_EDGES.iter().enumerate() {
            for d in 0..3 {
                p[4 + e][d] = 0.5 * (c[*i][d] + c[*j][d]);
            }
        }
        p
    }

    #[test]
    fn unit_tet_volume_is_one_sixth() {
        assert!(
            (tet4_signed_volume(UNIT_TET) - 1.0 / 6.0).abs() < 1e-15,
            "tet volume"
        );
        let swapped = [UNIT_TET[0], UNIT_TET[2], UNIT_TET[1], UNIT_TET[3]];
        assert!(
            tet4_signed_volume(swapped) < 0.0,
            "swapped corners give a negative volume"
        );
    }

    #[test]
    fn straight_tet10_volume_and_jacobian_match_tet4() {
        let c = [
            [0.1, 0.2, 0.3],
            [1.3, 0.1, 0.2],
            [0.2, 1.1, 0.4],
            [0.3, 0.2, 0.9],
        ];
        let p = straight_tet10(c);
        let v4 = tet4_signed_volume(c);
        assert!(
            (tet10_volume(&p) - v4).abs() < 1e-14,
            "Tet10 volume of a straight tet"
        );
        let (lo, hi) = tet10_jacobian_range(&p);
        assert!(
            (lo - 6.0 * v4).abs() < 1e-13 && (hi - 6.0 * v4).abs() < 1e-13,
            "constant det J = 6V"
        );
    }

    #[test]
    fn curved_tet10_volume_matches_cubic_polynomial_exactly() {
        // Map x = ξ + s ξ η, y = η, z = ζ on the unit tet: det J = 1 + s η, volume = 1/6 + s/24.
        let s = 0.3;
        let mut p = straight_tet10(UNIT_TET);
        // Only node 5 (edge 1-2, at ξ = η = 1/2) moves: x gains s/4.
        p[5][0] += s / 4.0;
        let expected = 1.0 / 6.0 + s / 24.0;
        assert!(
            (tet10_volume(&p) - expected).abs() < 1e-14,
            "curved Tet10 volume {}",
            tet10_volume(&p)
        );
    }

    #[test]
    fn regular_tet_has_radius_ratio_one_and_sliver_near_zero() {
        let regular = [
            [1.0, 1.0, 1.0],
            [1.0, -1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0],
        ];
        assert!(
            (radius_ratio(regular) - 1.0).abs() < 1e-12,
            "regular tet radius ratio"
        );
        let sliver = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 1e-6],
        ];
        assert!(radius_ratio(sliver) < 1e-5, "sliver radius ratio");
    }

    #[test]
    fn tri6_area_of_flat_triangle_equals_tri3_area() {
        let c = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 1.0]];
        let mut p = [[0.0; 3]; 6];
        p[..3].copy_from_slice(&c);
        for (e, [i, j]) in [[0, 1], [1, 2], [2, 0]].iter().enumerate() {
            for d in 0..3 {
                p[3 + e][d] = 0.5 * (c[*i][d] + c[*j][d]);
            }
        }
        assert!(
            (tri6_area(&p) - triangle_area(c)).abs() < 1e-14,
            "flat Tri6 area"
        );
    }

    #[test]
    fn tet10_edge_node_follows_gmsh_order() {
        assert_eq!(tet10_edge_node(0, 1), Some(4), "edge 0-1");
        assert_eq!(tet10_edge_node(2, 3), Some(8), "edge 2-3");
        assert_eq!(tet10_edge_node(3, 1), Some(9), "edge 1-3");
        assert_eq!(tet10_edge_node(2, 2), None, "no edge 2-2");
    }
}
