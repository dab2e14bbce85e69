//! The whole-slider static stage: parameters → lattice operator (once) → per preload, the frozen
//! wave at each phase θ₀ (w(x) = A_n sin(θ₀ − kx), docs/physics.md §6) plus each post's extra height
//! ([`crate::heights`]) → constrained CG contact of all posts → post forces and gaps per phase →
//! η fitted as docs/physics.md §6 ([`static_contact::fit_eta`], pooled over the phases), load sharing
//! (Σf)²/(N Σf²), contact fraction, complementarity residual, iterations, wall time.
//!
//! Preload mechanisms ([`Mechanism`]): `rigid` (the body bonded to a rigid flat back, today's
//! clamp of the strip FEM: C is the lattice operator, the approach z_s the one multiplier);
//! `pressure` and `point` (a free back: C + G with G the bending of the slider outline as a free
//! Kirchhoff plate, [`crate::plate`], the preload's own deflection subtracted from the obstacle,
//! and the post forces balancing P and its two moments about the load point, [`crate::balanced`]).

use std::f64::consts::PI;
use std::time::Instant;

use contact_springs::{Material, post_springs};
use motor::Motor;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use static_contact::{EtaFit, FitSample, fit_eta};

use crate::balanced::BalancedCg;
use crate::error::{Result, SliderError, invalid};
use crate::heights::{Imperfections, ImperfectionsExt};
use crate::lattice::{
    ComplianceOperator, DiagonalParts, LatticeGeometry, LatticeOperator, NearField, OperatorSpec,
};
use crate::plate::FreePlate;
use crate::precondition::{ContactPreconditioner, PlatePreconditioner};
use crate::solver::{CgOptions, CgSolution, ConstrainedCg};

/// How the preload reaches the slider body (scene key `load.mechanism`): the motor's
/// [`motor::PreloadMechanism`] (`rigid`: the body bonded to a rigid flat back, the strip FEM's
/// clamp; `pressure`: P/(L·W) on a free back; `point`: a ball at (x, y) from the slider's corner).
pub use motor::PreloadMechanism as Mechanism;

/// What the whole-slider model needs of a [`Mechanism`] besides its data: parsing the scene's
/// words, the load point and its checks.
pub trait MechanismExt: Sized {
    /// Parses the scene's `load.mechanism` with its `load.point` (m, from the slider's corner):
    /// the point is required by `point` and refused by the others (it would change nothing).
    fn parse(name: &str, point_m: Option<(f64, f64)>) -> Result<Self>;
    /// Where the preload's resultant acts (m from the slider's corner): the centre for a
    /// pressure, the point for a ball; `None` for the rigid back.
    fn load_point_m(&self, g: &LatticeGeometry) -> Option<(f64, f64)>;
    /// Refuses a load point outside the slider or outside the post array (the posts could not
    /// balance its moment: the slider tips over its edge posts), and a free back on a single
    /// row or column of posts; errors name `load.point` / `load.mechanism`.
    fn validate(&self, g: &LatticeGeometry) -> Result<()>;
}

impl MechanismExt for Mechanism {
    fn parse(name: &str, point_m: Option<(f64, f64)>) -> Result<Self> {
        match (name, point_m) {
            ("point", Some((x_m, y_m))) => Ok(Self::Point { x_m, y_m }),
            ("point", None) => Err(invalid(
                "load.point",
                f64::NAN,
                "required by load.mechanism = \"point\" (e.g. \"2.5 mm, 2.5 mm\")",
            )),
            ("rigid" | "pressure", Some((x, _))) => Err(invalid(
                "load.point",
                x,
                format!("only used by load.mechanism = \"point\", not `{name}`"),
            )),
            ("rigid", None) => Ok(Self::Rigid),
            ("pressure", None) => Ok(Self::Pressure),
            (other, _) => Err(invalid(
                "load.mechanism",
                f64::NAN,
                format!("unknown mechanism `{other}` (rigid | pressure | point)"),
            )),
        }
    }

    fn load_point_m(&self, g: &LatticeGeometry) -> Option<(f64, f64)> {
        match *self {
            Self::Rigid => None,
            Self::Pressure => Some((0.5 * g.slider_length_m, 0.5 * g.slider_width_m)),
            Self::Point { x_m, y_m } => Some((x_m, y_m)),
        }
    }

    fn validate(&self, g: &LatticeGeometry) -> Result<()> {
        let Some((x, y)) = self.load_point_m(g) else {
            return Ok(());
        };
        if g.posts_x < 2 || g.posts_y < 2 {
            return Err(invalid(
                "load.mechanism",
                g.posts_x.min(g.posts_y) as f64,
                "a free back (pressure | point) needs at least 2 × 2 posts to balance its moments",
            ));
        }
        let (l, w) = (g.slider_length_m, g.slider_width_m);
        if !(x.is_finite() && y.is_finite() && (0.0..=l).contains(&x) && (0.0..=w).contains(&y)) {
            return Err(invalid(
                "load.point",
                x,
                format!(
                    "({x:e}, {y:e}) m is outside the slider [0, {l:e}] × [0, {w:e}] m \
                     (measured from its corner)"
                ),
            ));
        }
        let (x0, x1) = (g.x_m(0), g.x_m(g.posts_x - 1));
        let (y0, y1) = (g.y_m(0), g.y_m(g.posts_y - 1));
        if !(x > x0 && x < x1 && y > y0 && y < y1) {
            return Err(invalid(
                "load.point",
                x,
                format!(
                    "({x:e}, {y:e}) m is outside the post array [{x0:e}, {x1:e}] × [{y0:e}, {y1:e}] m: \
                     the posts cannot balance its moment, the slider would tip"
                ),
            ));
        }
        Ok(())
    }
}

/// Everything a whole-slider run depends on, in SI units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SliderParams {
    /// Slider material.
    pub slider_material: Material,
    /// Stator material.
    pub stator_material: Material,
    /// Post diameter d (m).
    pub post_diameter_m: f64,
    /// Post height h (m): the clearance of the body above the post tips.
    pub post_height_m: f64,
    /// Posts along x.
    pub posts_x: usize,
    /// Posts along y.
    pub posts_y: usize,
    /// Pitch (m).
    pub post_pitch_m: f64,
    /// Slider length along x (m), margins included.
    pub slider_length_m: f64,
    /// Slider width along y (m).
    pub slider_width_m: f64,
    /// Body thickness above the posts (m).
    pub slider_thickness_m: f64,
    /// Normal wave amplitude A_n (m); 0 for a flat stator.
    pub wave_amplitude_m: f64,
    /// The local amplitude along the slider, A(x_i)/A_n of each post column i (x ascending;
    /// empty: the constant-amplitude wave): the energy-conserving wave's profile, under which
    /// the static stage fits η at the amplitudes the posts see (docs/physics.md §5.5). Left
    /// out of the serialised parameters when empty, so constant-amplitude runs keep their keys.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub amplitude_scale_x: Vec<f64>,
    /// Wavelength λ (m).
    pub wavelength_m: f64,
    /// Preload P (N).
    pub preload_n: f64,
    /// Phases θ₀ = 2πk/phases (≥ 1).
    pub phases: usize,
    /// Post-height scatter, tilt, bow, height map.
    pub imperfections: Imperfections,
    /// Preload mechanism.
    pub mechanism: Mechanism,
    /// Slider-side near field of each post.
    pub near_field: NearField,
    /// Solver options.
    pub solver: CgOptions,
}

impl Default for SliderParams {
    /// The paper's motor ([`Motor::paper`], docs/physics.md §1): 100 × 100 posts of 20 µm at
    /// 40 µm in a 5 × 5 × 0.5 mm Si body, LiNbO3 stator, A_n = 20 nm, λ = 3979/9.61e6 m,
    /// P = 40 N; 4 phases, ideal posts, rigid back.
    fn default() -> Self {
        Self::for_motor(&Motor::paper())
    }
}

impl SliderParams {
    /// The whole slider of `motor` with the default settings (4 phases, ideal posts, rigid back,
    /// Johnson near field), its imperfections and preload mechanism. The lattice takes the x
    /// pitch (square lattices only).
    pub fn for_motor(motor: &Motor) -> Self {
        let posts = &motor.posts;
        Self {
            slider_material: motor.slider.material.clone(),
            stator_material: motor.stator.clone(),
            post_diameter_m: posts.diameter_m,
            post_height_m: posts.height_m,
            posts_x: posts.count_x as usize,
            posts_y: posts.count_y as usize,
            post_pitch_m: posts.pitch_x_m(),
            slider_length_m: motor.slider.length_m,
            slider_width_m: motor.slider.width_m,
            slider_thickness_m: motor.slider.thickness_m,
            wave_amplitude_m: motor.wave.normal_amplitude_m,
            amplitude_scale_x: Vec::new(),
            wavelength_m: motor.wave.wavelength_m(),
            preload_n: motor.load.preload_n,
            phases: 4,
            imperfections: motor.imperfections.clone(),
            mechanism: motor.load.mechanism,
            near_field: NearField::Johnson,
            solver: CgOptions::default(),
        }
    }
}

impl SliderParams {
    /// The lattice.
    pub fn geometry(&self) -> LatticeGeometry {
        LatticeGeometry {
            posts_x: self.posts_x,
            posts_y: self.posts_y,
            pitch_m: self.post_pitch_m,
            post_radius_m: 0.5 * self.post_diameter_m,
            slider_length_m: self.slider_length_m,
            slider_width_m: self.slider_width_m,
        }
    }

    /// The operator's inputs.
    pub fn operator_spec(&self) -> OperatorSpec {
        OperatorSpec {
            geometry: self.geometry(),
            slider_material: self.slider_material.clone(),
            stator_material: self.stator_material.clone(),
            slider_thickness_m: self.slider_thickness_m,
            near_field: self.near_field,
        }
    }

    /// Checks what the operator does not; errors name the field.
    pub fn validate(&self) -> Result<()> {
        self.geometry().validate()?;
        let positive = |field: &'static str, v: f64| {
            if v > 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err(invalid(field, v, "must be positive and finite"))
            }
        };
        positive("preload_n", self.preload_n)?;
        positive("post_height_m", self.post_height_m)?;
        positive("wavelength_m", self.wavelength_m)?;
        if !(self.wave_amplitude_m >= 0.0 && self.wave_amplitude_m.is_finite()) {
            return Err(invalid(
                "wave_amplitude_m",
                self.wave_amplitude_m,
                "must be ≥ 0 and finite",
            ));
        }
        if !self.amplitude_scale_x.is_empty() && self.amplitude_scale_x.len() != self.posts_x {
            return Err(invalid(
                "amplitude_scale_x",
                self.amplitude_scale_x.len() as f64,
                format!(
                    "one factor per post column ({} columns), or none",
                    self.posts_x
                ),
            ));
        }
        if let Some(a) = self
            .amplitude_scale_x
            .iter()
            .find(|a| !(**a >= 0.0 && a.is_finite()))
        {
            return Err(invalid(
                "amplitude_scale_x",
                *a,
                "factors must be ≥ 0 and finite",
            ));
        }
        if self.phases == 0 {
            return Err(invalid("phases", 0.0, "at least one phase"));
        }
        self.mechanism.validate(&self.geometry())?;
        if self.mechanism.is_free() {
            for (field, v) in [
                ("slider.tilt_x", self.imperfections.tilt_x_m),
                ("slider.tilt_y", self.imperfections.tilt_y_m),
            ] {
                if v != 0.0 {
                    return Err(invalid(
                        field,
                        v,
                        "a free back (load.mechanism = pressure | point) aligns itself with the \
                         stator, a tilt would change nothing; tilt applies to the rigid back",
                    ));
                }
            }
        }
        self.imperfections.validate(&self.geometry())
    }
}

/// One phase of one preload.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SliderSnapshot {
    /// θ₀ (rad); `None` for the flat stator.
    pub phase_rad: Option<f64>,
    /// Obstacle height h_i = w(x_i) + δ_i (m), lattice order.
    pub obstacle_height_m: Vec<f64>,
    /// Post forces (N), lattice order (index i·n_y + j).
    pub force_n: Vec<f64>,
    /// Gaps (m).
    pub gap_m: Vec<f64>,
    /// Fraction of posts in contact.
    pub contact_fraction: f64,
    /// (Σf)²/(N Σf²).
    pub load_sharing: f64,
    /// Scaled complementarity residual.
    pub complementarity_residual: f64,
    /// CG iterations.
    pub iterations: usize,
    /// Slider approach z_s (m).
    pub reference_height_m: f64,
    /// Free back: its rigid rotation (gap change per unit moment arm, m, along x and y).
    pub rotation_m: [f64; 2],
    /// Scaled residual per iteration.
    pub residual_history: Vec<f64>,
}

/// The report of a whole-slider run; top-level keys follow the contract.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SliderReport {
    /// Always `"slider"`.
    pub model: String,
    /// How the preload is applied.
    pub mechanism: Mechanism,
    /// Preload (N).
    pub preload_n: f64,
    /// η fitted over the wave phases (`None`: not identifiable, see `eta_fit.reason`).
    pub effective_contact_ratio: Option<f64>,
    /// The fit.
    pub eta_fit: EtaFit,
    /// Mean contact fraction over the phases.
    pub contact_fraction: f64,
    /// Mean load sharing over the phases.
    pub load_sharing: f64,
    /// Largest scaled complementarity residual.
    pub complementarity_residual: f64,
    /// CG iterations of all phases.
    pub iterations: usize,
    /// Post forces (N) of the first phase (θ₀ = 0), lattice order i·n_y + j.
    pub post_forces_n: Vec<f64>,
    /// Posts along x and y.
    pub posts_x: usize,
    /// Posts along y.
    pub posts_y: usize,
    /// Johnson series stiffness k_n (N/m) η refers to.
    pub k_n_n_per_m: f64,
    /// The diagonal of C.
    pub diagonal: DiagonalParts,
    /// Every phase.
    pub snapshots: Vec<SliderSnapshot>,
    /// Operator build time (s).
    pub operator_s: f64,
    /// Contact solves and η fit (s).
    pub contact_s: f64,
    /// The whole stage (s).
    pub wall_time_s: f64,
}

/// The operator and the post offsets of a slider: everything that does not depend on P.
#[derive(Debug)]
pub struct SliderModel {
    /// Parameters.
    pub params: SliderParams,
    /// C.
    pub operator: LatticeOperator,
    /// δ_i (m).
    pub post_offset_m: Vec<f64>,
    /// The free back's bending and load (pressure and point mechanisms).
    pub free_back: Option<FreeBack>,
    /// Build time (s).
    pub build_s: f64,
    /// Precondition a ball-loaded back's contact solve by its plate ([`PlatePreconditioner`]).
    /// False from [`SliderModel::build`]: measured on the default slider it cuts the iterations
    /// from 37–40 to 28–29 but costs more time (a refactorisation per contact-set change). The
    /// pressure mechanism always runs the plain CG: preconditioned, its contact set oscillates
    /// (validation/whole-slider/README.md, Speed).
    pub precondition_free_back: bool,
}

/// The free back of a pressure- or point-loaded slider: its plate, the posts' moment arms about
/// the load point, and the deflection under the preload.
#[derive(Debug)]
pub struct FreeBack {
    /// The plate of the slider outline.
    pub plate: FreePlate,
    /// Moment arms (ξ_i, η_i) of the posts about the load point, in units of half the post
    /// array's length and width.
    pub arms: Vec<(f64, f64)>,
    /// Upward deflection at the posts (m per N of preload) under the preload alone.
    pub load_deflection_m_per_n: Vec<f64>,
}

impl FreeBack {
    fn new(params: &SliderParams) -> Result<Self> {
        let g = params.geometry();
        let (xp, yp) = params
            .mechanism
            .load_point_m(&g)
            .expect("a free mechanism has a load point");
        let posts: Vec<(f64, f64)> = (0..g.posts_x)
            .flat_map(|i| (0..g.posts_y).map(move |j| (g.x_m(i), g.y_m(j))))
            .collect();
        let plate = FreePlate::new(
            g.slider_length_m,
            g.slider_width_m,
            params.slider_thickness_m,
            &params.slider_material,
            &posts,
        )?;
        let (ax, ay) = (
            0.5 * g.posts_x as f64 * g.pitch_m,
            0.5 * g.posts_y as f64 * g.pitch_m,
        );
        let arms = posts
            .iter()
            .map(|&(x, y)| ((x - xp) / ax, (y - yp) / ay))
            .collect();
        let load_deflection_m_per_n = match params.mechanism {
            Mechanism::Pressure => {
                plate.pressure_deflection(1.0 / (g.slider_length_m * g.slider_width_m))
            }
            _ => plate.point_load_deflection(1.0, xp, yp),
        };
        Ok(Self {
            plate,
            arms,
            load_deflection_m_per_n,
        })
    }
}

/// The compliance of a free slider: the lattice operator (stator, the body's local part) plus
/// the bending of its back.
struct FreeBodyOperator<'a> {
    lattice: &'a LatticeOperator,
    plate: &'a FreePlate,
}

impl ComplianceOperator for FreeBodyOperator<'_> {
    fn len(&self) -> usize {
        self.lattice.len()
    }
    fn apply(&self, force_n: &[f64], out_m: &mut [f64]) {
        self.lattice.apply(force_n, out_m);
        self.plate.add_post_deflection(force_n, out_m);
    }
    fn diagonal(&self) -> Vec<f64> {
        let mut d = self.lattice.diagonal();
        let mut unit = vec![0.0; d.len()];
        let mut u = vec![0.0; d.len()];
        for i in 0..d.len() {
            unit[i] = 1.0;
            u.iter_mut().for_each(|x| *x = 0.0);
            self.plate.add_post_deflection(&unit, &mut u);
            d[i] += u[i];
            unit[i] = 0.0;
        }
        d
    }
}

impl SliderModel {
    /// Validates and builds the operator (once).
    pub fn build(params: &SliderParams) -> Result<Self> {
        let start = Instant::now();
        params.validate()?;
        let post_offset_m = params.imperfections.post_offsets_m(&params.geometry())?;
        params.imperfections.check_body_clearance(
            &params.geometry(),
            params.post_height_m,
            &post_offset_m,
        )?;
        let operator = LatticeOperator::new(&params.operator_spec())?;
        let free_back = if params.mechanism.is_free() {
            Some(FreeBack::new(params)?)
        } else {
            None
        };
        Ok(Self {
            params: params.clone(),
            operator,
            post_offset_m,
            free_back,
            build_s: start.elapsed().as_secs_f64(),
            precondition_free_back: false,
        })
    }

    /// Obstacle heights at phase θ₀ (`None`: flat stator).
    pub fn obstacle_heights(&self, phase_rad: Option<f64>) -> Vec<f64> {
        let p = &self.params;
        let g = p.geometry();
        let k = 2.0 * PI / p.wavelength_m;
        let mut h = self.post_offset_m.clone();
        if let Some(theta) = phase_rad {
            for i in 0..g.posts_x {
                let local = p.amplitude_scale_x.get(i).copied().unwrap_or(1.0);
                let w = local * p.wave_amplitude_m * (theta - k * g.x_m(i)).sin();
                for j in 0..g.posts_y {
                    h[g.index(i, j)] += w;
                }
            }
        }
        h
    }

    /// Gap scale L (m): the wave amplitude, else the spread of the post heights, else P/N·C_ii.
    fn length_scale(&self, preload_n: f64, height_m: &[f64]) -> f64 {
        let spread = height_m.iter().copied().fold(f64::MIN, f64::max)
            - height_m.iter().copied().fold(f64::MAX, f64::min);
        if self.params.wave_amplitude_m > 0.0 {
            self.params.wave_amplitude_m
        } else if spread > 0.0 {
            spread
        } else {
            preload_n / self.operator.len() as f64 * self.operator.parts().total_m_per_n()
        }
    }

    /// Solves one phase.
    pub fn solve_phase(&self, preload_n: f64, phase_rad: Option<f64>) -> Result<SliderSnapshot> {
        let h = self.obstacle_heights(phase_rad);
        let sol = self
            .solve_heights(preload_n, &h, None, self.params.solver)
            .map_err(|e| with_context(e, preload_n, phase_rad))?;
        Ok(snapshot(phase_rad, h, sol))
    }

    /// Solves the contact of every post on given obstacle heights h_i (m, lattice order; the
    /// post offsets δ_i already included, e.g. [`Self::obstacle_heights`] with a local wave
    /// amplitude) under `preload_n`, with this slider's operator and preload mechanism (rigid
    /// back: Σf = P; free back: P and its moments about the load point, the preload's own plate
    /// deflection subtracted): the static stage's solve, also used by the coupled dynamics of
    /// the whole slider at every grid phase. `start_n`: forces (N) to start the solve from,
    /// e.g. the solution of nearby heights (the same solution to the tolerance, fewer
    /// iterations); `None`: equal forces. `solver`: the CG's tolerance and iteration limit (the
    /// static stage's are `params.solver`).
    pub fn solve_heights(
        &self,
        preload_n: f64,
        h: &[f64],
        start_n: Option<&[f64]>,
        solver: CgOptions,
    ) -> Result<CgSolution> {
        if h.len() != self.operator.len() {
            return Err(invalid(
                "obstacle_height_m",
                h.len() as f64,
                format!("one height per post ({} posts)", self.operator.len()),
            ));
        }
        let scale = self.length_scale(preload_n, h);
        match &self.free_back {
            None => {
                ConstrainedCg::new(solver).solve_from(&self.operator, h, preload_n, scale, start_n)
            }
            Some(back) => {
                // gap = z + θ·φ − h + (C + G) f + w_load: the load's deflection lowers the obstacle.
                let shifted: Vec<f64> = h
                    .iter()
                    .zip(&back.load_deflection_m_per_n)
                    .map(|(hi, w)| hi - preload_n * w)
                    .collect();
                let op = FreeBodyOperator {
                    lattice: &self.operator,
                    plate: &back.plate,
                };
                let use_pre = self.precondition_free_back
                    && matches!(self.params.mechanism, Mechanism::Point { .. });
                // Built only when used: it indexes K for every post (10 000 × 136 entries).
                let mut pre = use_pre.then(|| {
                    PlatePreconditioner::new(&back.plate, self.operator.parts().total_m_per_n())
                });
                let pre = pre.as_mut().map(|p| p as &mut dyn ContactPreconditioner);
                BalancedCg::new(solver)
                    .solve_preconditioned(&op, pre, &shifted, preload_n, scale, &back.arms, start_n)
            }
        }
    }

    /// All phases of one preload, and η.
    pub fn analyse(&self, preload_n: f64) -> Result<SliderReport> {
        let start = Instant::now();
        let p = &self.params;
        let k_n = post_springs(
            &p.slider_material,
            &p.stator_material,
            0.5 * p.post_diameter_m,
        )
        .map_err(|e| invalid("post_diameter_m", p.post_diameter_m, e.to_string()))?
        .k_n_n_per_m;
        // Phases are independent solves on the shared operator: in parallel (deterministic).
        let snapshots = (0..p.phases)
            .into_par_iter()
            .map(|k| self.solve_phase(preload_n, Some(2.0 * PI * k as f64 / p.phases as f64)))
            .collect::<Result<Vec<_>>>()?;
        let samples: Vec<FitSample> = snapshots
            .iter()
            .map(|s| FitSample {
                height_m: s.obstacle_height_m.clone(),
                force_n: s.force_n.clone(),
                preload_n,
            })
            .collect();
        let eta_fit = fit_eta(&samples, k_n);
        let m = snapshots.len() as f64;
        let contact_s = start.elapsed().as_secs_f64();
        Ok(SliderReport {
            model: "slider".into(),
            mechanism: p.mechanism,
            preload_n,
            effective_contact_ratio: eta_fit.eta,
            eta_fit,
            contact_fraction: snapshots.iter().map(|s| s.contact_fraction).sum::<f64>() / m,
            load_sharing: snapshots.iter().map(|s| s.load_sharing).sum::<f64>() / m,
            complementarity_residual: snapshots
                .iter()
                .map(|s| s.complementarity_residual)
                .fold(0.0, f64::max),
            iterations: snapshots.iter().map(|s| s.iterations).sum(),
            post_forces_n: snapshots[0].force_n.clone(),
            posts_x: p.posts_x,
            posts_y: p.posts_y,
            k_n_n_per_m: k_n,
            diagonal: self.operator.parts(),
            snapshots,
            operator_s: self.build_s,
            contact_s,
            wall_time_s: self.build_s + contact_s,
        })
    }
}

fn with_context(e: SliderError, preload_n: f64, phase: Option<f64>) -> SliderError {
    match e {
        SliderError::NotConverged {
            iterations,
            residual,
            tolerance,
            active,
            posts,
            ..
        } => SliderError::NotConverged {
            iterations,
            residual,
            tolerance,
            active,
            posts,
            context: format!(
                " at preload {preload_n} N, phase {}",
                phase.map_or("flat".to_string(), |p| format!("{p:.4} rad"))
            ),
        },
        other => other,
    }
}

fn snapshot(phase_rad: Option<f64>, h: Vec<f64>, sol: CgSolution) -> SliderSnapshot {
    let f = &sol.force_n;
    let n = f.len() as f64;
    let sum: f64 = f.iter().sum();
    let sum_sq: f64 = f.iter().map(|x| x * x).sum();
    SliderSnapshot {
        phase_rad,
        obstacle_height_m: h,
        contact_fraction: f.iter().filter(|&&x| x > 0.0).count() as f64 / n,
        load_sharing: if sum_sq > 0.0 {
            sum * sum / (n * sum_sq)
        } else {
            0.0
        },
        complementarity_residual: sol.complementarity_residual,
        iterations: sol.iterations,
        reference_height_m: sol.reference_height_m,
        rotation_m: sol.rotation_m,
        force_n: sol.force_n,
        gap_m: sol.gap_m,
        residual_history: sol.residual_history,
    }
}

/// Builds the model and analyses the main preload: the static stage of `static.model = "slider"`.
pub fn run(params: &SliderParams) -> Result<SliderReport> {
    let start = Instant::now();
    let model = SliderModel::build(params)?;
    let mut report = model.analyse(params.preload_n)?;
    report.wall_time_s = start.elapsed().as_secs_f64();
    Ok(report)
}
