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
    /// The local wave amplitude A_i/A₀ of every post (lattice order): 1 on the
    /// constant-amplitude wave, the self-consistent profile of the energy-conserving wave.
    pub amplitude_scale: Vec<f64>,
}

impl SliderMaps {
    /// The maps of `means` on `geometry`'s lattice, with the posts' local wave amplitudes
    /// `amplitude_scale` (A_i/A₀, lattice order; empty: 1 everywhere).
    pub fn new(
        geometry: &LatticeGeometry,
        point: CoupledPoint,
        means: PostMeans,
        amplitude_scale: &[f64],
    ) -> Self {
        let amplitude_scale = match amplitude_scale.is_empty() {
            true => vec![1.0; geometry.len()],
            false => amplitude_scale.to_vec(),
        };
        Self {
            posts_x: geometry.posts_x,
            posts_y: geometry.posts_y,
            x_m: (0..geometry.posts_x).map(|i| geometry.x_m(i)).collect(),
            y_m: (0..geometry.posts_y).map(|j| geometry.y_m(j)).collect(),
            point,
            means,
            amplitude_scale,
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

/// Colour levels of the heat maps (one SVG path per level).
const COLOUR_LEVELS: usize = 48;

/// The three maps the pipeline and the example draw, with their file stems and units: time-mean
/// normal force (where the slider carries), slip fraction (where it slips) and friction power
/// (where it wears).
pub const MAP_FIELDS: [(&str, &str); 3] = [
    ("mean_normal_force", "N"),
    ("slip_fraction", ""),
    ("friction_power", "W"),
];

/// The map of the local wave amplitude A_i/A₀ (drawn when the energy-conserving wave is on:
/// where the wave runs out under the slider), with its file stem and unit.
pub const AMPLITUDE_FIELD: (&str, &str) = ("amplitude_scale", "");

impl SliderMaps {
    /// The per-post field of [`MAP_FIELDS`] (or contact_fraction, stator_power,
    /// [`AMPLITUDE_FIELD`]) named `name` (lattice order); `None` for another name.
    pub fn field(&self, name: &str) -> Option<&[f64]> {
        match name {
            "mean_normal_force" => Some(&self.means.mean_normal_force_n),
            "slip_fraction" => Some(&self.means.slip_fraction),
            "contact_fraction" => Some(&self.means.contact_fraction),
            "friction_power" => Some(&self.means.friction_power_w),
            "stator_power" => Some(&self.means.stator_power_w),
            "amplitude_scale" => Some(&self.amplitude_scale),
            _ => None,
        }
    }

    /// One row per post: column i (along x), row j (along y), x_m, y_m and every time mean.
    pub fn csv(&self) -> String {
        let m = &self.means;
        let mut csv = String::from(
            "column,row,x_m,y_m,mean_normal_force_n,slip_fraction,contact_fraction,friction_power_w,stator_power_w,amplitude_scale\n",
        );
        for i in 0..self.posts_x {
            for j in 0..self.posts_y {
                let k = i * self.posts_y + j;
                csv.push_str(&format!(
                    "{i},{j},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}\n",
                    self.x_m[i],
                    self.y_m[j],
                    m.mean_normal_force_n[k],
                    m.slip_fraction[k],
                    m.contact_fraction[k],
                    m.friction_power_w[k],
                    m.stator_power_w[k],
                    self.amplitude_scale[k]
                ));
            }
        }
        csv
    }

    /// An SVG heat map of a per-post `field` (lattice order) on the posts' positions: x to the
    /// right (the wave travels along +x), y up; colours from dark blue (min) through green to
    /// yellow (max), a colour bar with `unit`. One path per colour level, so 10⁴ posts stay
    /// ≈ 0.3 MB.
    pub fn svg(&self, field: &[f64], title: &str, unit: &str) -> String {
        use std::fmt::Write as _;
        let (nx, ny) = (self.posts_x, self.posts_y);
        let cell = (600.0 / nx.max(ny) as f64).max(1.0);
        let (w, h) = (cell * nx as f64, cell * ny as f64);
        let lo = field.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = field.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let unit_of = |v: f64| if hi > lo { (v - lo) / (hi - lo) } else { 0.5 };
        let mut s = String::new();
        let _ = write!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" font-family="sans-serif" font-size="13">"#,
            w + 140.0,
            h + 60.0
        );
        let _ = write!(s, r#"<text x="10" y="20">{title}</text>"#);
        let mut paths = vec![String::new(); COLOUR_LEVELS];
        for i in 0..nx {
            for j in 0..ny {
                let t = unit_of(field[i * ny + j]);
                let level = ((t * COLOUR_LEVELS as f64) as usize).min(COLOUR_LEVELS - 1);
                let _ = write!(
                    paths[level],
                    "M{:.1} {:.1}h{:.1}v{:.1}h-{:.1}z",
                    10.0 + i as f64 * cell,
                    30.0 + (ny - 1 - j) as f64 * cell,
                    cell,
                    cell,
                    cell
                );
            }
        }
        for (level, d) in paths.iter().enumerate().filter(|(_, d)| !d.is_empty()) {
            let t = (level as f64 + 0.5) / COLOUR_LEVELS as f64;
            let _ = write!(s, r#"<path fill="{}" d="{d}"/>"#, colour(t));
        }
        for k in 0..=10 {
            let v = lo + (hi - lo) * k as f64 / 10.0;
            let y = 30.0 + h - h * k as f64 / 10.0;
            let _ = write!(
                s,
                r#"<rect x="{:.1}" y="{:.1}" width="16" height="{:.1}" fill="{}"/><text x="{:.1}" y="{:.1}">{v:.3e} {unit}</text>"#,
                w + 20.0,
                y - h / 10.0,
                h / 10.0,
                colour(unit_of(v)),
                w + 40.0,
                y + 4.0
            );
        }
        let _ = write!(
            s,
            r#"<text x="10" y="{:.1}">x → (wave direction), {nx} × {ny} posts</text></svg>"#,
            h + 50.0
        );
        s
    }
}

/// The colour of t ∈ [0, 1]: dark blue, green, yellow (viridis' ends and middle).
fn colour(t: f64) -> String {
    let stops = [
        (0.0, [68, 1, 84]),
        (0.5, [33, 145, 140]),
        (1.0, [253, 231, 37]),
    ];
    let k = if t <= 0.5 { 0 } else { 1 };
    let u = ((t - stops[k].0) / 0.5).clamp(0.0, 1.0);
    let c: Vec<u8> = (0..3)
        .map(|i| {
            (stops[k].1[i] as f64 + u * (stops[k + 1].1[i] as f64 - stops[k].1[i] as f64)) as u8
        })
        .collect();
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}
