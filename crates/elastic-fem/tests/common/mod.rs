//! Helpers shared by the integration tests.
#![allow(dead_code)]

use elastic_fem::mesh_gen::BoxMesh;
use elastic_fem::{Material, Model};

/// Steel-like isotropic material.
pub fn steel() -> Material {
    Material::isotropic(200e9, 0.3).expect("valid steel constants")
}

/// Smooth interior distortion of the unit-cube-like box that keeps its faces planar:
/// x' = x + δ s(x) d, with s vanishing on every face.
pub fn distort(mesh: &mut BoxMesh, amplitude: f64) {
    let l = mesh.lengths_m;
    mesh.map_nodes(|x| {
        let pi = std::f64::consts::PI;
        let s = (pi * x[0] / l[0]).sin() * (pi * x[1] / l[1]).sin() * (pi * x[2] / l[2]).sin();
        [
            x[0] + amplitude * l[0] * 0.7 * s,
            x[1] - amplitude * l[1] * 0.5 * s,
            x[2] + amplitude * l[2] * 0.3 * s,
        ]
    });
}

/// Tet10 box (2 × 2 × 2 cells) under the smooth [`distort`]ion with its midside nodes left on the
/// mapped edges: some elements are curved (degree-5 rule). Asserts that it has curved elements.
pub fn curved_tet10_box() -> BoxMesh {
    let mut mesh = BoxMesh::tet10([1.0, 1.2, 0.8], [2, 2, 2]);
    distort(&mut mesh, 0.08);
    let model = model_of(&mesh, steel());
    assert!(
        model.quality().curved_elements > 0,
        "the smooth map must curve some Tet10 elements"
    );
    mesh
}

/// Model from a box mesh.
pub fn model_of(mesh: &BoxMesh, material: Material) -> Model {
    Model::new(mesh.nodes.clone(), mesh.connectivity.clone(), material).expect("valid box mesh")
}

/// Max-norm of a slice.
pub fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Least-squares slope of log(error) against log(h).
pub fn fitted_rate(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let lx: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = e.iter().map(|v| v.ln()).collect();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let num: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let den: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    num / den
}

/// Deterministic pseudo-random numbers in [0, 1) (64-bit LCG).
pub struct Lcg(pub u64);

impl Lcg {
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}
