//! Compliance of rigid flat disks pressed on an elastic half-space (the stator), frictionless.
//!
//! K. L. Johnson, *Contact Mechanics* (CUP 1985) §3.8, eqs (3.35)–(3.36): a rigid flat punch of
//! radius a pressed with force F on an isotropic half-space (G, ν) sinks by
//! δ = F (1−ν)/(4 G a) (the inverse of the spring `k_sn` of docs/physics.md §3) and displaces the free
//! surface outside it by u_z(r) = F (1−ν)/(2π G a) · arcsin(a/r), r ≥ a.
//!
//! The mutual compliance of two disks at centre distance r is taken as u_z(r) at the other disk's
//! centre. Averaging u_z over the other disk with its own rigid-punch pressure weight changes it by
//! a relative ≈ a²/(6r²) (1 % of the mutual term, 0.2 % of the self term at r = 4a, the nearest
//! neighbour of 20 µm posts at 40 µm pitch); the test against the meshed stator block bounds it.
//!
//! Valid for disks far from the stator's edges and depth (the stator is a 1 mm plate, 2.4 λ deep:
//! a wave-scale load pattern, e^{−k z}, is gone long before its bottom).

use nalgebra::DMatrix;

/// Self compliance of a rigid frictionless disk on a half-space, (1−ν)/(4Ga) (m/N).
pub fn disk_self_compliance(shear_modulus_pa: f64, poisson_ratio: f64, radius_m: f64) -> f64 {
    (1.0 - poisson_ratio) / (4.0 * shear_modulus_pa * radius_m)
}

/// Surface displacement per unit force at distance `distance_m` ≥ a from the centre of a rigid
/// disk of radius a: (1−ν)/(2πGa) · arcsin(a/r) (m/N). Inside the disk it is the self compliance.
pub fn disk_mutual_compliance(
    shear_modulus_pa: f64,
    poisson_ratio: f64,
    radius_m: f64,
    distance_m: f64,
) -> f64 {
    if distance_m <= radius_m {
        return disk_self_compliance(shear_modulus_pa, poisson_ratio, radius_m);
    }
    (1.0 - poisson_ratio) / (2.0 * std::f64::consts::PI * shear_modulus_pa * radius_m)
        * (radius_m / distance_m).asin()
}

/// How the posts of a strip are repeated in y over the real slider.
///
/// The strip holds `strip_rows` rows of posts at y = (r + ½)·pitch, r = 0..strip_rows, between
/// two symmetry planes; the slider has `slider_rows` rows. The strip is placed in the middle of
/// the slider and unfolded by mirror images across its symmetry planes, so slider row k carries
/// the forces of strip row `unfold(k − first)` (period 2·strip_rows).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RowLayout {
    /// Post pitch in y (m).
    pub pitch_m: f64,
    /// Rows of posts inside the strip (≥ 1).
    pub strip_rows: usize,
    /// Rows of posts of the whole slider (≥ strip_rows).
    pub slider_rows: usize,
}

impl RowLayout {
    /// Index of the first strip row among the slider rows (the strip is centred).
    pub fn first_strip_row(&self) -> usize {
        (self.slider_rows - self.strip_rows) / 2
    }

    /// Strip row whose forces slider row `k` carries (mirror unfolding).
    pub fn strip_row_of(&self, k: usize) -> usize {
        let period = 2 * self.strip_rows as i64;
        let m = (k as i64 - self.first_strip_row() as i64).rem_euclid(period) as usize;
        if m < self.strip_rows {
            m
        } else {
            2 * self.strip_rows - 1 - m
        }
    }
}

/// A post of the strip seen by the half-space: centre x (m) and strip row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripPost {
    /// Centre x (m).
    pub x_m: f64,
    /// Row inside the strip (0-based, y = (row + ½)·pitch).
    pub row: usize,
}

/// Dense half-space compliance C_ij (m/N) between the strip's posts: the z displacement of disk i
/// per unit force on disk j *and on all its images* in the other slider rows (every slider row
/// carries the forces of the strip row it unfolds to).
pub fn strip_compliance(
    shear_modulus_pa: f64,
    poisson_ratio: f64,
    radius_m: f64,
    posts: &[StripPost],
    layout: &RowLayout,
) -> DMatrix<f64> {
    summed_over_images(posts, layout, |dx, dy| {
        let r = (dx * dx + dy * dy).sqrt();
        disk_mutual_compliance(shear_modulus_pa, poisson_ratio, radius_m, r)
    })
}

/// Symmetric dense matrix of `pair(dx, dy)` (the compliance of disk i to a unit force at the
/// offset (dx, dy)) between the strip's posts, summed over each post j and all its images in the
/// other slider rows (every slider row carries the forces of the strip row it unfolds to).
fn summed_over_images(
    posts: &[StripPost],
    layout: &RowLayout,
    pair: impl Fn(f64, f64) -> f64,
) -> DMatrix<f64> {
    let n = posts.len();
    let first = layout.first_strip_row();
    // Slider rows grouped by the strip row they carry: offsets in y from strip row 0's line.
    let mut images: Vec<Vec<f64>> = vec![Vec::new(); layout.strip_rows];
    for k in 0..layout.slider_rows {
        let y = (k as f64 - first as f64) * layout.pitch_m;
        images[layout.strip_row_of(k)].push(y);
    }
    let mut c = DMatrix::zeros(n, n);
    for i in 0..n {
        let yi = posts[i].row as f64 * layout.pitch_m;
        for j in i..n {
            let dx = posts[i].x_m - posts[j].x_m;
            let sum: f64 = images[posts[j].row]
                .iter()
                .map(|yk| pair(dx, yi - yk))
                .sum();
            c[(i, j)] = sum;
            c[(j, i)] = sum;
        }
    }
    c
}

/// Tangential self compliance of a rigid disk bonded to a half-space under a tangential force,
/// (2−ν)/(8Ga) (m/N): Mindlin's rigid circular punch (Johnson §3.8, the tangential counterpart of
/// eq. (3.35); the full-stick limit of §7.1).
pub fn disk_tangential_self_compliance(
    shear_modulus_pa: f64,
    poisson_ratio: f64,
    radius_m: f64,
) -> f64 {
    (2.0 - poisson_ratio) / (8.0 * shear_modulus_pa * radius_m)
}

/// Surface x displacement per unit x force at offset (dx, dy) (m) from a tangential point force
/// on a half-space (Cerruti; Johnson §3.2 eq. (3.86a)): (1/(2πG r))·[(1−ν) + ν dx²/r²] (m/N).
/// Inside a disk radius `radius_m` the rigid-disk self compliance is returned (as for the
/// normal terms, the point-force form is used from the disk edge outwards: relative error
/// ≈ a²/(6r²) at centre distance r).
pub fn tangential_mutual_compliance(
    shear_modulus_pa: f64,
    poisson_ratio: f64,
    radius_m: f64,
    dx_m: f64,
    dy_m: f64,
) -> f64 {
    let r = (dx_m * dx_m + dy_m * dy_m).sqrt();
    if r <= radius_m {
        return disk_tangential_self_compliance(shear_modulus_pa, poisson_ratio, radius_m);
    }
    ((1.0 - poisson_ratio) + poisson_ratio * dx_m * dx_m / (r * r))
        / (2.0 * std::f64::consts::PI * shear_modulus_pa * r)
}

/// Normal surface displacement per unit tangential x force at offset dx, and (by reciprocity,
/// with the opposite sign) tangential displacement per unit normal force: −(1−2ν) dx/(4πG r²)
/// (Johnson eqs. (3.19a), (3.86c)) (m/N). This is the normal–tangential coupling of one body;
/// between two bodies only the mismatch survives, measured by the Dundurs parameter
/// [`dundurs_beta`].
pub fn normal_tangential_cross_compliance(
    shear_modulus_pa: f64,
    poisson_ratio: f64,
    dx_m: f64,
    dy_m: f64,
) -> f64 {
    let r2 = dx_m * dx_m + dy_m * dy_m;
    if r2 == 0.0 {
        return 0.0;
    }
    -(1.0 - 2.0 * poisson_ratio) * dx_m / (4.0 * std::f64::consts::PI * shear_modulus_pa * r2)
}

/// Dundurs' second parameter β = ½[(1−2ν₁)/G₁ − (1−2ν₂)/G₂] / [(1−ν₁)/G₁ + (1−ν₂)/G₂]
/// (Johnson §5.7, eq. (5.53)): the ratio of the normal–tangential coupling of two bodies in
/// contact to their normal compliance. β = 0: normal pressure causes no relative tangential
/// displacement and vice versa (Goodman's approximation exact). Si on LiNbO3: β ≈ 0.021.
pub fn dundurs_beta(g1_pa: f64, nu1: f64, g2_pa: f64, nu2: f64) -> f64 {
    0.5 * ((1.0 - 2.0 * nu1) / g1_pa - (1.0 - 2.0 * nu2) / g2_pa)
        / ((1.0 - nu1) / g1_pa + (1.0 - nu2) / g2_pa)
}

/// Dense half-space tangential compliance (m/N) between the strip's posts: x displacement of
/// disk i per unit x force on disk j and on all its images in the other slider rows (as
/// [`strip_compliance`] for the normal direction; tangential forces are mirrored with the rows,
/// x forces are even under a y mirror).
pub fn strip_tangential_compliance(
    shear_modulus_pa: f64,
    poisson_ratio: f64,
    radius_m: f64,
    posts: &[StripPost],
    layout: &RowLayout,
) -> DMatrix<f64> {
    summed_over_images(posts, layout, |dx, dy| {
        tangential_mutual_compliance(shear_modulus_pa, poisson_ratio, radius_m, dx, dy)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const G: f64 = 67e9;
    const NU: f64 = 0.25;
    const A: f64 = 10e-6;

    #[test]
    fn the_surface_displacement_is_continuous_at_the_disk_edge() {
        let inside = disk_self_compliance(G, NU, A);
        let edge = disk_mutual_compliance(G, NU, A, A * (1.0 + 1e-12));
        assert!(
            (edge / inside - 1.0).abs() < 1e-5,
            "surface displacement at r = a: {edge} vs disk sink {inside}"
        );
    }

    #[test]
    fn far_field_displacement_tends_to_boussinesq() {
        // Far away the disk acts as a point force: u_z = (1−ν) F / (2π G r).
        let r = 1000.0 * A;
        let boussinesq = (1.0 - NU) / (2.0 * std::f64::consts::PI * G * r);
        let disk = disk_mutual_compliance(G, NU, A, r);
        assert!(
            (disk / boussinesq - 1.0).abs() < 1e-6,
            "far-field compliance {disk} vs Boussinesq {boussinesq}"
        );
    }

    #[test]
    fn mirror_unfolding_maps_rows_symmetrically() {
        let layout = RowLayout {
            pitch_m: 40e-6,
            strip_rows: 2,
            slider_rows: 7,
        };
        assert_eq!(layout.first_strip_row(), 2, "strip centred among 7 rows");
        let rows: Vec<usize> = (0..7).map(|k| layout.strip_row_of(k)).collect();
        assert_eq!(
            rows,
            vec![1, 0, 0, 1, 1, 0, 0],
            "slider rows carry strip rows 0/1 mirrored about the strip's planes"
        );
    }

    #[test]
    fn one_row_strip_compliance_is_symmetric_and_sums_the_rows() {
        let posts: Vec<StripPost> = (0..3)
            .map(|i| StripPost {
                x_m: i as f64 * 40e-6,
                row: 0,
            })
            .collect();
        let layout = RowLayout {
            pitch_m: 40e-6,
            strip_rows: 1,
            slider_rows: 3,
        };
        let c = strip_compliance(G, NU, A, &posts, &layout);
        assert!(
            (c[(0, 1)] - c[(1, 0)]).abs() <= 1e-15 * c[(0, 1)],
            "half-space compliance symmetry"
        );
        let expected_self =
            disk_self_compliance(G, NU, A) + 2.0 * disk_mutual_compliance(G, NU, A, 40e-6);
        assert!(
            (c[(1, 1)] / expected_self - 1.0).abs() < 1e-12,
            "self term with the two neighbouring rows: {} vs {expected_self}",
            c[(1, 1)]
        );
    }
    #[test]
    fn tangential_far_field_along_the_force_exceeds_the_normal_one_by_one_over_one_minus_nu() {
        // Along the force (dx = r): u_x = 1/(2πG r) vs u_z = (1−ν)/(2πG r).
        let r = 1000.0 * A;
        let ux = tangential_mutual_compliance(G, NU, A, r, 0.0);
        let uz = disk_mutual_compliance(G, NU, A, r);
        assert!(
            (ux * (1.0 - NU) / uz - 1.0).abs() < 1e-6,
            "tangential {ux} vs normal {uz} far-field compliance"
        );
        let across = tangential_mutual_compliance(G, NU, A, 0.0, r);
        assert!(
            (across / ux - (1.0 - NU)).abs() < 1e-12,
            "across the force the tangential compliance is (1−ν) of the along value"
        );
    }

    #[test]
    fn si_on_linbo3_has_a_small_dundurs_beta() {
        let beta = dundurs_beta(66.5e9, 0.22, 67.0e9, 0.25);
        assert!(
            beta > 0.015 && beta < 0.03,
            "Dundurs β of Si on LiNbO3 = {beta}"
        );
        assert!(
            dundurs_beta(G, NU, G, NU).abs() < 1e-15,
            "identical bodies have β = 0"
        );
    }

    #[test]
    fn tangential_strip_compliance_is_symmetric_and_positive_definite() {
        let posts: Vec<StripPost> = (0..5)
            .map(|i| StripPost {
                x_m: i as f64 * 40e-6,
                row: 0,
            })
            .collect();
        let layout = RowLayout {
            pitch_m: 40e-6,
            strip_rows: 1,
            slider_rows: 5,
        };
        let c = strip_tangential_compliance(G, NU, A, &posts, &layout);
        assert!(
            (&c - c.transpose()).amax() <= 1e-15 * c.amax(),
            "tangential compliance symmetry"
        );
        assert!(
            c.clone().cholesky().is_some(),
            "tangential compliance positive definite"
        );
        assert!(
            c[(2, 2)] > disk_tangential_self_compliance(G, NU, A),
            "neighbouring rows add to the self term"
        );
    }
}
