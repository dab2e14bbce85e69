//! Coupled stick/slip of **every post of the whole slider** (the post lattice of
//! `slider-contact`, 10⁴ posts for the paper's slider) on its own static state: post-height
//! scatter, height map, tilt, bow and preload mechanism, as the static stage solves them.
//!
//! Model: the strip's coupled model ([`crate::model`]) with its two compliances replaced by the
//! whole slider's:
//!
//! - **normal** (Goodman's approximation: independent of friction and speed, so solved once per
//!   scene on the phase grid θ_j = θ₀ + 2πj/M): at every grid phase the static stage's own
//!   contact solve ([`NormalContact`]; for a [`slider_contact::SliderModel`] its
//!   `solve_heights`: the lattice operator, constrained CG, Σf = P on a rigid back, P and both
//!   moments on a free back with the plate's bending) on the obstacle
//!   h_i = δ_i + α_i A_n sin(θ_j − σ k x_i), δ_i the post's height offset of the static stage,
//!   α_i its local wave amplitude (1, or the energy-conserving wave's profile);
//! - **tangential**: the lattice operator C_t of `slider_contact::tangential` (Cerruti
//!   half-space terms of both bodies, the bonded layer's correction, FFT convolution), each
//!   step's box QP solved matrix-free ([`crate::boxqp::solve_operator`]: the strip's primal–dual
//!   active set, CG on the free block, warm-started from the previous step's forces and sets).
//!
//! Everything else — Coulomb law with μ_s/μ_k per post, the imposed speed's Doppler-shifted
//! step, periodic steady state with its extrapolation, midpoint-force energy bookkeeping
//! (stator = output + friction to round-off), stall thrust, no-load speed, the curve's warm
//! chains, η_dyn — is the strip model's code, unchanged ([`CoupledModel::from_normal_grid`]).
//! The strip is the one-row limit: a 1 × n slider on the same compliances gives the strip's
//! results, and an ideal lattice periodic in y gives them exactly (tests `slider_dynamics`).
//!
//! **Symmetry and size.** A slider with the y-mirror symmetry (ideal, or symmetric height map,
//! tilt and bow: detected by [`Mirror::of`], broken by height scatter) runs on the half of its
//! posts with the folded tangential operator (`slider_contact::tangential_mirror`), strip
//! share ½: the same results (a test holds it to 1e-10) at half the unknowns and half the FFT
//! work; its per-post results are expanded back to every post. A lattice whose model would
//! hold more than [`MAX_SLIDER_MODEL_BYTES`] is refused before anything is allocated
//! ([`SliderScene::model_bytes`]); a step that does not converge is named with its speed, grid
//! step and lattice post.
//!
//! Outputs beyond the strip's: 2D maps per post ([`SliderMaps`]: time-mean normal force, slip
//! fraction, contact fraction, friction power — where the slider wears first — and stator
//! power) at stall and at half the no-load speed.
//!
//! **Normal–tangential coupling**: dropped, as in the strip model; for Si on LiNbO3 Dundurs'
//! β = 0.021 (`slider_contact::dundurs_beta`), and a warning is given when |β| exceeds
//! `slider_contact::NEGLIGIBLE_DUNDURS_BETA`. The tangential compliance of a free back is the
//! bonded layer's (the back moves rigidly in x with the imposed speed; its in-plane stretching
//! under the friction forces, O(t/L) of the layer's shear, is not modelled).
//!
//! **Energy-conserving wave**: [`SliderScene::amplitude_scale`] carries α_i per post (lattice
//! order; the strip's `CoupledScene::amplitude_scale` convention), and
//! [`SliderDynamics::solve_attenuated`] solves every curve point at its self-consistent profile
//! (the fixed point of [`crate::attenuation`], one lane of the wave's power per lattice row;
//! the `attenuation` submodule).
//!
//! Valid where the strip model is (quasi-static posts, rigid heavy slider at an imposed speed,
//! continuous wave) and the lattice operators are (loads ≫ a apart, ≥ t from the slider's
//! edges for the body's local part).

mod attenuation;
mod maps;
pub mod mirror;

use std::f64::consts::PI;
use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;
use slider_contact::{
    CgOptions, ComplianceOperator, ConstrainedCg, LatticeGeometry, NearField, SliderModel,
    TangentialKernel,
};
use stick_slip::{DynamicScene, Wave};

pub use attenuation::{AttenuatedSlider, ProfiledState, SliderProfiles};
pub use maps::{AMPLITUDE_FIELD, MAP_FIELDS, SliderMaps};
pub use mirror::Mirror;

use crate::error::{CoupledError, Result};
use crate::model::{ComplianceProduct, CoupledModel, PostHistories};
use crate::model::{CoupledPoint, PeriodState, PostMeans};
use crate::result::{CoupledResult, assemble, solve};
use crate::scene::{CoupledScene, DEFAULT_STEPS_PER_PERIOD, PreloadBalance, WaveDirection};

/// Default natural-residual tolerance of the whole slider's step solves (relative to the
/// friction scale): the CG solves reach it in ≈ √κ log(1/ε) products; the periodicity rule is
/// 100× it. Default 1e-10.
pub const DEFAULT_SLIDER_TOLERANCE: f64 = 1e-10;
/// Default points of the whole slider's speed–thrust curve (stall to no load): each point costs
/// a steady solve of every post (validation/whole-slider/dynamics: the cost table), the curve
/// of the strip's model has 50. Default 8.
pub const DEFAULT_SLIDER_CURVE_POINTS: usize = 8;
/// Tolerance of the whole slider's no-load speed from a prediction (of the crest speed,
/// [`SliderDynamics::solve_from_guess`]): the thrust at a speed is known to the periodicity
/// rule (≈ 1e-8 of the friction scale), so the root is known to ≈ 1e-8 of the crest speed;
/// tighter costs evaluations that only move it within that. Default 1e-7.
pub const SLIDER_SPEED_TOLERANCE: f64 = 1e-7;

/// Memory a whole slider's coupled model may hold (bytes; [`SliderScene::model_bytes`]): a
/// larger lattice is refused before anything is allocated, naming its size and this limit.
/// The paper's 10⁴ posts at 64 steps need ≈ 22 MB. Default 4 GB (≈ 2·10⁶ posts at 64 steps).
pub const MAX_SLIDER_MODEL_BYTES: f64 = 4e9;

/// The whole slider's dynamic scene (SI).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SliderScene {
    /// The post lattice (post i along x, j along y is post i·n_y + j).
    pub geometry: LatticeGeometry,
    /// Each post's height offset δ_i (m, lattice order): scatter, height map, tilt, bow
    /// (`SliderModel::post_offset_m` of the static stage).
    pub post_offset_m: Vec<f64>,
    /// The travelling wave (continuous, no decay).
    pub wave: Wave,
    /// Static friction coefficient μ_s.
    pub mu_static: f64,
    /// Kinetic friction coefficient μ_k ≤ μ_s.
    pub mu_kinetic: f64,
    /// Preload (N).
    pub preload_n: f64,
    /// Direction of the wave.
    pub wave_direction: WaveDirection,
    /// Nominal steps per wave period.
    pub steps_per_period: usize,
    /// Phase of the slider's x = 0 edge at the first grid step (rad).
    pub start_phase_rad: f64,
    /// Points of the speed–thrust curve.
    pub curve_points: usize,
    /// Natural-residual tolerance of each step's solve (relative).
    pub tolerance: f64,
    /// Local wave amplitude A_i/A₀ per post (lattice order); empty: 1 everywhere.
    pub amplitude_scale: Vec<f64>,
}

impl SliderScene {
    /// The scene of a static stage's slider (its lattice, post offsets and preload) driven by
    /// `wave` with friction μ_s, μ_k; defaults otherwise.
    pub fn for_static(model: &SliderModel, wave: Wave, mu_static: f64, mu_kinetic: f64) -> Self {
        Self {
            geometry: model.params.geometry(),
            post_offset_m: model.post_offset_m.clone(),
            wave,
            mu_static,
            mu_kinetic,
            preload_n: model.params.preload_n,
            wave_direction: WaveDirection::PlusX,
            steps_per_period: DEFAULT_STEPS_PER_PERIOD,
            start_phase_rad: 0.0,
            curve_points: DEFAULT_SLIDER_CURVE_POINTS,
            tolerance: DEFAULT_SLIDER_TOLERANCE,
            amplitude_scale: Vec::new(),
        }
    }

    /// Post centres x (m) from the slider's −x edge, lattice order.
    pub fn post_x_m(&self) -> Vec<f64> {
        let g = &self.geometry;
        (0..g.posts_x)
            .flat_map(|i| std::iter::repeat_n(g.x_m(i), g.posts_y))
            .collect()
    }

    /// The strip model's settings for these posts (its dense compliances empty: the slider's
    /// are operators).
    pub fn coupled_settings(&self) -> CoupledScene {
        CoupledScene {
            wave: self.wave.clone(),
            post_x_m: self.post_x_m(),
            normal_compliance_m_per_n: nalgebra::DMatrix::zeros(0, 0),
            tangential_compliance_m_per_n: nalgebra::DMatrix::zeros(0, 0),
            mu_static: self.mu_static,
            mu_kinetic: self.mu_kinetic,
            preload_n: self.preload_n,
            wave_direction: self.wave_direction,
            strip_share: 1.0,
            preload_balance: PreloadBalance::Instant,
            steps_per_period: self.steps_per_period,
            start_phase_rad: self.start_phase_rad,
            curve_points: self.curve_points,
            tolerance: self.tolerance,
            amplitude_scale: self.amplitude_scale.clone(),
        }
    }

    /// Obstacle heights h_i = δ_i + α_i A_n sin(θ − σ k x_i) (m) at reference phase θ.
    pub fn obstacle_heights_m(&self, phase_rad: f64) -> Vec<f64> {
        let k = self.wave.wavenumber_rad_per_m();
        let sigma = self.wave_direction.sign();
        let a = self.wave.normal_amplitude_m;
        self.post_x_m()
            .iter()
            .enumerate()
            .map(|(i, x)| {
                let alpha = self.amplitude_scale.get(i).copied().unwrap_or(1.0);
                self.post_offset_m[i] + alpha * a * (phase_rad - sigma * (k * x)).sin()
            })
            .collect()
    }

    /// Memory the coupled model of this scene holds (bytes, estimated before anything is
    /// allocated): per post the normal forces and the wave's motion at every grid phase, the
    /// normal grid's solves, the step solvers' vectors of two parallel branches and the maps'
    /// sums (8 bytes each, ≈ 3M + 64 numbers for M steps per period), plus the tangential
    /// operator's padded grid and its work arrays (≈ 48 bytes per padded point).
    pub fn model_bytes(&self) -> f64 {
        let g = &self.geometry;
        let posts = g.posts_x as f64 * g.posts_y as f64;
        let padded = |n: usize| 2.0 * n.max(1) as f64;
        8.0 * posts * (3.0 * self.steps_per_period as f64 + 64.0)
            + 48.0 * padded(g.posts_x) * padded(g.posts_y)
    }

    fn validate(&self) -> Result<()> {
        let bytes = self.model_bytes();
        if bytes > MAX_SLIDER_MODEL_BYTES {
            let g = &self.geometry;
            return Err(CoupledError::InvalidParameter {
                parameter: "posts_x × posts_y",
                value: g.posts_x as f64 * g.posts_y as f64,
                requirement: format!(
                    "the coupled model of {} × {} posts at {} steps per period would need ≈ {:.1} GB, above the limit of {:.1} GB (MAX_SLIDER_MODEL_BYTES)",
                    g.posts_x,
                    g.posts_y,
                    self.steps_per_period,
                    bytes / 1e9,
                    MAX_SLIDER_MODEL_BYTES / 1e9
                ),
            });
        }
        self.geometry.validate()?;
        if self.post_offset_m.len() != self.geometry.len() {
            return Err(CoupledError::DimensionMismatch {
                what: "post_offset_m",
                expected: self.geometry.len(),
                found: self.post_offset_m.len(),
            });
        }
        if let Some(d) = self.post_offset_m.iter().find(|d| !d.is_finite()) {
            return Err(CoupledError::InvalidParameter {
                parameter: "post_offset_m",
                value: *d,
                requirement: "must be finite".into(),
            });
        }
        self.coupled_settings().validate_settings()
    }
}

/// The strip model of the slider's middle row on the slider's own compliances: C_strip(i, k) is
/// the displacement of post (i, n_y/2) when every post of column k carries a unit force (all
/// rows alike, as the strip's mirror images), normal and tangential (symmetrised); strip share
/// 1/n_y; the scene's settings otherwise (δ_i and α_i of the middle row). The one-row limit the
/// whole slider is compared with: their difference is the edge effect (rows near the slider's y
/// edges carry differently), and for a lattice periodic in y it vanishes.
pub fn middle_row_strip(
    scene: &SliderScene,
    normal: &dyn ComplianceOperator,
    tangential: &dyn ComplianceOperator,
) -> Result<CoupledScene> {
    scene.validate()?;
    let g = scene.geometry;
    let (nx, ny) = (g.posts_x, g.posts_y);
    let mid = ny / 2;
    let row = |op: &dyn ComplianceOperator| {
        let mut c = nalgebra::DMatrix::zeros(nx, nx);
        let (mut f, mut u) = (vec![0.0; nx * ny], vec![0.0; nx * ny]);
        for k in 0..nx {
            f.iter_mut().for_each(|x| *x = 0.0);
            f[k * ny..(k + 1) * ny].iter_mut().for_each(|x| *x = 1.0);
            op.apply(&f, &mut u);
            for i in 0..nx {
                c[(i, k)] = u[i * ny + mid];
            }
        }
        (&c + c.transpose()) * 0.5
    };
    let mut strip = scene.coupled_settings();
    strip.post_x_m = (0..nx).map(|i| g.x_m(i)).collect();
    strip.normal_compliance_m_per_n = row(normal);
    strip.tangential_compliance_m_per_n = row(tangential);
    strip.strip_share = 1.0 / ny as f64;
    if !scene.amplitude_scale.is_empty() {
        strip.amplitude_scale = (0..nx)
            .map(|i| scene.amplitude_scale[i * ny + mid])
            .collect();
    }
    if scene.post_offset_m.iter().any(|d| *d != 0.0) {
        return Err(CoupledError::InvalidParameter {
            parameter: "post_offset_m",
            value: scene
                .post_offset_m
                .iter()
                .fold(0.0, |m: f64, d| m.max(d.abs())),
            requirement: "the strip of the middle row stands for an ideal slider (no post offsets)"
                .into(),
        });
    }
    strip.validate()?;
    Ok(strip)
}

/// The steady points at `speeds` in that order, each started from the previous one's periodic
/// state (the first from `start`), with the last one's state.
fn chain<'a>(
    model: &CoupledModel,
    speeds: impl Iterator<Item = &'a f64>,
    start: Option<PeriodState>,
) -> Result<(Vec<CoupledPoint>, Option<PeriodState>)> {
    let mut warm = start;
    let mut points = Vec::new();
    for &speed in speeds {
        let (point, state) = model.at_speed_from(speed, warm.as_ref())?;
        warm = Some(state);
        points.push(point);
    }
    Ok((points, warm))
}

/// The normal contact of all posts at one instant: post forces for given obstacle heights.
pub trait NormalContact: Sync {
    /// Number of posts.
    fn posts(&self) -> usize;
    /// A representative normal self compliance C_ii (m/N): the solver's force scale.
    fn self_compliance_m_per_n(&self) -> f64;
    /// Post forces f_i ≥ 0 (N, lattice order) and the rigid approach z (m) for obstacle
    /// heights h (m) under the preload (N), the solve started from the forces `start_n` (N,
    /// e.g. the solution of nearby heights) if given: the same solution to the tolerance, the
    /// contact's own or the looser `tolerance` if given (its scaled complementarity residual,
    /// `slider_contact::CgOptions::tolerance`).
    fn solve_contact(
        &self,
        heights_m: &[f64],
        preload_n: f64,
        start_n: Option<&[f64]>,
        tolerance: Option<f64>,
    ) -> Result<(Vec<f64>, f64)>;
}

impl NormalContact for SliderModel {
    fn posts(&self) -> usize {
        self.operator.len()
    }
    fn self_compliance_m_per_n(&self) -> f64 {
        self.operator.parts().total_m_per_n()
    }
    fn solve_contact(
        &self,
        heights_m: &[f64],
        preload_n: f64,
        start_n: Option<&[f64]>,
        tolerance: Option<f64>,
    ) -> Result<(Vec<f64>, f64)> {
        let solver = loosened(self.params.solver, tolerance);
        let s = self.solve_heights(preload_n, heights_m, start_n, solver)?;
        Ok((s.force_n, s.reference_height_m))
    }
}

/// `options` with the tolerance `tolerance` where that is looser.
fn loosened(options: CgOptions, tolerance: Option<f64>) -> CgOptions {
    CgOptions {
        tolerance: tolerance.map_or(options.tolerance, |t| t.max(options.tolerance)),
        ..options
    }
}

/// A rigid back on any normal compliance operator, solved by the constrained CG of
/// `slider-contact` (Σf = P): tests and hand-made lattices.
#[derive(Debug, Clone)]
pub struct RigidBackContact<C> {
    /// C_n (m/N).
    pub operator: C,
    /// CG options.
    pub options: CgOptions,
    /// Gap scale of the solve (m), e.g. the wave amplitude.
    pub length_scale_m: f64,
}

impl<C: ComplianceOperator + Sync> NormalContact for RigidBackContact<C> {
    fn posts(&self) -> usize {
        self.operator.len()
    }
    fn self_compliance_m_per_n(&self) -> f64 {
        let d = self.operator.diagonal();
        d.iter().sum::<f64>() / d.len().max(1) as f64
    }
    fn solve_contact(
        &self,
        heights_m: &[f64],
        preload_n: f64,
        start_n: Option<&[f64]>,
        tolerance: Option<f64>,
    ) -> Result<(Vec<f64>, f64)> {
        let s = ConstrainedCg::new(loosened(self.options, tolerance)).solve_from(
            &self.operator,
            heights_m,
            preload_n,
            self.length_scale_m,
            start_n,
        )?;
        Ok((s.force_n, s.reference_height_m))
    }
}

/// The whole slider's coupled model, normal forces on the phase grid solved.
#[derive(Clone)]
pub struct SliderDynamics {
    scene: SliderScene,
    model: CoupledModel,
    /// C_t as the model holds it (the folded operator under a mirror): the models of other
    /// amplitude profiles share it.
    tangential: Arc<dyn ComplianceProduct>,
    dundurs_beta: Option<f64>,
    normal_grid_wall_s: f64,
    mirror: Option<Mirror>,
}

impl std::fmt::Debug for SliderDynamics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SliderDynamics")
            .field("scene", &self.scene)
            .field("model", &self.model)
            .field("mirror", &self.mirror)
            .finish_non_exhaustive()
    }
}

/// The normal contact of every post on the phase grid (full lattice order).
struct NormalGrid {
    normals_n: Vec<Vec<f64>>,
    approach_m: Vec<f64>,
    k_ref_n_per_m: f64,
    wall_s: f64,
}

impl NormalGrid {
    /// Validates the scene and solves the normal contact at every grid phase with `normal`
    /// (in parallel over the phases), each phase's solve started from `start`'s forces at that
    /// phase (full lattice order, e.g. the grid of a nearby amplitude profile) if given, to
    /// the contact's own tolerance or the looser `tolerance` if given.
    fn solve(
        scene: &SliderScene,
        normal: &dyn NormalContact,
        start: Option<&[Vec<f64>]>,
        tolerance: Option<f64>,
    ) -> Result<Self> {
        scene.validate()?;
        let n = scene.geometry.len();
        if normal.posts() != n {
            return Err(CoupledError::DimensionMismatch {
                what: "normal contact operator",
                expected: n,
                found: normal.posts(),
            });
        }
        let started = Instant::now();
        let m = scene.steps_per_period;
        let grid = (0..m)
            .into_par_iter()
            .map(|j| {
                let theta = scene.start_phase_rad + 2.0 * PI * j as f64 / m as f64;
                let from = start.and_then(|grid| grid.get(j)).map(Vec::as_slice);
                let heights_m = scene.obstacle_heights_m(theta);
                normal.solve_contact(&heights_m, scene.preload_n, from, tolerance)
            })
            .collect::<Result<Vec<_>>>()?;
        let (normals_n, approach_m): (Vec<Vec<f64>>, Vec<f64>) = grid.into_iter().unzip();
        Ok(Self {
            normals_n,
            approach_m,
            k_ref_n_per_m: 1.0 / normal.self_compliance_m_per_n(),
            wall_s: started.elapsed().as_secs_f64(),
        })
    }
}

/// The whole slider's coupled run: the strip's result for the whole slider plus its maps.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SliderDynamicsResult {
    /// Curve, stall, no-load speed, energy balance, η_dyn, … (`posts` = every post).
    #[serde(flatten)]
    pub coupled: CoupledResult,
    /// Posts along x.
    pub posts_x: usize,
    /// Posts along y.
    pub posts_y: usize,
    /// Dundurs' β of the bodies (normal–tangential coupling dropped), if known.
    pub dundurs_beta: Option<f64>,
    /// Maps at stall and at half the no-load speed.
    pub maps: Vec<SliderMaps>,
    /// Lattice indices of the posts in [`Self::histories`]: the middle row (j = n_y/2), x
    /// ascending.
    pub history_posts: Vec<usize>,
    /// Forces and modes of the middle row's posts over the steady period of the maps at half
    /// the no-load speed.
    pub histories: PostHistories,
    /// Wall time of the normal solves on the phase grid (s).
    pub normal_grid_wall_s: f64,
}

impl SliderDynamics {
    /// Builds the model: validates the scene, solves the normal contact at every grid phase
    /// with `normal` (in parallel over the phases) and takes `tangential` as C_t.
    pub fn new(
        scene: &SliderScene,
        normal: &dyn NormalContact,
        tangential: Arc<dyn ComplianceProduct>,
    ) -> Result<Self> {
        let grid = NormalGrid::solve(scene, normal, None, None)?;
        Self::on_grid(scene, grid, tangential, None, None)
    }

    /// The model on a solved normal grid: on every post, or with `mirror` on the folded
    /// lattice (`tangential` then the folded C_m, the normal forces and the scene's per-post
    /// data restricted to its rows, strip share ½). `start`: a model of the same posts (another
    /// amplitude profile's), whose wave table the new model takes.
    fn on_grid(
        scene: &SliderScene,
        grid: NormalGrid,
        tangential: Arc<dyn ComplianceProduct>,
        mirror: Option<Mirror>,
        start: Option<&CoupledModel>,
    ) -> Result<Self> {
        let mut settings = scene.coupled_settings();
        let mut normals = grid.normals_n;
        if let Some(fold) = mirror {
            settings.post_x_m = fold.restrict(&settings.post_x_m);
            if !settings.amplitude_scale.is_empty() {
                settings.amplitude_scale = fold.restrict(&settings.amplitude_scale);
            }
            settings.strip_share = 0.5;
            normals = normals.iter().map(|f| fold.restrict(f)).collect();
        }
        let mut model = CoupledModel::from_normal_grid(
            &settings,
            grid.k_ref_n_per_m,
            normals,
            grid.approach_m,
            tangential.clone(),
            start,
        )?;
        model.set_lattice_rows(mirror.map_or(scene.geometry.posts_y, |m| m.half_posts_y()));
        Ok(Self {
            scene: scene.clone(),
            model,
            tangential,
            dundurs_beta: None,
            normal_grid_wall_s: grid.wall_s,
            mirror,
        })
    }

    /// The model of a static stage's slider: its normal contact (operator, offsets, preload
    /// mechanism) and the tangential lattice operator of the same lattice and bodies with the
    /// slider side's tangential near field `tangential_near_field` (Johnson's 1/k_pt, or
    /// calibrated on the strip FEM: `slider_contact::calibrate_tangential_near_field`).
    /// On the folded lattice when the slider has the y-mirror symmetry ([`Mirror::of`]:
    /// ideal or symmetric sliders, not under height scatter), else on every post.
    pub fn for_slider(
        scene: &SliderScene,
        static_model: &SliderModel,
        tangential_near_field: NearField,
    ) -> Result<Self> {
        Self::for_slider_with(scene, static_model, tangential_near_field, true)
    }

    /// [`Self::for_slider`], the y-mirror used only if `use_mirror` (and the slider has it).
    pub fn for_slider_with(
        scene: &SliderScene,
        static_model: &SliderModel,
        tangential_near_field: NearField,
        use_mirror: bool,
    ) -> Result<Self> {
        scene.validate()?;
        let spec = static_model.params.operator_spec();
        let kernel = TangentialKernel::new(&spec, tangential_near_field)?;
        let grid = NormalGrid::solve(scene, static_model, None, None)?;
        let mirror = Mirror::of(scene, &grid.normals_n).filter(|_| use_mirror);
        let tangential: Arc<dyn ComplianceProduct> = match mirror {
            Some(_) => Arc::new(kernel.mirror_operator(&spec.geometry)?),
            None => Arc::new(kernel.operator()),
        };
        let mut out = Self::on_grid(scene, grid, tangential, mirror, None)?;
        out.dundurs_beta = Some(slider_contact::dundurs_beta(&spec));
        Ok(out)
    }

    /// The y-mirror the model runs on, if any.
    pub fn mirror(&self) -> Option<Mirror> {
        self.mirror
    }

    /// The scene.
    pub fn scene(&self) -> &SliderScene {
        &self.scene
    }

    /// The coupled model (steady points, curve, histories: the strip model's API). With a
    /// [`Self::mirror`] its posts are the folded lattice's ([`Mirror::restrict`] order).
    pub fn model(&self) -> &CoupledModel {
        &self.model
    }

    /// Wall time of the normal solves on the phase grid (s).
    pub fn normal_grid_wall_s(&self) -> f64 {
        self.normal_grid_wall_s
    }

    /// The maps at an imposed speed (m/s) along the drive direction, from rest.
    pub fn maps_at(&self, speed_m_per_s: f64) -> Result<SliderMaps> {
        let (point, means, _) = self.model.post_means_from(speed_m_per_s, None)?;
        Ok(self.maps(point, means))
    }

    /// The maps of the model's per-post means (expanded to the full lattice under a mirror).
    fn maps(&self, point: CoupledPoint, means: PostMeans) -> SliderMaps {
        let means = match self.mirror {
            Some(fold) => fold.expand_means(means),
            None => means,
        };
        SliderMaps::new(
            &self.scene.geometry,
            point,
            means,
            &self.scene.amplitude_scale,
        )
    }

    /// The model's indices of the full lattice's posts `posts`.
    fn model_posts(&self, posts: &[usize]) -> Vec<usize> {
        match self.mirror {
            Some(fold) => posts.iter().map(|&p| fold.folded_index(p)).collect(),
            None => posts.to_vec(),
        }
    }

    /// Lattice indices of the middle row's posts (j = n_y/2), x ascending.
    pub fn middle_row_posts(&self) -> Vec<usize> {
        let g = &self.scene.geometry;
        (0..g.posts_x)
            .map(|i| i * g.posts_y + g.posts_y / 2)
            .collect()
    }

    /// Stall thrust, no-load speed, curve, energy balance, η_dyn (with `lumped`, the lumped
    /// scene of the same motor), the maps at stall and at half the no-load speed, and the
    /// middle row's histories over the latter's period. The no-load speed by the strip model's
    /// search from the crest speed ([`CoupledModel::no_load_search`]); with a prediction of it,
    /// [`Self::solve_from_guess`] is cheaper.
    pub fn solve(&self, lumped: Option<&DynamicScene>) -> Result<SliderDynamicsResult> {
        self.solve_from_guess(lumped, None)
    }

    /// [`Self::solve`] with the no-load speed searched from the prediction `no_load_guess_m_per_s`
    /// (the lumped model's, or the middle row's strip) by [`CoupledModel::no_load_search_near`]
    /// to [`SLIDER_SPEED_TOLERANCE`]. Every speed after the stall starts from a neighbouring
    /// speed's periodic state, and the work runs as two parallel branches twice: the no-load
    /// search (from the stall's state) beside the stall's maps; then the curve's upper half
    /// downwards from the search's last state beside its lower half upwards from the stall's
    /// state, which ends with the maps at half the no-load speed.
    pub fn solve_from_guess(
        &self,
        lumped: Option<&DynamicScene>,
        no_load_guess_m_per_s: Option<f64>,
    ) -> Result<SliderDynamicsResult> {
        let Some(guess) = no_load_guess_m_per_s else {
            return self.solve_cold(lumped);
        };
        let started = Instant::now();
        let model = &self.model;
        let (stall_point, stall_state) = model.at_speed_from(0.0, None)?;
        let (search, stall_maps) = rayon::join(
            || model.no_load_search_near(stall_point.thrust_n, guess, SLIDER_SPEED_TOLERANCE, None),
            || model.post_means_from(0.0, Some(&stall_state)),
        );
        let (no_load, top) = search?;
        let points = model.scene().curve_points;
        let speeds: Vec<f64> = (1..points)
            .map(|k| no_load * k as f64 / (points - 1) as f64)
            .collect();
        let (lower, upper) = speeds.split_at((points - 1) / 2);
        let history_posts = self.middle_row_posts();
        let (upper, lower) = rayon::join(
            || chain(model, upper.iter().rev(), top),
            || -> Result<_> {
                let (points, last) = chain(model, lower.iter(), Some(stall_state.clone()))?;
                let half = model.post_means_and_histories_from(
                    0.5 * no_load,
                    last.as_ref(),
                    &self.model_posts(&history_posts),
                )?;
                Ok((points, half))
            },
        );
        let (mut upper, _) = upper?;
        let (lower, (point, means, histories, _)) = lower?;
        upper.reverse();
        let mut curve = vec![stall_point];
        curve.extend(lower.into_iter().chain(upper));
        let (stall_point, stall_means, _) = stall_maps?;
        let maps = vec![self.maps(stall_point, stall_means), self.maps(point, means)];
        let coupled = assemble(model, lumped, no_load, curve, started)?;
        Ok(self.finish(coupled, maps, history_posts, histories, started))
    }

    /// [`Self::solve`]: the strip model's sequence, the maps from rest.
    fn solve_cold(&self, lumped: Option<&DynamicScene>) -> Result<SliderDynamicsResult> {
        let started = Instant::now();
        let coupled = solve(&self.model, lumped)?;
        let half = 0.5 * coupled.no_load_speed_m_per_s;
        let history_posts = self.middle_row_posts();
        let (stall, at_half) = rayon::join(
            || self.maps_at(0.0),
            || {
                self.model.post_means_and_histories_from(
                    half,
                    None,
                    &self.model_posts(&history_posts),
                )
            },
        );
        let (point, means, histories, _) = at_half?;
        let maps = vec![stall?, self.maps(point, means)];
        Ok(self.finish(coupled, maps, history_posts, histories, started))
    }

    /// The result with the β warning and the wall time from `started` (normal grid included).
    fn finish(
        &self,
        mut coupled: CoupledResult,
        maps: Vec<SliderMaps>,
        history_posts: Vec<usize>,
        histories: PostHistories,
        started: Instant,
    ) -> SliderDynamicsResult {
        if let Some(beta) = self
            .dundurs_beta
            .filter(|b| b.abs() > slider_contact::NEGLIGIBLE_DUNDURS_BETA)
        {
            coupled.warnings.push(format!(
                "Dundurs β = {beta:.3} exceeds {}: the normal–tangential coupling the model drops is not negligible",
                slider_contact::NEGLIGIBLE_DUNDURS_BETA
            ));
        }
        coupled.wall_time_s = started.elapsed().as_secs_f64() + self.normal_grid_wall_s;
        coupled.posts = self.scene.geometry.len();
        if self.mirror.is_some() {
            // The folded model counts a post and its image once.
            let bound = self.model.never_separating_posts();
            let (folded, full) = (
                format!("{bound} posts never separate"),
                format!("{} posts never separate", 2 * bound),
            );
            for w in &mut coupled.warnings {
                if w.starts_with(&folded) {
                    *w = w.replacen(&folded, &full, 1);
                }
            }
        }
        SliderDynamicsResult {
            coupled,
            posts_x: self.scene.geometry.posts_x,
            posts_y: self.scene.geometry.posts_y,
            dundurs_beta: self.dundurs_beta,
            maps,
            history_posts,
            histories,
            normal_grid_wall_s: self.normal_grid_wall_s,
        }
    }
}
