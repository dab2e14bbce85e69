//! What a real slider has besides the ideal lattice: each post's extra height δ_i (m) — positive
//! when the post tip reaches further towards the stator than the ideal plane, so it touches first.
//!
//! δ_i = s_i + m_i − τ_x x_i/L − τ_y y_i/W − b (x_i² + y_i²)/((L/2)² + (W/2)²)
//!
//! with (x_i, y_i) the post centre from the slider's centre, L × W the slider (its real margins
//! included), s_i ~ N(0, σ²) seeded scatter ([`motor::rng`]), m_i a measured height map (CSV,
//! mean not removed), τ_x, τ_y the tilt (height change of the slider's back plane across its
//! length/width: the +x end is higher by τ_x, i.e. farther from the stator) and b the bow (a
//! paraboloid: the corners are higher than the centre by b; b > 0 is convex towards the stator).
//! Obstacle height of post i: h_i = w(x_i) + δ_i, with the frozen wave w.

use std::path::Path;

use crate::error::{Result, SliderError, invalid};
use crate::lattice::LatticeGeometry;
use motor::rng::SplitMix64;

/// A measured height map: one extra height (m) per post (the motor's [`motor::HeightMap`]).
pub use motor::HeightMap;
/// The imperfections of a real slider (module doc; the motor's [`motor::Imperfections`]).
pub use motor::Imperfections;

/// Largest height-map CSV accepted (bytes): a line per post of at most ≈ 60 bytes for the
/// largest lattice the scene accepts (2000 × 2000 posts).
pub const MAX_HEIGHT_MAP_BYTES: u64 = 256 << 20;

/// Reading a [`HeightMap`] from its CSV.
pub trait HeightMapCsv: Sized {
    /// Reads a CSV of lines `row,column,height_m` (an optional header line whose first field is
    /// not a number; `#` comments and blank lines skipped): row = post index along y
    /// (0..posts_y), column = along x (0..posts_x), every post exactly once, finite heights.
    fn read_csv(path: &Path, posts_x: usize, posts_y: usize) -> Result<Self>;
    /// Parses the CSV text of [`HeightMapCsv::read_csv`].
    fn parse(text: &str, file: &str, posts_x: usize, posts_y: usize) -> Result<Self>;
}

impl HeightMapCsv for HeightMap {
    fn read_csv(path: &Path, posts_x: usize, posts_y: usize) -> Result<Self> {
        let file = path.display().to_string();
        let text = atomic_files::read_input_text(path, MAX_HEIGHT_MAP_BYTES).map_err(|e| {
            SliderError::HeightMap {
                file: file.clone(),
                detail: e.into_parts().1.to_string(),
            }
        })?;
        Self::parse(&text, &file, posts_x, posts_y)
    }

    fn parse(text: &str, file: &str, posts_x: usize, posts_y: usize) -> Result<Self> {
        let err = |detail: String| SliderError::HeightMap {
            file: file.to_string(),
            detail,
        };
        let mut height = vec![f64::NAN; posts_x * posts_y];
        let mut seen = vec![false; posts_x * posts_y];
        for (k, line) in text.lines().enumerate() {
            let line_no = k + 1;
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            if fields.len() != 3 {
                return Err(err(format!(
                    "line {line_no}: expected `row,column,height_m`, found {} fields",
                    fields.len()
                )));
            }
            let Ok(row) = fields[0].parse::<usize>() else {
                if k == 0 || text.lines().take(k).all(|l| l.trim().is_empty()) {
                    continue; // header
                }
                return Err(err(format!(
                    "line {line_no}: row `{}` is not an index",
                    fields[0]
                )));
            };
            let col = fields[1].parse::<usize>().map_err(|_| {
                err(format!(
                    "line {line_no}: column `{}` is not an index",
                    fields[1]
                ))
            })?;
            let h = fields[2].parse::<f64>().map_err(|_| {
                err(format!(
                    "line {line_no}: height_m `{}` is not a number",
                    fields[2]
                ))
            })?;
            if !h.is_finite() {
                return Err(err(format!("line {line_no}: height_m is {h} (not finite)")));
            }
            if row >= posts_y || col >= posts_x {
                return Err(err(format!(
                    "line {line_no}: post (row {row}, column {col}) outside the {posts_y} × \
                     {posts_x} lattice (rows along y, columns along x)"
                )));
            }
            let idx = col * posts_y + row;
            if seen[idx] {
                return Err(err(format!(
                    "line {line_no}: post (row {row}, column {col}) given twice"
                )));
            }
            seen[idx] = true;
            height[idx] = h;
        }
        let missing = seen.iter().filter(|s| !**s).count();
        if missing > 0 {
            let first = seen.iter().position(|s| !*s).unwrap_or(0);
            return Err(err(format!(
                "{missing} of {} posts missing (first: row {}, column {}); the map must give \
                 every post of the {posts_y} × {posts_x} lattice",
                posts_x * posts_y,
                first % posts_y,
                first / posts_y
            )));
        }
        Ok(Self {
            file: file.to_string(),
            height_m: height,
        })
    }
}

/// What the whole-slider model computes from [`Imperfections`]: checks and post offsets δ_i.
pub trait ImperfectionsExt {
    /// Checks the fields; errors name them.
    fn validate(&self, geometry: &LatticeGeometry) -> Result<()>;
    /// Refuses a tilt or bow that brings a corner of the slider body (its underside,
    /// `post_height_m` above the post tips) onto the stator before the posts: then the body, not
    /// the posts, carries the preload and every post is lifted off. Compares the body's lowest
    /// corner with the most protruding post (offsets δ from [`ImperfectionsExt::post_offsets_m`]).
    fn check_body_clearance(
        &self,
        g: &LatticeGeometry,
        post_height_m: f64,
        offsets_m: &[f64],
    ) -> Result<()>;
    /// δ_i (m) of every post in lattice order.
    fn post_offsets_m(&self, g: &LatticeGeometry) -> Result<Vec<f64>>;
}

/// The tilt-and-bow part of δ at a point (x, y) from the slider's centre (m).
fn shape_m(imp: &Imperfections, g: &LatticeGeometry, x: f64, y: f64) -> f64 {
    let (l, w) = (g.slider_length_m, g.slider_width_m);
    -imp.tilt_x_m * x / l
        - imp.tilt_y_m * y / w
        - imp.bow_m * (x * x + y * y) / (0.25 * (l * l + w * w))
}

impl ImperfectionsExt for Imperfections {
    fn validate(&self, geometry: &LatticeGeometry) -> Result<()> {
        let s = self.height_scatter_m;
        if !(s >= 0.0 && s.is_finite()) {
            return Err(invalid(
                "posts.height_scatter (height_scatter_m)",
                s,
                "must be ≥ 0 and finite",
            ));
        }
        for (field, v) in [
            ("slider.tilt_x (tilt_x_m)", self.tilt_x_m),
            ("slider.tilt_y (tilt_y_m)", self.tilt_y_m),
            ("slider.bow (bow_m)", self.bow_m),
        ] {
            if !v.is_finite() {
                return Err(invalid(field, v, "must be finite"));
            }
        }
        if let Some(map) = &self.height_map
            && map.height_m.len() != geometry.len()
        {
            return Err(SliderError::HeightMap {
                file: map.file.clone(),
                detail: format!(
                    "{} heights for a lattice of {} posts",
                    map.height_m.len(),
                    geometry.len()
                ),
            });
        }
        Ok(())
    }

    fn check_body_clearance(
        &self,
        g: &LatticeGeometry,
        post_height_m: f64,
        offsets_m: &[f64],
    ) -> Result<()> {
        let highest_post = offsets_m.iter().copied().fold(f64::MIN, f64::max);
        let (hl, hw) = (0.5 * g.slider_length_m, 0.5 * g.slider_width_m);
        for (x, y) in [(-hl, -hw), (-hl, hw), (hl, -hw), (hl, hw)] {
            let body = shape_m(self, g, x, y);
            if body - post_height_m > highest_post {
                let parts = [
                    (
                        "slider.tilt_x (tilt_x_m)",
                        self.tilt_x_m,
                        (self.tilt_x_m * x / g.slider_length_m).abs(),
                    ),
                    (
                        "slider.tilt_y (tilt_y_m)",
                        self.tilt_y_m,
                        (self.tilt_y_m * y / g.slider_width_m).abs(),
                    ),
                    ("slider.bow (bow_m)", self.bow_m, self.bow_m.abs()),
                ];
                let (field, value, _) = parts
                    .into_iter()
                    .max_by(|a, b| a.2.total_cmp(&b.2))
                    .expect("three parts");
                return Err(invalid(
                    field,
                    value,
                    format!(
                        "lifts every post off: the slider body's corner at ({:.3e}, {:.3e}) m from its \
                         centre would reach the stator {:.3e} m before the posts (post height {post_height_m:.3e} m)",
                        x,
                        y,
                        body - post_height_m - highest_post
                    ),
                ));
            }
        }
        Ok(())
    }

    fn post_offsets_m(&self, g: &LatticeGeometry) -> Result<Vec<f64>> {
        self.validate(g)?;
        let scatter = if self.height_scatter_m > 0.0 {
            SplitMix64::new(self.scatter_seed).normals(g.len())
        } else {
            vec![0.0; g.len()]
        };
        let (l, w) = (g.slider_length_m, g.slider_width_m);
        let mut out = Vec::with_capacity(g.len());
        for i in 0..g.posts_x {
            let x = g.x_m(i) - 0.5 * l;
            for j in 0..g.posts_y {
                let y = g.y_m(j) - 0.5 * w;
                let idx = g.index(i, j);
                let map = self.height_map.as_ref().map_or(0.0, |m| m.height_m[idx]);
                out.push(self.height_scatter_m * scatter[idx] + map + shape_m(self, g, x, y));
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry() -> LatticeGeometry {
        LatticeGeometry {
            posts_x: 3,
            posts_y: 2,
            pitch_m: 40e-6,
            post_radius_m: 10e-6,
            slider_length_m: 200e-6,
            slider_width_m: 80e-6,
        }
    }

    #[test]
    fn a_height_map_fills_the_lattice_by_row_and_column() {
        let text =
            "row,column,height_m\n0,0,1e-9\n1,0,2e-9\n0,1,3e-9\n1,1,4e-9\n0,2,5e-9\n1,2,6e-9\n";
        let map = HeightMap::parse(text, "m.csv", 3, 2).unwrap();
        assert_eq!(
            map.height_m,
            vec![1e-9, 2e-9, 3e-9, 4e-9, 5e-9, 6e-9],
            "heights in lattice order i·n_y + j"
        );
    }

    #[test]
    fn a_height_map_of_the_wrong_shape_or_with_nan_is_refused_naming_the_line() {
        let short = "0,0,1e-9\n1,0,2e-9\n";
        let e = HeightMap::parse(short, "m.csv", 3, 2)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("m.csv") && e.contains("4 of 6 posts missing"),
            "{e}"
        );
        let nan = "0,0,NaN\n";
        let e = HeightMap::parse(nan, "m.csv", 3, 2)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 1") && e.contains("not finite"), "{e}");
        let outside = "2,0,1e-9\n";
        let e = HeightMap::parse(outside, "m.csv", 3, 2)
            .unwrap_err()
            .to_string();
        assert!(e.contains("outside the 2 × 3 lattice"), "{e}");
    }

    #[test]
    fn negative_scatter_is_refused_naming_the_field() {
        let imp = Imperfections {
            height_scatter_m: -1e-9,
            ..Default::default()
        };
        let e = imp.post_offsets_m(&geometry()).unwrap_err().to_string();
        assert!(e.contains("height_scatter_m"), "{e}");
    }

    #[test]
    fn tilt_and_bow_follow_their_definitions() {
        let g = geometry();
        let tilt = Imperfections {
            tilt_x_m: 10e-9,
            ..Default::default()
        }
        .post_offsets_m(&g)
        .unwrap();
        // Posts at x = −40, 0, +40 µm from the centre of a 200 µm slider: δ = ∓2 nm.
        assert!(
            (tilt[0] - 2e-9).abs() < 1e-21,
            "tilt δ of the −x post: {}",
            tilt[0]
        );
        assert!(
            (tilt[4] + 2e-9).abs() < 1e-21,
            "tilt δ of the +x post: {}",
            tilt[4]
        );
        let bow = Imperfections {
            bow_m: 10e-9,
            ..Default::default()
        }
        .post_offsets_m(&g)
        .unwrap();
        let expected = -10e-9 * (40e-6f64.powi(2) + 20e-6f64.powi(2))
            / (0.25 * (200e-6f64.powi(2) + 80e-6f64.powi(2)));
        assert!(
            (bow[0] - expected).abs() < 1e-21,
            "bow δ of a corner post: {}",
            bow[0]
        );
    }

    #[test]
    fn a_tilt_that_lands_the_body_corner_first_is_refused_naming_the_tilt() {
        let g = LatticeGeometry {
            posts_x: 10,
            posts_y: 10,
            pitch_m: 40e-6,
            post_radius_m: 10e-6,
            slider_length_m: 5e-3,
            slider_width_m: 5e-3,
        };
        let ok = Imperfections {
            tilt_x_m: 100e-9,
            ..Default::default()
        };
        ok.check_body_clearance(&g, 2e-6, &ok.post_offsets_m(&g).unwrap())
            .expect("100 nm tilt is fine");
        // The body corner, 0.5 mm beyond the last post, drops 30 µm × 0.5/5 = 3 µm > h = 2 µm below it.
        let steep = Imperfections {
            tilt_x_m: -30e-6,
            ..Default::default()
        };
        let e = steep
            .check_body_clearance(&g, 2e-6, &steep.post_offsets_m(&g).unwrap())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("tilt_x_m") && e.contains("lifts every post off"),
            "{e}"
        );
    }

    #[test]
    fn the_scatter_is_reproducible_from_its_seed() {
        let imp = Imperfections {
            height_scatter_m: 5e-9,
            scatter_seed: 42,
            ..Default::default()
        };
        let g = geometry();
        assert_eq!(
            imp.post_offsets_m(&g).unwrap(),
            imp.post_offsets_m(&g).unwrap(),
            "same seed, same heights"
        );
        let other = Imperfections {
            scatter_seed: 43,
            ..imp.clone()
        };
        assert_ne!(
            imp.post_offsets_m(&g).unwrap(),
            other.post_offsets_m(&g).unwrap(),
            "another seed differs"
        );
    }
}
