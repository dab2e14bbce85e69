//! Per-post maps of the whole slider over one steady period: where it carries, slips and wears.

use serde::Serialize;
use slider_contact::LatticeGeometry;

use crate::model::{CoupledPoint, PostMeans};

/// Time means of every post at one speed, lattice order (post i along x, j along y at
/// i·n_y + j), with the steady point they belong to. Σ friction_power_w is the point's
/// friction dissipation and Σ stator_power_w its stator power (to the periodicity tolerance).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SliderMaps {
    /// Posts along x.
    pub posts_x: usize,
    /// Posts along y.
    pub posts_y: usize,
    /// Post centres x (m), per column i.
    pub x_m: Vec<f64>,
    /// Post centres y (m), per row j.
    pub y_m: Vec<f64>,
    /// The steady point (speed, thrust, powers, energy balance).
    pub point: CoupledPoint,
    /// The per-post time means.
    #[serde(flatten)]
    pub means: PostMeans,
}

impl SliderMaps {
    /// The maps of `means` on `geometry`'s lattice.
    pub fn new(geometry: &LatticeGeometry, point: CoupledPoint, means: PostMeans) -> Self {
        Self {
            posts_x: geometry.posts_x,
            posts_y: geometry.posts_y,
            x_m: (0..geometry.posts_x).map(|i| geometry.x_m(i)).collect(),
            y_m: (0..geometry.posts_y).map(|j| geometry.y_m(j)).collect(),
            point,
            means,
        }
    }

    /// Σ over posts of the friction power (W).
    pub fn total_friction_power_w(&self) -> f64 {
        self.means.friction_power_w.iter().sum()
    }

    /// The post (i, j) with the largest friction power: where the slider wears first.
    pub fn hottest_post(&self) -> (usize, usize) {
        let k = self
            .means
            .friction_power_w
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map_or(0, |(k, _)| k);
        (k / self.posts_y, k % self.posts_y)
    }

    /// Mean over the rows j of a per-post field (lattice order): its profile along x.
    pub fn profile_along_x(&self, field: &[f64]) -> Vec<f64> {
        (0..self.posts_x)
            .map(|i| {
                field[i * self.posts_y..(i + 1) * self.posts_y]
                    .iter()
                    .sum::<f64>()
                    / self.posts_y as f64
            })
            .collect()
    }
}
