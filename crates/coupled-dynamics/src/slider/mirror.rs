//! The slider's **y-mirror symmetry**: a slider whose post offsets δ_i, local wave amplitudes
//! α_i and normal forces on the phase grid are mirror images across its x-axis
//! (row j ↔ row n_y − 1 − j) — the ideal slider, or one whose height map, tilt and bow are
//! symmetric in y — has a mirror-symmetric steady state, since the wave runs along x and the
//! tangential compliance is even in y. Its n_x × n_y/2 posts of rows j < n_y/2 then carry the
//! whole problem on the folded compliance C_m = R C E (`slider_contact::tangential_mirror`):
//! half the unknowns in every step's box QP, half the FFT work in every product.
//!
//! The folded model is the strip model on the half lattice with strip share ½ (every post of
//! the half stands for itself and its image), so thrust, powers and the energy books are the
//! whole slider's; per-post results are expanded back to the full lattice (the extensive
//! means × ½, an exact scaling). Detected, never assumed: n_y even, δ and α mirror-symmetric to
//! [`MIRROR_TOLERANCE`] of their largest magnitude, and every grid phase's normal forces
//! mirror-symmetric to [`MIRROR_TOLERANCE`] of the largest (which covers a preload mechanism
//! or a free back that would break it). Height scatter breaks the symmetry, and the model then
//! runs on every post.

use crate::model::PostMeans;

use super::SliderScene;

/// Relative asymmetry below which a slider counts as mirror-symmetric: the round-off of the
/// offsets' and the normal solves' own arithmetic, far below any physical asymmetry (a 5 nm
/// scatter is 10⁻¹ of the 20 nm wave). Default 1e-9.
pub const MIRROR_TOLERANCE: f64 = 1e-9;

/// The fold of an n_x × n_y lattice (n_y even) onto its rows j < n_y/2.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mirror {
    /// Posts along x.
    pub posts_x: usize,
    /// Posts along y of the full lattice.
    pub posts_y: usize,
}

/// Whether `v` (full lattice order) equals its mirror image to `MIRROR_TOLERANCE` of its
/// largest magnitude.
fn symmetric(v: &[f64], nx: usize, ny: usize) -> bool {
    let scale = v.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
    (0..nx).all(|i| {
        (0..ny / 2)
            .all(|j| (v[i * ny + j] - v[i * ny + ny - 1 - j]).abs() <= MIRROR_TOLERANCE * scale)
    })
}

impl Mirror {
    /// The fold of `scene`'s lattice if its offsets, amplitudes and the normal forces of every
    /// grid phase (`normals_n`, full lattice order) are mirror-symmetric and n_y is even.
    pub fn of(scene: &SliderScene, normals_n: &[Vec<f64>]) -> Option<Self> {
        let (nx, ny) = (scene.geometry.posts_x, scene.geometry.posts_y);
        let even = ny >= 2 && ny.is_multiple_of(2);
        (even
            && symmetric(&scene.post_offset_m, nx, ny)
            && (scene.amplitude_scale.is_empty() || symmetric(&scene.amplitude_scale, nx, ny))
            && normals_n.iter().all(|f| symmetric(f, nx, ny)))
        .then_some(Self {
            posts_x: nx,
            posts_y: ny,
        })
    }

    /// Rows of the folded lattice (n_y/2).
    pub fn half_posts_y(&self) -> usize {
        self.posts_y / 2
    }

    /// Posts of the folded lattice.
    pub fn len(&self) -> usize {
        self.posts_x * self.half_posts_y()
    }

    /// Whether the folded lattice has no posts.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The folded index of the full lattice's post `p` (its own, or its image's).
    pub fn folded_index(&self, p: usize) -> usize {
        let (i, j) = (p / self.posts_y, p % self.posts_y);
        i * self.half_posts_y() + j.min(self.posts_y - 1 - j)
    }

    /// The rows j < n_y/2 of a full-lattice vector.
    pub fn restrict<T: Copy>(&self, full: &[T]) -> Vec<T> {
        let (ny, h) = (self.posts_y, self.half_posts_y());
        (0..self.posts_x)
            .flat_map(|i| (0..h).map(move |j| full[i * ny + j]))
            .collect()
    }

    /// The full-lattice vector of a folded one (each post's value at its image too).
    pub fn expand<T: Copy>(&self, folded: &[T]) -> Vec<T> {
        (0..self.posts_x * self.posts_y)
            .map(|p| folded[self.folded_index(p)])
            .collect()
    }

    /// The folded model's per-post means on the full lattice: the extensive ones (normal
    /// force, powers, which the folded model states for a post and its image together) × ½.
    pub fn expand_means(&self, means: PostMeans) -> PostMeans {
        let halved = |v: &[f64]| -> Vec<f64> { self.expand(v).iter().map(|x| 0.5 * x).collect() };
        PostMeans {
            speed_m_per_s: means.speed_m_per_s,
            mean_normal_force_n: halved(&means.mean_normal_force_n),
            slip_fraction: self.expand(&means.slip_fraction),
            contact_fraction: self.expand(&means.contact_fraction),
            friction_power_w: halved(&means.friction_power_w),
            stator_power_w: halved(&means.stator_power_w),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fold_maps_each_post_and_its_image_to_one_folded_post() {
        let m = Mirror {
            posts_x: 3,
            posts_y: 4,
        };
        let full: Vec<usize> = (0..12).collect();
        assert_eq!(m.restrict(&full), vec![0, 1, 4, 5, 8, 9]);
        assert_eq!(
            m.expand(&[10, 11, 20, 21, 30, 31]),
            vec![10, 11, 11, 10, 20, 21, 21, 20, 30, 31, 31, 30]
        );
        assert_eq!(m.folded_index(7), 2, "post (1, 3) is the image of (1, 0)");
    }
}
