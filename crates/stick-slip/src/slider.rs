//! The rigid slider: mass, preload, external load, post layout, effective contact ratio and
//! the vertical model (docs/physics.md §4–6).

use serde::{Deserialize, Serialize};

use motor::{Motor, PostArray};

use crate::error::{
    Result, StickSlipError, Warning, require_finite, require_non_negative, require_positive,
};
use crate::limits::MAX_RUN_MEMORY_BYTES;

// The paper's slider (docs/physics.md §1), from the one copy of its numbers in `motor::paper`.
pub use motor::paper::{
    EFFECTIVE_RATIO as PAPER_EFFECTIVE_RATIO, PITCH_M as PAPER_PITCH_M,
    SLIDER_SIDE_M as PAPER_SLIDER_SIDE_M, SLIDER_THICKNESS_M as PAPER_SLIDER_THICKNESS_M,
};
/// Posts per side of the paper's densest array (100 × 100 = 10000 posts of 20 µm).
pub const PAPER_POSTS_PER_SIDE: usize = motor::paper::POSTS_PER_SIDE as usize;

/// Where the posts sit on the slider, along the wave direction x (relative to the slider
/// centre). Only x matters to the wave; posts with equal x (mod λ, without decay or burst) share
/// a phase and are simulated as one group.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum PostLayout {
    /// An n × n square array with the given pitch, centred: n columns of n posts at
    /// x_j = (j − (n−1)/2)·pitch.
    SquareArray {
        /// Posts per side n (n² posts in total).
        posts_per_side: usize,
        /// Centre-to-centre distance (m).
        pitch_m: f64,
    },
    /// Posts at explicit x positions (one entry per post), with optional initial gaps g_i ≥ 0
    /// (height scatter): N_i = k_n⟨w − z_s − g_i⟩₊.
    Positions {
        /// x of every post relative to the slider centre (m).
        x_m: Vec<f64>,
        /// Initial gap of every post (m); `None`: all zero.
        #[serde(default)]
        gap_m: Option<Vec<f64>>,
    },
    /// `post_count` posts spread uniformly over the wave phase (the periodic-average model's
    /// assumption; the transient uses equally spaced phase groups).
    UniformPhase {
        /// Number of posts.
        post_count: usize,
    },
}

impl PostLayout {
    /// The layout of the motor's post array: a centred square array when the lattice is square,
    /// else one x per post (refused, naming `posts.count`, when the positions alone would exceed
    /// the run's memory limit).
    pub fn for_array(posts: &PostArray) -> Result<Self> {
        if posts.count_x == posts.count_y && posts.is_square_lattice(1e-12) {
            return Ok(Self::SquareArray {
                posts_per_side: posts.count_x as usize,
                pitch_m: posts.pitch_x_m(),
            });
        }
        let bytes = posts.count() as f64 * 4.0 * std::mem::size_of::<f64>() as f64;
        if bytes > MAX_RUN_MEMORY_BYTES {
            return Err(StickSlipError::InvalidParameter {
                parameter: "posts.count",
                value: posts.count() as f64,
                requirement: format!(
                    "a rectangular array needs ≈ {bytes:.3e} bytes of post positions, above the limit of {MAX_RUN_MEMORY_BYTES:.3e} bytes"
                ),
            });
        }
        let x_m = posts
            .column_x_m()
            .into_iter()
            .flat_map(|x| std::iter::repeat_n(x, posts.count_y as usize))
            .collect();
        Ok(Self::Positions { x_m, gap_m: None })
    }

    /// Total number of posts N.
    pub fn post_count(&self) -> usize {
        match self {
            Self::SquareArray { posts_per_side, .. } => posts_per_side * posts_per_side,
            Self::Positions { x_m, .. } => x_m.len(),
            Self::UniformPhase { post_count } => *post_count,
        }
    }

    /// Whether any post has a non-zero initial gap.
    pub fn has_gaps(&self) -> bool {
        matches!(self, Self::Positions { gap_m: Some(g), .. } if g.iter().any(|&g| g != 0.0))
    }

    /// Check the layout.
    pub fn validate(&self) -> Result<()> {
        let bad = |detail: String| Err(StickSlipError::InvalidLayout { detail });
        match self {
            Self::SquareArray {
                posts_per_side,
                pitch_m,
            } => {
                if *posts_per_side == 0 {
                    return bad("square-array: posts_per_side must be ≥ 1".into());
                }
                if *posts_per_side > 1 {
                    require_positive("slider.layout.pitch_m", *pitch_m)?;
                }
            }
            Self::Positions { x_m, gap_m } => {
                if x_m.is_empty() {
                    return bad("positions: x_m holds no post".into());
                }
                if let Some(i) = x_m.iter().position(|x| !x.is_finite()) {
                    return bad(format!("positions: x_m[{i}] = {} is not finite", x_m[i]));
                }
                if let Some(gaps) = gap_m {
                    if gaps.len() != x_m.len() {
                        return bad(format!(
                            "positions: gap_m has {} entries for {} posts",
                            gaps.len(),
                            x_m.len()
                        ));
                    }
                    if let Some(i) = gaps.iter().position(|g| !(g.is_finite() && *g >= 0.0)) {
                        return bad(format!(
                            "positions: gap_m[{i}] = {} must be finite and ≥ 0",
                            gaps[i]
                        ));
                    }
                }
            }
            Self::UniformPhase { post_count } => {
                if *post_count == 0 {
                    return bad("uniform-phase: post_count must be ≥ 1".into());
                }
            }
        }
        Ok(())
    }

    /// Every post as (x (m), gap (m), count) with posts of equal x and gap merged. Uniform-phase
    /// layouts are spread over one wavelength in `groups` equally spaced positions.
    pub(crate) fn columns(&self, wavelength_m: f64, uniform_groups: usize) -> Vec<(f64, f64, f64)> {
        match self {
            Self::SquareArray {
                posts_per_side,
                pitch_m,
            } => {
                let n = *posts_per_side;
                let centre = (n as f64 - 1.0) / 2.0;
                (0..n)
                    .map(|j| ((j as f64 - centre) * pitch_m, 0.0, n as f64))
                    .collect()
            }
            Self::Positions { x_m, gap_m } => {
                let mut posts: Vec<(f64, f64)> = x_m
                    .iter()
                    .enumerate()
                    .map(|(i, &x)| (x, gap_m.as_ref().map_or(0.0, |g| g[i])))
                    .collect();
                posts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
                let mut columns: Vec<(f64, f64, f64)> = Vec::new();
                for (x, g) in posts {
                    match columns.last_mut() {
                        Some(last) if last.0 == x && last.1 == g => last.2 += 1.0,
                        _ => columns.push((x, g, 1.0)),
                    }
                }
                columns
            }
            Self::UniformPhase { post_count } => {
                let groups = uniform_groups.clamp(1, *post_count);
                let weight = *post_count as f64 / groups as f64;
                (0..groups)
                    .map(|j| (wavelength_m * j as f64 / groups as f64, 0.0, weight))
                    .collect()
            }
        }
    }
}

/// Vertical dynamics of the slider.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum VerticalModel {
    /// Quasi-static: the tip height z_s is constant and fixed by Σ⟨N_i⟩ = P over a period.
    #[default]
    PeriodMean,
    /// Dynamic: M z̈_s = ΣN_i − P − c ż_s, with c = 2ζ√(M K_n), K_n = N_eff k_n the fully
    /// engaged contact stiffness (ζ = 0: undamped bounce).
    Dynamic {
        /// Damping ratio ζ of the vertical slider mode (dimensionless, ≥ 0).
        damping_ratio: f64,
    },
}

/// The rigid slider.
///
/// Sign convention (docs/physics.md §4): the wave travels along +x, the slider is driven along −x.
/// `external_load_n` is the magnitude of a load *opposing* the drive (it pushes the slider along
/// +x): M v̇ = ΣF_i + external_load_n, i.e. docs/physics.md's F_load = −external_load_n. A negative
/// value assists the drive.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Slider {
    /// Slider mass M (kg).
    pub mass_kg: f64,
    /// Preload P pressing the slider onto the stator (N).
    pub preload_n: f64,
    /// Load opposing the drive (N); the operating point's thrust.
    #[serde(default)]
    pub external_load_n: f64,
    /// Post positions.
    pub layout: PostLayout,
    /// Effective contact ratio η: the model uses N_eff = η·N posts (docs/physics.md §6).
    #[serde(default = "unit_ratio")]
    pub effective_ratio: f64,
    /// Vertical model.
    #[serde(default)]
    pub vertical: VerticalModel,
}

fn unit_ratio() -> f64 {
    1.0
}

impl Slider {
    /// The paper's slider: Si 5 × 5 × 0.5 mm, 100 × 100 posts at 40 µm pitch, η = 0.36,
    /// preload 40 N, no external load, quasi-static vertical.
    pub fn paper_default() -> Self {
        Self::for_motor(
            &Motor::paper(),
            PAPER_EFFECTIVE_RATIO,
            VerticalModel::PeriodMean,
        )
        .expect("the paper's square array has a square-array layout")
    }

    /// The rigid slider of `motor` with effective contact ratio η and the vertical model.
    pub fn for_motor(motor: &Motor, effective_ratio: f64, vertical: VerticalModel) -> Result<Self> {
        Ok(Self {
            mass_kg: motor.slider.mass_kg,
            preload_n: motor.load.preload_n,
            external_load_n: motor.load.external_load_n,
            layout: PostLayout::for_array(&motor.posts)?,
            effective_ratio,
            vertical,
        })
    }

    /// Effective post count N_eff = η·N.
    pub fn effective_post_count(&self) -> f64 {
        self.effective_ratio * self.layout.post_count() as f64
    }

    /// Check the slider.
    pub fn validate(&self) -> Result<Vec<Warning>> {
        let mut warnings = Vec::new();
        require_positive("slider.mass_kg", self.mass_kg)?;
        require_positive("slider.preload_n", self.preload_n)?;
        require_finite("slider.external_load_n", self.external_load_n)?;
        contact_springs::effective_ratio::check(self.effective_ratio).map_err(|e| {
            StickSlipError::InvalidParameter {
                parameter: "slider.effective_ratio",
                value: self.effective_ratio,
                requirement: e.to_string(),
            }
        })?;
        if self.effective_ratio > 1.0 {
            warnings.push(Warning::new(
                "slider.effective_ratio",
                format!(
                    "η = {} > 1 uses more posts than the slider has",
                    self.effective_ratio
                ),
            ));
        }
        self.layout.validate()?;
        if let VerticalModel::Dynamic { damping_ratio } = self.vertical {
            require_non_negative("slider.vertical.damping_ratio", damping_ratio)?;
        }
        Ok(warnings)
    }
}
