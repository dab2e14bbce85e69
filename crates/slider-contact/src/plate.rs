//! Bending of the free slider body ("pressure" and "point" preload mechanisms): a Kirchhoff plate
//! of the whole slider outline (length L × width W, thickness t, free edges, the real margins),
//! discretised by conforming Bogner–Fox–Schmit rectangles (bicubic Hermite, nodal dofs w, w_x,
//! w_y, w_xy; F. K. Bogner, R. L. Fox & L. A. Schmit, Proc. Conf. Matrix Methods in Structural
//! Mechanics, Wright-Patterson AFB, 1965), whose energy is
//!
//! U = D/2 ∫ [w_xx² + w_yy² + 2ν w_xx w_yy + 2(1−ν) w_xy²] dA,  D = E t³ / (12 (1 − ν²)).
//!
//! The post forces (upward, on the underside) and the preload (downward: a uniform pressure P/(LW)
//! on the back or a point force P at (x, y)) are nodal loads through the shape functions; w is
//! positive away from the stator. The three rigid modes of the free plate (w = 1, x, y) are removed
//! by setting w = 0 at three corners: for a self-equilibrated load (post forces balancing the
//! preload in force and both moments, which the contact solver enforces) the reactions there vanish
//! and the deflection is the free plate's up to a rigid motion, which the contact solver's
//! multipliers (approach and two rotations) absorb. The stiffness is factorised once (sparse
//! Cholesky of `elastic_fem::sparse`); one application to the post forces is a pair of triangular
//! solves.
//!
//! **Split with the lattice operator (no double counting).** The lattice operator keeps the
//! body's local part — the half-space disk term plus the bonded-layer correction of
//! [`crate::layer`], i.e. the compliance of the body *relative to its back* — and this plate adds
//! the deflection *of the back* (mid-surface). In Fourier space (wavenumber k) the plate term is
//! 1/(D k⁴) and the local term tends to the half-space 2/(E* k) for kt ≫ 1 and to the thin-layer
//! compression t/M for kt ≪ 1: each is the exact leading term of the free layer in its own range,
//! and neither contains the other. What neither contains is Mindlin's transverse shear
//! deflection 1/(κ G t k²), (kt)²/4 of the bending term for Si: below 3 % for wavelengths
//! ≥ 2π t/0.35 ≈ 9 mm (the slider-scale bending), ≈ 25 % at kt = 1 (wavelength 3 mm), where the
//! bending term is still ten times the local one. Valid for L, W ≫ t (5 × 0.5 mm: 10 t); for
//! wavelengths ≲ t (the wave, λ = 0.41 mm, the post pitch) the plate term is ≲ 1 % of the local
//! term and its element size (≤ t/2) does not matter.

use contact_springs::Material;
use elastic_fem::sparse::{NumericCholesky, Ordering, SymbolicCholesky, SymmetricMatrix};

use crate::error::{Result, invalid};

/// Plate elements per body thickness t along each side (element size ≤ t / this). The plate
/// resolves bending on scales ≥ t; four times finer elements change the deflection at the posts
/// under a central point load by < 0.1 % of its largest value (`plate::tests`). Dimensionless; default 2.
pub const ELEMENTS_PER_THICKNESS: f64 = 2.0;
/// Fewest plate elements along a side (small test sliders). Default 8.
pub const MIN_ELEMENTS_PER_SIDE: usize = 8;

/// 4-point Gauss–Legendre rule on [0, 1] (exact for degree 7: the bicubic energy integrand is
/// at most degree 6 in each variable).
const GAUSS_4: [(f64, f64); 4] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_93),
    (0.330_009_478_207_571_9, 0.326_072_577_431_273_07),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_07),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_93),
];

/// The 1D cubic Hermite functions on an element of length h at ξ ∈ [0, 1], for function
/// `k` = 2·end + kind (kind 0: value at the end, 1: slope at the end), derivative order 0, 1, 2 in
/// the physical coordinate.
fn hermite(k: usize, xi: f64, h: f64, order: usize) -> f64 {
    let (v, d1, d2) = match k {
        0 => (
            1.0 - 3.0 * xi * xi + 2.0 * xi.powi(3),
            -6.0 * xi + 6.0 * xi * xi,
            -6.0 + 12.0 * xi,
        ),
        1 => (
            h * (xi - 2.0 * xi * xi + xi.powi(3)),
            h * (1.0 - 4.0 * xi + 3.0 * xi * xi),
            h * (-4.0 + 6.0 * xi),
        ),
        2 => (
            3.0 * xi * xi - 2.0 * xi.powi(3),
            6.0 * xi - 6.0 * xi * xi,
            6.0 - 12.0 * xi,
        ),
        _ => (
            h * (-xi * xi + xi.powi(3)),
            h * (-2.0 * xi + 3.0 * xi * xi),
            h * (-2.0 + 6.0 * xi),
        ),
    };
    match order {
        0 => v,
        1 => d1 / h,
        _ => d2 / (h * h),
    }
}

/// The 16 element functions: (corner a ∈ {0,1} along x, corner b along y, nodal dof
/// 0 = w, 1 = w_x, 2 = w_y, 3 = w_xy) → (x Hermite index, y Hermite index).
fn element_functions() -> [(usize, usize, usize, usize, usize); 16] {
    let mut out = [(0, 0, 0, 0, 0); 16];
    let mut n = 0;
    for a in 0..2 {
        for b in 0..2 {
            for dof in 0..4 {
                let (sx, sy) = (dof & 1, dof >> 1);
                out[n] = (a, b, dof, 2 * a + sx, 2 * b + sy);
                n += 1;
            }
        }
    }
    out
}

/// The free Kirchhoff plate of the slider outline, factorised, with the posts' interpolation.
#[derive(Debug)]
pub struct FreePlate {
    elements_x: usize,
    elements_y: usize,
    hx: f64,
    hy: f64,
    /// Reduced dof of each global dof (`usize::MAX`: a fixed corner w).
    reduced: Vec<usize>,
    factor: NumericCholesky,
    /// The reduced stiffness K (upper triangle), kept for the contact preconditioner.
    stiffness: SymmetricMatrix,
    /// Per post: its 16 (reduced dof, shape value) pairs.
    post_weights: Vec<[(usize, f64); 16]>,
    /// The same pairs with a fixed corner dof sent to a scratch slot (index = reduced dim):
    /// the scatter and gather of every iteration without a branch.
    post_slots: Vec<[(u32, f64); 16]>,
    /// Flexural rigidity D (N·m).
    pub flexural_rigidity_nm: f64,
}

impl FreePlate {
    /// Meshes and factorises the plate L × W × t of `material`; `posts_m` are the post centres
    /// (x, y) from the slider's (−x, −y) corner (m).
    pub fn new(
        length_m: f64,
        width_m: f64,
        thickness_m: f64,
        material: &Material,
        posts_m: &[(f64, f64)],
    ) -> Result<Self> {
        let count = |side: f64| {
            ((side * ELEMENTS_PER_THICKNESS / thickness_m).ceil() as usize)
                .max(MIN_ELEMENTS_PER_SIDE)
        };
        Self::with_elements(
            length_m,
            width_m,
            thickness_m,
            material,
            posts_m,
            count(length_m),
            count(width_m),
        )
    }

    /// As [`FreePlate::new`] with a given number of elements along x and y (≥ 1).
    pub fn with_elements(
        length_m: f64,
        width_m: f64,
        thickness_m: f64,
        material: &Material,
        posts_m: &[(f64, f64)],
        ex: usize,
        ey: usize,
    ) -> Result<Self> {
        let e = material.youngs_modulus_pa();
        let nu = material.poisson_ratio;
        let d = e * thickness_m.powi(3) / (12.0 * (1.0 - nu * nu));
        let nodes_y = ey + 1;
        let n_dof = 4 * (ex + 1) * nodes_y;
        let fixed = [0, ex * nodes_y, ey].map(|node| 4 * node);
        let mut reduced = vec![usize::MAX; n_dof];
        let mut next = 0;
        for (dof, r) in reduced.iter_mut().enumerate() {
            if !fixed.contains(&dof) {
                *r = next;
                next += 1;
            }
        }
        let mut plate = Self {
            elements_x: ex,
            elements_y: ey,
            hx: length_m / ex as f64,
            hy: width_m / ey as f64,
            reduced,
            factor: placeholder_factor()?,
            stiffness: placeholder_matrix()?,
            post_weights: Vec::new(),
            post_slots: Vec::new(),
            flexural_rigidity_nm: d,
        };
        let matrix = plate.stiffness(d, nu, next)?;
        plate.factor = SymbolicCholesky::analyze(&matrix, Ordering::Amd)
            .and_then(|s| s.factor(&matrix))
            .map_err(|e| invalid("slider_thickness_m", thickness_m, format!("plate: {e}")))?;
        plate.stiffness = matrix;
        plate.post_weights = posts_m.iter().map(|&(x, y)| plate.weights(x, y)).collect();
        let scratch = u32::try_from(next).expect("plate dofs fit in u32");
        plate.post_slots = plate
            .post_weights
            .iter()
            .map(|w| w.map(|(r, s)| (u32::try_from(r).unwrap_or(scratch), s)))
            .collect();
        Ok(plate)
    }

    /// Global dof of (node a along x, node b along y, nodal dof).
    fn dof(&self, a: usize, b: usize, k: usize) -> usize {
        4 * (a * (self.elements_y + 1) + b) + k
    }

    /// Element (ix, iy) and local (ξ, η) of a point (clamped onto the plate).
    fn locate(&self, x: f64, y: f64) -> (usize, usize, f64, f64) {
        let ix = ((x / self.hx).floor().max(0.0) as usize).min(self.elements_x - 1);
        let iy = ((y / self.hy).floor().max(0.0) as usize).min(self.elements_y - 1);
        (
            ix,
            iy,
            (x / self.hx - ix as f64).clamp(0.0, 1.0),
            (y / self.hy - iy as f64).clamp(0.0, 1.0),
        )
    }

    /// The 16 (reduced dof, w shape value) pairs at a point.
    fn weights(&self, x: f64, y: f64) -> [(usize, f64); 16] {
        let (ix, iy, xi, eta) = self.locate(x, y);
        element_functions().map(|(a, b, k, fx, fy)| {
            (
                self.reduced[self.dof(ix + a, iy + b, k)],
                hermite(fx, xi, self.hx, 0) * hermite(fy, eta, self.hy, 0),
            )
        })
    }

    /// The element stiffness (16 × 16), the same for every element.
    fn element_stiffness(&self, d: f64, nu: f64) -> [[f64; 16]; 16] {
        let funcs = element_functions();
        let mut k = [[0.0; 16]; 16];
        for &(xi, wx) in &GAUSS_4 {
            for &(eta, wy) in &GAUSS_4 {
                let curv: Vec<[f64; 3]> = funcs
                    .iter()
                    .map(|&(_, _, _, fx, fy)| {
                        [
                            hermite(fx, xi, self.hx, 2) * hermite(fy, eta, self.hy, 0),
                            hermite(fx, xi, self.hx, 0) * hermite(fy, eta, self.hy, 2),
                            hermite(fx, xi, self.hx, 1) * hermite(fy, eta, self.hy, 1),
                        ]
                    })
                    .collect();
                let w = wx * wy * self.hx * self.hy * d;
                for p in 0..16 {
                    for q in 0..16 {
                        let (a, b) = (curv[p], curv[q]);
                        k[p][q] += w
                            * (a[0] * b[0]
                                + a[1] * b[1]
                                + nu * (a[0] * b[1] + a[1] * b[0])
                                + 2.0 * (1.0 - nu) * a[2] * b[2]);
                    }
                }
            }
        }
        k
    }

    /// Assembles the reduced stiffness (upper triangle, CSC).
    fn stiffness(&self, d: f64, nu: f64, dim: usize) -> Result<SymmetricMatrix> {
        let ke = self.element_stiffness(d, nu);
        let funcs = element_functions();
        let mut entries: Vec<(usize, usize, f64)> = Vec::new();
        for ix in 0..self.elements_x {
            for iy in 0..self.elements_y {
                let dofs = funcs.map(|(a, b, k, _, _)| self.reduced[self.dof(ix + a, iy + b, k)]);
                for p in 0..16 {
                    for q in 0..16 {
                        let (r, c) = (dofs[p], dofs[q]);
                        if r != usize::MAX && c != usize::MAX && r <= c {
                            entries.push((c, r, ke[p][q]));
                        }
                    }
                }
            }
        }
        entries.sort_unstable_by_key(|&(c, r, _)| (c, r));
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
        let mut last: Option<(usize, usize)> = None;
        for (c, r, v) in entries {
            if last == Some((c, r)) {
                *values.last_mut().expect("an entry") += v;
                continue;
            }
            while col_ptr.len() <= c {
                col_ptr.push(row_idx.len());
            }
            row_idx.push(r);
            values.push(v);
            last = Some((c, r));
        }
        col_ptr.push(row_idx.len());
        SymmetricMatrix::from_upper_parts(dim, col_ptr, row_idx, values)
            .map_err(|e| invalid("slider_thickness_m", d, format!("plate assembly: {e}")))
    }

    /// The reduced stiffness K (upper triangle, CSC).
    pub(crate) fn stiffness_matrix(&self) -> &SymmetricMatrix {
        &self.stiffness
    }

    /// The factor of K (its symbolic analysis serves any matrix of K's pattern).
    pub(crate) fn factor(&self) -> &NumericCholesky {
        &self.factor
    }

    /// Per post: its 16 (reduced dof, w shape value) pairs (`usize::MAX`: a fixed corner).
    pub(crate) fn post_weights(&self) -> &[[(usize, f64); 16]] {
        &self.post_weights
    }

    pub(crate) fn reduced_dim(&self) -> usize {
        self.factor.symbolic().dim()
    }

    /// Deflection at the posts (m, up) of nodal loads `load` (reduced dofs, N; one extra
    /// scratch entry at the end, ignored).
    fn deflection_at_posts(&self, mut load: Vec<f64>, out_m: &mut [f64], add: bool) {
        let dim = self.reduced_dim();
        load.resize(dim + 1, 0.0);
        self.factor
            .solve_in_place(&mut load[..dim])
            .expect("the plate factor solves finite loads");
        load[dim] = 0.0;
        for (o, w) in out_m.iter_mut().zip(&self.post_slots) {
            let u: f64 = w.iter().map(|&(r, s)| s * load[r as usize]).sum();
            *o = if add { *o + u } else { u };
        }
    }

    /// out += G f: the upward deflection at the posts (m) of upward post forces f (N).
    pub fn add_post_deflection(&self, force_n: &[f64], out_m: &mut [f64]) {
        let mut load = vec![0.0; self.reduced_dim() + 1];
        for (f, w) in force_n.iter().zip(&self.post_slots) {
            if *f != 0.0 {
                for &(r, s) in w {
                    load[r as usize] += f * s;
                }
            }
        }
        self.deflection_at_posts(load, out_m, true);
    }

    /// Upward deflection at the posts (m) under a downward point force P (N) at (x, y) (m).
    pub fn point_load_deflection(&self, preload_n: f64, x_m: f64, y_m: f64) -> Vec<f64> {
        let mut load = vec![0.0; self.reduced_dim()];
        for (r, s) in self.weights(x_m, y_m) {
            if r != usize::MAX {
                load[r] -= preload_n * s;
            }
        }
        let mut out = vec![0.0; self.post_weights.len()];
        self.deflection_at_posts(load, &mut out, false);
        out
    }

    /// Upward deflection at the posts (m) under a uniform downward pressure p (Pa) on the whole
    /// back (consistent nodal loads).
    pub fn pressure_deflection(&self, pressure_pa: f64) -> Vec<f64> {
        let mut load = vec![0.0; self.reduced_dim()];
        let funcs = element_functions();
        for ix in 0..self.elements_x {
            for iy in 0..self.elements_y {
                for &(xi, wx) in &GAUSS_4 {
                    for &(eta, wy) in &GAUSS_4 {
                        let w = wx * wy * self.hx * self.hy * pressure_pa;
                        for &(a, b, k, fx, fy) in &funcs {
                            let r = self.reduced[self.dof(ix + a, iy + b, k)];
                            if r != usize::MAX {
                                load[r] -=
                                    w * hermite(fx, xi, self.hx, 0) * hermite(fy, eta, self.hy, 0);
                            }
                        }
                    }
                }
            }
        }
        let mut out = vec![0.0; self.post_weights.len()];
        self.deflection_at_posts(load, &mut out, false);
        out
    }

    /// Upward deflection (m) at arbitrary points of nodal loads from point forces (x, y, F up).
    pub fn deflection_at(&self, forces: &[(f64, f64, f64)], points: &[(f64, f64)]) -> Vec<f64> {
        let mut load = vec![0.0; self.reduced_dim()];
        for &(x, y, f) in forces {
            for (r, s) in self.weights(x, y) {
                if r != usize::MAX {
                    load[r] += f * s;
                }
            }
        }
        self.factor
            .solve_in_place(&mut load)
            .expect("the plate factor solves finite loads");
        points
            .iter()
            .map(|&(x, y)| {
                self.weights(x, y)
                    .iter()
                    .filter(|(r, _)| *r != usize::MAX)
                    .map(|&(r, s)| s * load[r])
                    .sum()
            })
            .collect()
    }
}

/// A 1 × 1 identity, replaced in [`FreePlate::new`].
fn placeholder_matrix() -> Result<SymmetricMatrix> {
    SymmetricMatrix::from_upper_parts(1, vec![0, 1], vec![0], vec![1.0])
        .map_err(|e| invalid("slider_thickness_m", f64::NAN, e.to_string()))
}

/// A 1 × 1 factor, replaced in [`FreePlate::new`] (keeps the constructor's field order simple).
fn placeholder_factor() -> Result<NumericCholesky> {
    let one = SymmetricMatrix::from_upper_parts(1, vec![0, 1], vec![0], vec![1.0])
        .map_err(|e| invalid("slider_thickness_m", 0.0, e.to_string()))?;
    SymbolicCholesky::analyze(&one, Ordering::Natural)
        .and_then(|s| s.factor(&one))
        .map_err(|e| invalid("slider_thickness_m", 0.0, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corner_forces_twist_the_free_plate_as_kirchhoff_says() {
        // A free rectangle with corner forces +F at (0,0), (L,W) and −F at (L,0), (0,W) is in pure
        // twist: w = F x y / (2 D (1 − ν)) + rigid motion (Timoshenko & Woinowsky-Krieger §12;
        // the corner force is 2 M_xy).
        let (l, w, t) = (5e-3, 3e-3, 0.5e-3);
        let si = Material::silicon();
        let plate = FreePlate::new(l, w, t, &si, &[]).unwrap();
        let f = 0.3;
        let forces = [(0.0, 0.0, f), (l, w, f), (l, 0.0, -f), (0.0, w, -f)];
        let points: Vec<(f64, f64)> = (0..7)
            .flat_map(|i| (0..5).map(move |j| (l * i as f64 / 6.0, w * j as f64 / 4.0)))
            .collect();
        let u = plate.deflection_at(&forces, &points);
        let d = plate.flexural_rigidity_nm;
        let nu = si.poisson_ratio;
        // The corners (0,0), (L,0), (0,W) are held: the exact field is F x y / (2D(1−ν)).
        for ((x, y), ui) in points.iter().zip(&u) {
            let exact = f * x * y / (2.0 * d * (1.0 - nu));
            assert!(
                (ui - exact).abs() < 1e-9 * f * l * w / d,
                "twist deflection at ({x}, {y}): plate {ui} vs Kirchhoff {exact}"
            );
        }
    }

    #[test]
    fn a_central_point_load_on_a_plate_on_three_corners_matches_a_finer_mesh() {
        // Mesh convergence: the default t/2 elements (20 × 20) against t/8 (80 × 80).
        let (l, w, t) = (5e-3, 5e-3, 0.5e-3);
        let si = Material::silicon();
        let posts: Vec<(f64, f64)> = (0..9).map(|i| (0.5e-3 * (i + 1) as f64, 2.3e-3)).collect();
        let coarse = FreePlate::new(l, w, t, &si, &posts).unwrap();
        let p = 1.0;
        let a = coarse.point_load_deflection(p, 2.5e-3, 2.5e-3);
        let fine = FreePlate::with_elements(l, w, t, &si, &posts, 80, 80).unwrap();
        let b = fine.point_load_deflection(p, 2.5e-3, 2.5e-3);
        let scale = b.iter().map(|x| x.abs()).fold(0.0, f64::max);
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!(
                (x - y).abs() < 1e-3 * scale,
                "plate deflection at post {k}: 20 × 20 elements {x} vs 80 × 80 {y}"
            );
        }
    }
}
