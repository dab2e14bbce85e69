//! What the whole slider's tests share: the lattice of the paper's post cell, its operator
//! spec, a tight CG, the relative difference and the y-periodic wrap of a lattice kernel.

#![allow(dead_code)] // each test file uses its own part

use nalgebra::DMatrix;
use slider_contact::{CgOptions, LatticeGeometry, NearField, OperatorSpec};

/// Post pitch (m) of the paper's cell.
pub const PITCH_M: f64 = 40e-6;
/// Preload per post (N): the paper's 40 N over 10⁴ posts.
pub const PRELOAD_PER_POST_N: f64 = 4e-3;

/// An `nx` × `ny` lattice of 20 µm posts at [`PITCH_M`], the body the array's size.
pub fn geometry(nx: usize, ny: usize) -> LatticeGeometry {
    LatticeGeometry {
        posts_x: nx,
        posts_y: ny,
        pitch_m: PITCH_M,
        post_radius_m: 10e-6,
        slider_length_m: nx as f64 * PITCH_M,
        slider_width_m: ny as f64 * PITCH_M,
    }
}

/// The operator spec of [`geometry`]: Si on LiNbO3, a 0.5 mm body, Johnson's near field.
pub fn spec(nx: usize, ny: usize) -> OperatorSpec {
    OperatorSpec {
        geometry: geometry(nx, ny),
        slider_material: contact_springs::Material::silicon(),
        stator_material: contact_springs::Material::lithium_niobate(),
        slider_thickness_m: 0.5e-3,
        near_field: NearField::Johnson,
    }
}

/// CG options at 1e-13.
pub fn tight() -> CgOptions {
    CgOptions {
        tolerance: 1e-13,
        ..CgOptions::default()
    }
}

/// |a − b| / |b|.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// The lattice kernel wrapped on a torus of `ny` rows (odd): c(di, dj) summed over the images
/// dj + m·ny, |m| ≤ `images`. Circulant in y, so an ideal lattice's rows are all alike.
pub fn periodic(
    kernel: impl Fn(i64, i64) -> f64,
    nx: usize,
    ny: usize,
    images: i64,
) -> DMatrix<f64> {
    let n = nx * ny;
    let half = (ny / 2) as i64;
    DMatrix::from_fn(n, n, |p, q| {
        let (ip, jp) = ((p / ny) as i64, (p % ny) as i64);
        let (iq, jq) = ((q / ny) as i64, (q % ny) as i64);
        let dj = (jp - jq + half).rem_euclid(ny as i64) - half;
        (-images..=images)
            .map(|m| kernel(ip - iq, dj + m * ny as i64))
            .sum()
    })
}
