//! The coupled quasi-static model: every post of the strip with unilateral contact and Coulomb
//! friction (μ_s, μ_k) on the dense normal and tangential tip compliances, driven by the
//! travelling wave at its own x, the rigid heavy slider at an imposed speed (periodic steady
//! state).
//!
//! Solver units: length A_n, time 1/ω, force k_ref A_n with k_ref = 1/mean(C_nn,ii); Ĉ = k_ref C.
//! The reference phase θ_r = ωt − k x_s(t) advances at s = 1 − κ v̂ (κ = kA_n, v̂ the slider's
//! scaled x-velocity); post i sees θ_i = θ_r − k x_i, the surface w_i = sin θ_i and the material
//! velocity u̇_i = −â sin θ_i (â = A_t/A_n).
//!
//! Normal problem (independent of friction, Goodman's approximation, and of the speed: it
//! depends on θ_r only, so it is solved once per scene on the phase grid): N ≥ 0,
//! g = z − w + Ĉ_n N ≥ 0, N·g = 0, with Σ N = P̂ at every instant ([`PreloadBalance::Instant`],
//! static-contact's active-set solver) or one z with the period mean Σ⟨N⟩ = P̂.
//!
//! Tangential problem of a step t_n → t_{n+1} = t_n + h (backward Euler on the quasi-static
//! Jenkins posts, the lumped model's return mapping generalised to a dense compliance): the
//! tip's elastic deflection e = Ĉ_t T, the stick condition Δe = Δu − v̂h, Coulomb's law with the
//! slip increment Δs = Δu − v̂h − Δe:  |T_i| ≤ μ_i N_i, Δs_i = λ_i sign T_i, λ_i ≥ 0,
//! λ_i(μ_i N_i − |T_i|) = 0. These are the KKT conditions of the box QP
//! min ½TᵀĈ_tT − bᵀT, |T_i| ≤ μ_i N_i, b = Ĉ_t Tⁿ + Δu − v̂h ([`crate::boxqp`]). μ_i = μ_k for a
//! post slipping in the previous step, else μ_s; a post that slips with μ_s drops to μ_k and
//! the step is re-solved (bounds only fall, so this ends).
//!
//! Energy per step, exactly consistent: every work term uses the midpoint force
//! T̄ = (Tⁿ + Tⁿ⁺¹)/2, the discrete gradient of the stored energy ½TᵀĈ_tT (Gonzalez,
//! J. Nonlinear Sci. 6 (1996) 449): stator T̄·Δu, output T̄·v̂h, friction T̄·Δs. The step's
//! compatibility Δu = v̂h + Ĉ_tΔT + Δs is exact (Δs = b − Ĉ_tTⁿ⁺¹), and
//! T̄·Ĉ_tΔT = ½Tⁿ⁺¹ᵀĈ_tTⁿ⁺¹ − ½TⁿᵀĈ_tTⁿ, so stator = output + friction + stored change holds
//! to round-off in every step, and over a periodic cycle stator = output + friction. The
//! right-endpoint bookkeeping (Tⁿ⁺¹ in every term) misses by the numerical dissipation
//! ½ΔTᵀĈ_tΔT, first order in h (reported separately).

use std::f64::consts::PI;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use slider_contact::Precision;
use static_contact::{ActiveSetOptions, ActiveSetSolver, ContactProblem};

use crate::anderson::Anderson;
use crate::boxqp::{self, ActiveSet};
use crate::error::{CoupledError, Result};
use crate::scene::{CoupledScene, PreloadBalance};

/// Periods stepped at most before a speed is declared quasi-periodic (averaged over the last
/// half). Default 64.
pub const MAX_PERIODS: usize = 64;
/// Largest change of a tip force between two period starts (of the friction scale) that counts
/// as periodic. Default 1e-11.
pub const PERIODIC_TOLERANCE: f64 = 1e-11;
/// Relative tolerance of the no-load speed root (of the crest speed). Default 1e-10.
pub const SPEED_TOLERANCE: f64 = 1e-10;
/// Periods stepped by every model of the process (a cost counter for benchmarks and probes).
static PERIODS_STEPPED: AtomicUsize = AtomicUsize::new(0);

/// Periods stepped so far by every coupled model of this process, on every thread: the cost
/// measure of a solve independent of the machine's load (read it before and after).
pub fn periods_stepped() -> usize {
    PERIODS_STEPPED.load(Ordering::Relaxed)
}

/// Count one stepped period.
fn count_period() {
    PERIODS_STEPPED.fetch_add(1, Ordering::Relaxed);
}

/// Bisection steps of the period-mean approach. Default 200 (stops at round-off).
const APPROACH_BISECTIONS: usize = 200;
/// The period mean Σ⟨N⟩ of [`PreloadBalance::PeriodMean`] is taken on a grid this many times
/// finer than the step grid (trapezoidal rule on a periodic function with kinks at the contact
/// edges: error O((2π/(rM))²), ≈ 1e-8 relative at r = 32, M = 128), so that the approach is
/// that of the continuous period mean, as in the lumped model. Default 32.
pub const PERIOD_MEAN_REFINEMENT: usize = 32;

/// A tangential compliance C_t (m/N) given by its product: the whole slider's lattice operator
/// (`slider_contact::LatticeOperator::tangential`, an FFT convolution) or any other
/// symmetric positive definite operator of the posts.
pub trait ComplianceProduct: Send + Sync {
    /// Number of posts.
    fn posts(&self) -> usize;
    /// u = C_t f (m for f in N; `u` overwritten).
    fn apply(&self, force_n: &[f64], out_m: &mut [f64]);
    /// u = C_t f in `precision` (`slider_contact::Precision`; an operator without a
    /// single-precision product computes in double).
    fn apply_at(&self, force_n: &[f64], out_m: &mut [f64], precision: Precision) {
        let _ = precision;
        self.apply(force_n, out_m);
    }
}

impl<T: slider_contact::ComplianceOperator + Send + Sync> ComplianceProduct for T {
    fn posts(&self) -> usize {
        self.len()
    }
    fn apply(&self, force_n: &[f64], out_m: &mut [f64]) {
        slider_contact::ComplianceOperator::apply(self, force_n, out_m);
    }
    fn apply_at(&self, force_n: &[f64], out_m: &mut [f64], precision: Precision) {
        slider_contact::ComplianceOperator::apply_at(self, force_n, out_m, precision);
    }
}

/// Ĉ_t = k_ref C_t, dense (the strip) or as a product (the whole slider).
#[derive(Clone)]
enum Tangential {
    Dense(DMatrix<f64>),
    Operator {
        op: Arc<dyn ComplianceProduct>,
        k_ref: f64,
    },
}

impl std::fmt::Debug for Tangential {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Dense(m) => write!(f, "Dense({} × {})", m.nrows(), m.ncols()),
            Self::Operator { op, k_ref } => {
                write!(f, "Operator({} posts, k_ref {k_ref:e})", op.posts())
            }
        }
    }
}

impl boxqp::SymmetricProduct for Tangential {
    fn size(&self) -> usize {
        match self {
            Self::Dense(m) => m.nrows(),
            Self::Operator { op, .. } => op.posts(),
        }
    }
    fn product(&self, x: &[f64], y: &mut [f64], precision: Precision) {
        match self {
            Self::Dense(m) => {
                let v = m * DVector::from_column_slice(x);
                y.copy_from_slice(v.as_slice());
            }
            Self::Operator { op, k_ref } => {
                op.apply_at(x, y, precision);
                y.iter_mut().for_each(|v| *v *= k_ref);
            }
        }
    }
}

impl Tangential {
    fn times(&self, x: &DVector<f64>) -> DVector<f64> {
        match self {
            Self::Dense(m) => m * x,
            Self::Operator { .. } => {
                let mut y = DVector::zeros(x.len());
                let double = Precision::Double;
                boxqp::SymmetricProduct::product(self, x.as_slice(), y.as_mut_slice(), double);
                y
            }
        }
    }
}

/// Per-post sums over one steady period (solver units), for the maps of the whole slider.
#[derive(Debug, Clone)]
pub(crate) struct PostSums {
    /// Σ T̄_i·Δu_i: stator work.
    pub stator_work: DVector<f64>,
    /// Σ T̄_i·Δs_i: friction work.
    pub friction_work: DVector<f64>,
    /// Σ N_i h: normal impulse.
    pub normal_impulse: DVector<f64>,
    /// Time slipping.
    pub slip_time: DVector<f64>,
    /// Time in contact.
    pub contact_time: DVector<f64>,
}

impl PostSums {
    fn new(n: usize) -> Self {
        Self {
            stator_work: DVector::zeros(n),
            friction_work: DVector::zeros(n),
            normal_impulse: DVector::zeros(n),
            slip_time: DVector::zeros(n),
            contact_time: DVector::zeros(n),
        }
    }
}

/// Time means of every post over one steady period at one speed, whole slider (SI).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PostMeans {
    /// Imposed speed along the drive direction (m/s).
    pub speed_m_per_s: f64,
    /// Time-mean normal force of each post (N).
    pub mean_normal_force_n: Vec<f64>,
    /// Time slipping over time in contact of each post (0 for a post never in contact).
    pub slip_fraction: Vec<f64>,
    /// Time in contact over the period of each post.
    pub contact_fraction: Vec<f64>,
    /// Time-mean friction power dissipated at each post's tip (W): where the slider wears.
    pub friction_power_w: Vec<f64>,
    /// Time-mean stator power each post draws (W).
    pub stator_power_w: Vec<f64>,
}

/// Contact state of a post during a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PostMode {
    /// No contact.
    Separated,
    /// Stuck.
    Stick,
    /// Slipping.
    Slip,
}

/// Steady period-average behaviour at one imposed speed, SI, whole slider.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CoupledPoint {
    /// Speed along the drive direction (m/s).
    pub speed_m_per_s: f64,
    /// Mean thrust along the drive direction (N).
    pub thrust_n: f64,
    /// Output power (W).
    pub output_power_w: f64,
    /// Power the stator delivers through the tangential contacts (W): Σ T̄·Δu per period,
    /// T̄ = (Tⁿ + Tⁿ⁺¹)/2 the discrete gradient of the stored energy.
    pub stator_power_w: f64,
    /// Friction dissipation Σ T̄·Δs (W): slip work, including the elastic energy released
    /// where a post drops from μ_s to μ_k.
    pub friction_dissipation_w: f64,
    /// Numerical dissipation of the backward-Euler trajectory Σ ½ΔTᵀC_tΔT (W): O(h); the
    /// amount by which the right-endpoint bookkeeping (T = Tⁿ⁺¹ in every work term) misses.
    pub numerical_dissipation_w: f64,
    /// Output over stator power.
    pub efficiency: f64,
    /// Time stuck over time in contact, all posts.
    pub stick_fraction: f64,
    /// Time in contact over time, mean over posts.
    pub contact_fraction: f64,
    /// (stator − output − friction − stored change)/power flow over the steady period, every
    /// term with the midpoint force T̄: closes to round-off (discrete energy identity, see the
    /// module docs); a check of the step's kinematic compatibility Δu = v̂h + Ĉ_tΔT + Δs.
    pub energy_balance_residual: f64,
    /// The same balance with the right-endpoint force Tⁿ⁺¹ in every work term (the usual
    /// backward-Euler bookkeeping): misses by the numerical dissipation, first order in h.
    pub right_endpoint_balance_residual: f64,
    /// The right-endpoint balance with the numerical dissipation included: round-off.
    pub energy_identity_residual: f64,
    /// Whether the steady cycle closed.
    pub converged: bool,
    /// Periods stepped.
    pub periods: usize,
    /// Largest natural residual of the step solves.
    pub max_solver_residual: f64,
    /// Total active-set iterations (and Gauss–Seidel sweeps).
    pub solver_iterations: usize,
    /// Steps that needed the Gauss–Seidel fallback.
    pub fallback_steps: usize,
}

/// Forces of every post over one steady period (strip posts; forces per post, N).
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct PostHistories {
    /// Imposed speed along the drive direction (m/s).
    pub speed_m_per_s: f64,
    /// Sample times from the period start (s).
    pub time_s: Vec<f64>,
    /// Normal force of each post at each sample (N), `[sample][post]`.
    pub normal_force_n: Vec<Vec<f64>>,
    /// Tangential force on the slider along the drive direction (N), `[sample][post]`.
    pub tangential_force_n: Vec<Vec<f64>>,
    /// Contact mode, `[sample][post]`.
    pub mode: Vec<Vec<PostMode>>,
}

/// The coupled model of a scene, with the normal forces on the phase grid solved.
#[derive(Debug, Clone)]
pub struct CoupledModel {
    scene: CoupledScene,
    /// Ĉ_t.
    ct: Tangential,
    /// Largest change of a tip force between two period starts (of the friction scale) that
    /// counts as periodic: [`PERIODIC_TOLERANCE`], or ≥ 100× the step tolerance where the steps
    /// are solved iteratively (the whole slider).
    periodic_tolerance: f64,
    /// σ k x_i (rad), σ = ±1 the wave direction: θ_i = θ_r − σ k x_i.
    kx: Vec<f64>,
    /// σ.
    sigma: f64,
    /// â.
    a_t: f64,
    /// κ.
    doppler: f64,
    /// Normal forces N̂_i at grid phase j (j = 0..M).
    normals: Vec<DVector<f64>>,
    /// Rigid approach ẑ at grid phase j.
    approach: Vec<f64>,
    /// cos(θ_j − σ k x_i) at grid phase j = 0..=M, `[j][i]`: the tangential wave motion of
    /// every post on the grid, the same at every speed (made once, not twice per step).
    wave_cos: Vec<DVector<f64>>,
    /// Whether the approach to the periodic state is extrapolated ([`Approach`]): only when
    /// every post separates at some phase (else the periodic state is not unique).
    extrapolate: bool,
    /// k_ref A_n (N).
    force_n: f64,
    length_m: f64,
    omega: f64,
    normal_wall_s: f64,
    /// The normal problem's factor at each grid phase where a model of a nearby profile
    /// reused or made one ([`NormalFactor`]); empty for a cold model.
    normal_factors: Vec<Option<Arc<NormalFactor>>>,
    /// The wave's unit shape on the phase grid, shared by the models of one scene's profiles.
    unit_wave: Arc<UnitWave>,
    /// Posts per lattice column when the posts are a lattice's (i·rows + j): how an error
    /// names a post.
    lattice_rows: Option<usize>,
}

/// sin(θ_j − σkx_i) and cos(θ_j − σkx_i) on the phase grid θ_j = θ₀ + 2πj/M, j = 0..=M: the
/// wave's unit shape, which a model of another amplitude profile of the same posts scales by
/// α_i instead of evaluating it again (the same values, so the same bits).
#[derive(Debug)]
struct UnitWave {
    start_phase_rad: f64,
    kx: Vec<f64>,
    sin: Vec<DVector<f64>>,
    cos: Vec<DVector<f64>>,
}

impl UnitWave {
    fn new(start_phase_rad: f64, kx: &[f64], m: usize) -> Self {
        let theta = |j: usize| start_phase_rad + 2.0 * PI * j as f64 / m as f64;
        let table = |f: fn(f64) -> f64| -> Vec<DVector<f64>> {
            (0..=m)
                .map(|j| DVector::from_fn(kx.len(), |i, _| f(theta(j) - kx[i])))
                .collect()
        };
        Self {
            start_phase_rad,
            kx: kx.to_vec(),
            sin: table(f64::sin),
            cos: table(f64::cos),
        }
    }

    fn fits(&self, start_phase_rad: f64, kx: &[f64], m: usize) -> bool {
        self.start_phase_rad == start_phase_rad && self.kx == kx && self.sin.len() == m + 1
    }
}

/// The Cholesky factor of Ĉ_AA on one phase's contact set A, kept with the model so that a
/// model of a nearby amplitude profile ([`CoupledModel::new_from`]) solves that phase by two
/// triangular solves when the contact set stays: on A the gaps vanish, Ĉ_AA N_A = h_A − z, and
/// Σ N_A = P̂ fixes z, so N_A = a − z b with a = Ĉ_AA⁻¹h_A, b = Ĉ_AA⁻¹1,
/// z = (1ᵀa − P̂)/(1ᵀb). The solution is taken when it is the contact problem's (every N_A ≥ 0,
/// every gap off A ≥ −tolerance, in the solver's units); otherwise the active-set solver runs
/// from A as before.
#[derive(Debug, Clone)]
struct NormalFactor {
    active: Vec<bool>,
    indices: Vec<usize>,
    cholesky: nalgebra::Cholesky<f64, nalgebra::Dyn>,
    /// b = Ĉ_AA⁻¹1, the same at every profile.
    unit: DVector<f64>,
}

impl NormalFactor {
    fn new(cn: &DMatrix<f64>, active: &[bool]) -> Option<Self> {
        let indices: Vec<usize> = (0..active.len()).filter(|&i| active[i]).collect();
        if indices.is_empty() {
            return None;
        }
        let sub = cn.select_rows(&indices).select_columns(&indices);
        let cholesky = sub.cholesky()?;
        let unit = cholesky.solve(&DVector::from_element(indices.len(), 1.0));
        Some(Self {
            active: active.to_vec(),
            cholesky,
            indices,
            unit,
        })
    }

    fn fits(&self, active: &[bool]) -> bool {
        self.active == active
    }

    /// The normal forces and approach on this contact set, if they solve the contact problem.
    fn solve(
        &self,
        cn: &DMatrix<f64>,
        heights: &DVector<f64>,
        preload: f64,
        tolerance: f64,
    ) -> Option<(DVector<f64>, f64)> {
        let k = self.indices.len();
        let h_a = DVector::from_fn(k, |r, _| heights[self.indices[r]]);
        let a = self.cholesky.solve(&h_a);
        let b = &self.unit;
        let z = (a.sum() - preload) / b.sum();
        let f_a = a - b * z;
        if f_a.iter().any(|f| !(*f >= 0.0)) {
            return None;
        }
        let mut force = DVector::zeros(heights.len());
        for (r, &i) in self.indices.iter().enumerate() {
            force[i] = f_a[r];
        }
        // Ĉ_n N from the columns of A alone (the others carry no force), in column order.
        let mut pressed = DVector::zeros(heights.len());
        for &j in &self.indices {
            pressed.axpy(force[j], &cn.column(j), 1.0);
        }
        let opens = (0..heights.len())
            .filter(|&i| !self.active[i])
            .all(|i| pressed[i] - heights[i] + z >= -tolerance);
        opens.then_some((force, z))
    }
}

impl CoupledModel {
    /// Validate the scene and solve the normal problem on the phase grid.
    pub fn new(scene: &CoupledScene) -> Result<Self> {
        Self::new_from(scene, None)
    }

    /// [`Self::new`] whose normal solves (with `preload_balance = Instant`) start from the
    /// contact sets of `start` at the same grid phase, a model of a nearby scene (the same
    /// posts and step count, e.g. another amplitude profile of the energy-conserving wave):
    /// the same normal forces to the active-set tolerance, in one or two equality solves per
    /// phase instead of a cold active-set search. `None`: the cold start of [`Self::new`].
    pub fn new_from(scene: &CoupledScene, start: Option<&CoupledModel>) -> Result<Self> {
        let start = start.filter(|s| {
            s.normals.len() == scene.steps_per_period
                && s.normals.iter().all(|f| f.len() == scene.post_x_m.len())
        });
        // The compliances of a start with the same ones were checked when it was made.
        let checked = start.is_some_and(|s| {
            matches!(s.ct, Tangential::Dense(_))
                && s.scene.normal_compliance_m_per_n == scene.normal_compliance_m_per_n
                && s.scene.tangential_compliance_m_per_n == scene.tangential_compliance_m_per_n
        });
        if checked {
            scene.validate_settings()?;
        } else {
            scene.validate()?;
        }
        let started = Instant::now();
        let n = scene.post_x_m.len();
        let k_ref = n as f64 / scene.normal_compliance_m_per_n.diagonal().sum();
        let length_m = scene.wave.normal_amplitude_m;
        let force_n = k_ref * length_m;
        let cn = &scene.normal_compliance_m_per_n * k_ref;
        let ct = &scene.tangential_compliance_m_per_n * k_ref;
        let k = scene.wave.wavenumber_rad_per_m();
        let kx: Vec<f64> = scene.post_x_m.iter().map(|x| k * x).collect();
        let m = scene.steps_per_period;
        let preload = scene.preload_n * scene.strip_share / force_n;
        let sigma = scene.wave_direction.sign();
        let kx: Vec<f64> = kx.iter().map(|v| sigma * v).collect();
        // Local amplitude A_i/A₀ (1 unless the energy-conserving wave sets it); `1.0 *` keeps
        // the constant-amplitude wave bit-identical.
        let alpha: Vec<f64> = if scene.amplitude_scale.is_empty() {
            vec![1.0; n]
        } else {
            scene.amplitude_scale.clone()
        };
        let unit = start
            .map(|s| s.unit_wave.clone())
            .filter(|u| u.fits(scene.start_phase_rad, &kx, m))
            .unwrap_or_else(|| Arc::new(UnitWave::new(scene.start_phase_rad, &kx, m)));
        let heights =
            |j: usize| -> DVector<f64> { DVector::from_fn(n, |i, _| alpha[i] * unit.sin[j][i]) };
        let (normals, approach, factors) = match scene.preload_balance {
            PreloadBalance::Instant => instant_normals(scene, &cn, &heights, preload, start)?,
            PreloadBalance::PeriodMean => {
                let fine = |j: usize| -> DVector<f64> {
                    let theta = scene.start_phase_rad
                        + 2.0 * PI * j as f64 / (m * PERIOD_MEAN_REFINEMENT) as f64;
                    DVector::from_fn(n, |i, _| alpha[i] * (theta - kx[i]).sin())
                };
                let z = period_mean_approach(
                    &cn,
                    m * PERIOD_MEAN_REFINEMENT,
                    &fine,
                    preload,
                    scene.tolerance,
                )?;
                let normals = (0..m)
                    .map(|j| {
                        normals_at_approach(
                            &cn,
                            &heights(j),
                            z,
                            preload,
                            scene.tolerance,
                            j,
                            &mut ActiveSet::new(n),
                        )
                    })
                    .collect::<Result<Vec<_>>>()?;
                (normals, vec![z; m], Vec::new())
            }
        };
        let ct = Tangential::Dense(ct);
        let mut model = Self::assemble(scene, k_ref, normals, approach, ct, started, Some(unit));
        model.normal_factors = factors;
        Ok(model)
    }

    /// The model of a scene whose normal forces on the phase grid and tangential compliance
    /// come from elsewhere (the whole slider, [`crate::slider`]): `normals_n[j]` the post forces
    /// (N, scene order) and `approach_m[j]` the rigid approach (m) at grid phase j = 0..M
    /// (θ_j = start_phase + 2πj/M), `tangential` the tangential compliance C_t (m/N) as a
    /// product, `k_ref` the force scale's stiffness (N/m). The scene's dense compliances are not
    /// read (they may be empty); its settings are validated. `start`: a model of the same posts
    /// and phase grid (another amplitude profile's), whose table of the wave's unit shape is
    /// taken instead of evaluated again (the same values).
    pub fn from_normal_grid(
        scene: &CoupledScene,
        k_ref_n_per_m: f64,
        normals_n: Vec<Vec<f64>>,
        approach_m: Vec<f64>,
        tangential: Arc<dyn ComplianceProduct>,
        start: Option<&CoupledModel>,
    ) -> Result<Self> {
        scene.validate_settings()?;
        let started = Instant::now();
        let n = scene.post_x_m.len();
        if normals_n.len() != scene.steps_per_period || approach_m.len() != normals_n.len() {
            return Err(CoupledError::DimensionMismatch {
                what: "normal grid (phases)",
                expected: scene.steps_per_period,
                found: normals_n.len().min(approach_m.len()),
            });
        }
        if let Some(row) = normals_n.iter().find(|row| row.len() != n) {
            return Err(CoupledError::DimensionMismatch {
                what: "normal grid (posts)",
                expected: n,
                found: row.len(),
            });
        }
        if tangential.posts() != n {
            return Err(CoupledError::DimensionMismatch {
                what: "tangential compliance operator",
                expected: n,
                found: tangential.posts(),
            });
        }
        if !(k_ref_n_per_m > 0.0 && k_ref_n_per_m.is_finite()) {
            return Err(CoupledError::InvalidParameter {
                parameter: "k_ref_n_per_m",
                value: k_ref_n_per_m,
                requirement: "must be finite and > 0".into(),
            });
        }
        let force_n = k_ref_n_per_m * scene.wave.normal_amplitude_m;
        let normals = normals_n
            .into_iter()
            .map(|row| DVector::from_iterator(n, row.into_iter().map(|f| f / force_n)))
            .collect();
        let approach = approach_m
            .iter()
            .map(|z| z / scene.wave.normal_amplitude_m)
            .collect();
        let ct = Tangential::Operator {
            op: tangential,
            k_ref: k_ref_n_per_m,
        };
        Ok(Self::assemble(
            scene,
            k_ref_n_per_m,
            normals,
            approach,
            ct,
            started,
            start.map(|s| s.unit_wave.clone()),
        ))
    }

    /// The model on its normals; `unit`: another model's wave table, taken where it fits this
    /// scene's posts and phase grid (else the table is evaluated).
    fn assemble(
        scene: &CoupledScene,
        k_ref: f64,
        normals: Vec<DVector<f64>>,
        approach: Vec<f64>,
        ct: Tangential,
        started: Instant,
        unit: Option<Arc<UnitWave>>,
    ) -> Self {
        let n = scene.post_x_m.len();
        let length_m = scene.wave.normal_amplitude_m;
        let k = scene.wave.wavenumber_rad_per_m();
        let sigma = scene.wave_direction.sign();
        let kx: Vec<f64> = scene.post_x_m.iter().map(|x| sigma * (k * x)).collect();
        let alpha: Vec<f64> = if scene.amplitude_scale.is_empty() {
            vec![1.0; n]
        } else {
            scene.amplitude_scale.clone()
        };
        let unit = unit
            .filter(|u| u.fits(scene.start_phase_rad, &kx, normals.len()))
            .unwrap_or_else(|| Arc::new(UnitWave::new(scene.start_phase_rad, &kx, normals.len())));
        let wave_cos = unit
            .cos
            .iter()
            .map(|c| DVector::from_fn(kx.len(), |i, _| alpha[i] * c[i]))
            .collect();
        let extrapolate = (0..kx.len()).all(|i| normals.iter().any(|nj| nj[i] <= 0.0));
        let periodic_tolerance = match ct {
            Tangential::Dense(_) => PERIODIC_TOLERANCE,
            Tangential::Operator { .. } => PERIODIC_TOLERANCE.max(100.0 * scene.tolerance),
        };
        Self {
            extrapolate,
            scene: scene.clone(),
            ct,
            periodic_tolerance,
            kx,
            sigma,
            a_t: scene.wave.tangential_amplitude_m / length_m,
            doppler: k * length_m,
            wave_cos,
            normals,
            approach,
            force_n: k_ref * length_m,
            length_m,
            omega: scene.wave.angular_frequency_rad_per_s(),
            normal_wall_s: started.elapsed().as_secs_f64(),
            normal_factors: Vec::new(),
            lattice_rows: None,
            unit_wave: unit,
        }
    }

    /// Every post's normal force at grid phase `j` (N, the model's post order; a strip post's
    /// own force, not over the strip share).
    pub(crate) fn normal_forces_n(&self, j: usize) -> Vec<f64> {
        self.normals[j].iter().map(|f| f * self.force_n).collect()
    }

    /// Names the posts of errors as lattice posts (i, j), post i·`rows` + j.
    pub(crate) fn set_lattice_rows(&mut self, rows: usize) {
        self.lattice_rows = Some(rows.max(1));
    }

    /// Post `k` as an error names it.
    fn post_name(&self, k: usize) -> String {
        match self.lattice_rows {
            Some(rows) => format!("post ({}, {}) of the lattice", k / rows, k % rows),
            None => format!("post {k}"),
        }
    }

    /// The scene.
    pub fn scene(&self) -> &CoupledScene {
        &self.scene
    }

    /// Wall time of the normal solves on the phase grid (s).
    pub fn normal_wall_time_s(&self) -> f64 {
        self.normal_wall_s
    }

    /// Total normal force of the strip at grid phase j (N).
    pub fn strip_normal_force_n(&self, j: usize) -> f64 {
        self.normals[j % self.normals.len()].sum() * self.force_n
    }

    /// Rigid approach (tip reference height) at grid phase j (m).
    pub fn approach_m(&self, j: usize) -> f64 {
        self.approach[j % self.approach.len()] * self.length_m
    }

    /// Fewest grid steps in contact over the posts that touch at all (the resolution of the
    /// shortest contact arc), or `None` if no post touches.
    pub fn min_contact_steps(&self) -> Option<usize> {
        (0..self.kx.len())
            .map(|i| self.normals.iter().filter(|nj| nj[i] > 0.0).count())
            .filter(|&k| k > 0)
            .min()
    }

    /// Posts in contact at every grid phase (they never separate: at v = 0 their stuck state
    /// is not unique and the result depends on the start, T = 0).
    pub fn never_separating_posts(&self) -> usize {
        (0..self.kx.len())
            .filter(|&i| self.normals.iter().all(|nj| nj[i] > 0.0))
            .count()
    }

    /// Crest speed A_t ω (m/s).
    pub fn crest_speed_m_per_s(&self) -> f64 {
        self.scene.wave.crest_speed_m_per_s()
    }
}

/// The normal forces, approach and reusable factors of [`PreloadBalance::Instant`] at every
/// grid phase j (obstacle `heights(j)`): static-contact's active-set solver, or with `start`
/// (a model of a nearby scene) its contact set's factor first ([`NormalFactor`]), the
/// active-set solver from that set where the factor's solution is not the contact problem's.
#[allow(clippy::type_complexity)]
fn instant_normals(
    scene: &CoupledScene,
    cn: &DMatrix<f64>,
    heights: &dyn Fn(usize) -> DVector<f64>,
    preload: f64,
    start: Option<&CoupledModel>,
) -> Result<(Vec<DVector<f64>>, Vec<f64>, Vec<Option<Arc<NormalFactor>>>)> {
    let m = scene.steps_per_period;
    let solver = ActiveSetSolver::new(ActiveSetOptions {
        tolerance: scene.tolerance.max(1e-12),
        ..ActiveSetOptions::default()
    });
    let mut normals = Vec::with_capacity(m);
    let mut approach = Vec::with_capacity(m);
    let mut factors = Vec::with_capacity(if start.is_some() { m } else { 0 });
    for j in 0..m {
        let h = heights(j);
        if let Some(s) = start {
            let active = s.normals[j].iter().map(|f| *f > 0.0).collect::<Vec<_>>();
            let reused = s.normal_factors.get(j).and_then(|f| f.as_ref());
            let factor = reused
                .filter(|f| f.fits(&active))
                .cloned()
                .or_else(|| NormalFactor::new(cn, &active).map(Arc::new));
            let solved = factor
                .as_ref()
                .and_then(|f| f.solve(cn, &h, preload, scene.tolerance.max(1e-12)));
            if let Some((force, z)) = solved {
                normals.push(force);
                approach.push(z);
                factors.push(factor);
                continue;
            }
        }
        let warm: Option<Vec<bool>> =
            start.map(|s| s.normals[j].iter().map(|f| *f > 0.0).collect());
        let problem = ContactProblem {
            compliance_m_per_n: cn.clone(),
            obstacle_height_m: h.as_slice().to_vec(),
            preload_n: preload,
            length_scale_m: Some(1.0),
        };
        let solution = solver.solve_from(&problem, warm.as_deref())?;
        normals.push(DVector::from_vec(solution.force_n));
        approach.push(solution.reference_height_m);
        if start.is_some() {
            factors.push(None);
        }
    }
    Ok((normals, approach, factors))
}

/// Normal forces at a fixed approach z: N ≥ 0, z − w + Ĉ_n N ≥ 0, complementary.
fn normals_at_approach(
    cn: &DMatrix<f64>,
    heights: &DVector<f64>,
    z: f64,
    preload: f64,
    tolerance: f64,
    j: usize,
    active: &mut ActiveSet,
) -> Result<DVector<f64>> {
    let n = cn.nrows();
    let b = heights.add_scalar(-z);
    boxqp::solve(
        cn,
        &b,
        &vec![0.0; n],
        &vec![f64::INFINITY; n],
        active,
        b.amax().max(preload),
        tolerance,
    )
    .map(|s| s.x)
    .map_err(|(iterations, residual)| CoupledError::NotConverged {
        what: "normal contact at fixed approach",
        iterations,
        residual,
        tolerance,
        context: format!("at grid phase {j}, approach {z:.6e} A_n"),
    })
}

/// The constant approach z with the period mean Σ⟨N⟩ = P̂ over `m` grid phases, by bisection
/// (ΣN falls monotonically as z rises).
fn period_mean_approach(
    cn: &DMatrix<f64>,
    m: usize,
    heights: &dyn Fn(usize) -> DVector<f64>,
    preload: f64,
    tolerance: f64,
) -> Result<f64> {
    let n = cn.nrows();
    let all: Vec<DVector<f64>> = (0..m).map(heights).collect();
    let mut sets: Vec<ActiveSet> = vec![ActiveSet::new(n); m];
    let mut mean = |z: f64| -> Result<f64> {
        let mut total = 0.0;
        for j in 0..m {
            total +=
                normals_at_approach(cn, &all[j], z, preload, tolerance, j, &mut sets[j])?.sum();
        }
        Ok(total / m as f64)
    };
    let mut hi = 1.0;
    let mut lo = -1.0 - preload * cn.row_sum().max();
    while mean(lo)? < preload {
        lo -= 1.0 + lo.abs();
    }
    for _ in 0..APPROACH_BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi || hi - lo <= 1e-15 * (1.0 + mid.abs()) {
            break;
        }
        if mean(mid)? > preload {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// Sums over an interval of steps, solver units.
#[derive(Debug, Clone, Copy, Default)]
struct Integrals {
    time: f64,
    force_time: f64,
    stator_work: f64,
    power_flow: f64,
    output_work: f64,
    friction: f64,
    right_stator_work: f64,
    right_output_work: f64,
    right_friction: f64,
    numerical: f64,
    stored_change: f64,
    stick_time: f64,
    contact_time: f64,
}

impl std::ops::Sub for Integrals {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self {
            time: self.time - o.time,
            force_time: self.force_time - o.force_time,
            stator_work: self.stator_work - o.stator_work,
            power_flow: self.power_flow - o.power_flow,
            output_work: self.output_work - o.output_work,
            friction: self.friction - o.friction,
            right_stator_work: self.right_stator_work - o.right_stator_work,
            right_output_work: self.right_output_work - o.right_output_work,
            right_friction: self.right_friction - o.right_friction,
            numerical: self.numerical - o.numerical,
            stored_change: self.stored_change - o.stored_change,
            stick_time: self.stick_time - o.stick_time,
            contact_time: self.contact_time - o.contact_time,
        }
    }
}

/// State of the tips between steps.
#[derive(Debug, Clone)]
struct TipState {
    force: DVector<f64>,
    /// Ĉ_t · force, kept with it (one product per step instead of five).
    compliance_force: DVector<f64>,
    mode: Vec<PostMode>,
    active: ActiveSet,
    /// The last step's force change (the matrix-free solve's first guess is force + change:
    /// exact for tips whose force ramps linearly).
    change: DVector<f64>,
    /// Precision of the matrix-free solve's inexact steps this period ([`inexact_precision`]).
    inexact: Precision,
}

/// Tips' change over the last period, in periodicity tolerances, above which a period's
/// matrix-free step solves take single-precision inner products in their inexact steps
/// (`boxqp` mixed precision); a period after one whose tips changed by less than that is
/// double. Single products perturb each period's path by ≈ 1e-7, which flips the set of a post
/// whose multiplier lies within that of zero from one period to the next; at the studies'
/// former periodicity tolerance of 1e-4 (steps to 1e-6), single up to the tolerance itself
/// (0 tolerances) kept the modes from repeating (the paper's nominal slider stepped 68 periods
/// at 0.75 v₀ instead of 13), and 10 tolerances (1e-3) did not. At the studies' 1e-3 (steps to
/// 1e-5), 1 tolerance (the same 1e-3 of the friction scale) against 10: four samples of the
/// paper's slider with 5 nm scatter stepped the same 55 periods each in 3 % less time, with
/// the same results to 6 digits. Default 1.
pub const SINGLE_PRECISION_CHANGE: f64 = 1.0;
/// Smallest periodicity tolerance (of the friction scale; 100× the step tolerance) under which
/// the inexact steps may take single-precision products: the studies' 1e-3 (steps to 1e-5)
/// does; the dynamic stage's 1e-8 (steps to 1e-10) does not, since there the f32 error is
/// within three decades of what the steps resolve and a small scattered lattice's amplitude
/// fixed point then stalled at 3e-4. Default 1e-5.
pub const SINGLE_PRECISION_TOLERANCE: f64 = 1e-5;
/// Share of the amplitude tolerance below which a profile's residual must fall before the
/// profile stays (the energy-conserving wave's steady period); once it stays, it moves again
/// only when the residual reaches the tolerance. The residual of a staying profile drifts as
/// the tips relax to their periodic state; a profile that stayed at 0.94 of the tolerance
/// crossed it on the next period and moved again (the paper's slider with 5 nm scatter: 9 periods at a
/// speed 0.07 % from its start, 4 of them after the profile first stayed; 8 with this rule).
/// A point is still accepted at the first periodic period whose residual is below the
/// tolerance, staying or not. Default 0.5.
pub const PROFILE_SETTLE_SHARE: f64 = 0.5;

/// The precision of a period's inexact steps after a period whose tips changed by `change`
/// (of the friction scale) under the periodicity tolerance `tolerance`.
fn inexact_precision(change: f64, tolerance: f64) -> Precision {
    let far = change > SINGLE_PRECISION_CHANGE * tolerance;
    match far && tolerance >= SINGLE_PRECISION_TOLERANCE {
        true => Precision::Single,
        false => Precision::Double,
    }
}

/// The tips' state at the start of a steady period (forces, modes, the contact solver's warm
/// start): the start of a neighbouring speed's stepping ([`CoupledModel::at_speed_from`]).
#[derive(Debug, Clone)]
pub struct PeriodState(TipState);

/// Relative spread of the last two period-to-period contraction ratios below which the approach
/// to the periodic state counts as geometric (one dominant mode). Default 0.05.
pub const GEOMETRIC_RATIO_SPREAD: f64 = 0.05;
/// Largest contraction ratio per period that is extrapolated (slower approaches are stepped).
/// Default 0.9.
pub const MAX_EXTRAPOLATED_RATIO: f64 = 0.9;
/// Smallest cosine between the last two period-to-period changes for a geometric approach.
/// Default 0.999.
pub const MIN_GEOMETRIC_COSINE: f64 = 0.999;

/// The period-start forces' approach to the periodic state, watched for a geometric phase.
///
/// Once the contact modes repeat, the period map is affine (every step's active sets repeat)
/// and its differences d_k = Tᵏ − Tᵏ⁻¹ shrink by the dominant eigenvalue ρ of its linear part:
/// d_k ≈ ρ d_{k−1}. When three successive differences agree with that (ratios within
/// [`GEOMETRIC_RATIO_SPREAD`], directions within [`MIN_GEOMETRIC_COSINE`]), the remaining
/// geometric tail Σ_{i≥1} ρⁱ d_k = ρ/(1−ρ) d_k is added at once (Aitken's Δ² along the
/// dominant mode: Brezinski & Redivo Zaglia, Extrapolation Methods, 1991, §2.1). The
/// periodicity rule then judges stepped periods from the extrapolated start, as before.
#[derive(Debug, Default)]
struct Approach {
    /// The last differences with their norms, while the modes repeat.
    differences: Vec<(DVector<f64>, f64)>,
}

impl Approach {
    /// Record the difference of a stepped period (`same_modes`: its start and end modes agree);
    /// the jump to add to the forces when the approach is geometric.
    fn record(&mut self, difference: DVector<f64>, same_modes: bool) -> Option<DVector<f64>> {
        if !same_modes {
            self.differences.clear();
            return None;
        }
        let norm = difference.norm();
        self.differences.push((difference, norm));
        if self.differences.len() > 3 {
            self.differences.remove(0);
        }
        let [(_, n0), (d1, n1), (d2, n2)] = self.differences.as_slice() else {
            return None;
        };
        if !(*n0 > 0.0 && *n1 > 0.0 && *n2 > 0.0) {
            return None;
        }
        let (early, late) = (n1 / n0, n2 / n1);
        let cosine = d1.dot(d2) / (n1 * n2);
        if (late - early).abs() > GEOMETRIC_RATIO_SPREAD * late
            || late >= MAX_EXTRAPOLATED_RATIO
            || cosine < MIN_GEOMETRIC_COSINE
        {
            return None;
        }
        let jump = d2 * (late / (1.0 - late));
        self.differences.clear();
        Some(jump)
    }
}

/// The result of [`CoupledModel::steady_profiled`]: the model of the settled profile, its
/// steady point, each post's time-mean stator power over the steady period (W, whole slider)
/// and the tips' state at that period's end (the start of a neighbouring speed).
pub(crate) struct ProfiledSteady {
    pub(crate) model: CoupledModel,
    pub(crate) point: CoupledPoint,
    pub(crate) post_power_w: Vec<f64>,
    pub(crate) end_state: PeriodState,
    /// The joint acceleration's differences as the profile settled (`None` if it never
    /// moved): the next speed's start ([`CoupledModel::steady_profiled`]'s `carried`).
    pub(crate) joint: Option<Anderson>,
}

/// The amplitude profile's side of [`CoupledModel::steady_profiled`] (the energy-conserving
/// wave, [`crate::attenuation`]): the fixed point's residual and update target from a period's
/// per-post powers, and the model of a new profile.
pub(crate) trait ProfileMap {
    /// The fixed point's residual max|g(α) − α| of the period's per-post stator powers
    /// `power_w` (W, whole slider) at the profile `alpha`, and the profile the update aims at
    /// (a map with the same fixed point, e.g. the marching update).
    fn target(&mut self, alpha: &[f64], power_w: &[f64]) -> Result<(f64, Vec<f64>)>;
    /// The residual below which the profile counts as settled.
    fn tolerance(&self) -> f64;
    /// Anderson's mixing β of the joint map, in (0, 1].
    fn relaxation(&self) -> f64;
    /// The model of the profile `alpha`, made from `from` (a model of a nearby profile).
    fn model(&mut self, alpha: &[f64], from: &CoupledModel) -> Result<CoupledModel>;
}

/// What one step imposes: the normal forces at its end, the tips' tangential motion Δu, the
/// slider's scaled velocity v̂ and the step h, and the slip increment that counts as slip.
#[derive(Clone, Copy)]
struct StepMotion<'a> {
    normal: &'a DVector<f64>,
    du: &'a DVector<f64>,
    v: f64,
    h: f64,
    slip_tolerance: f64,
}

/// Solver statistics of a run.
#[derive(Debug, Clone, Copy, Default)]
struct SolverStats {
    max_residual: f64,
    iterations: usize,
    fallback_steps: usize,
}

impl CoupledModel {
    /// Scaled x-velocity of the slider moving at `speed_m_per_s` along the drive direction −σx.
    fn scaled_velocity(&self, speed_m_per_s: f64) -> f64 {
        -self.sigma * speed_m_per_s / (self.length_m * self.omega)
    }

    /// Drive direction along x: −σ (−1 for the +x wave).
    pub fn drive_direction_x(&self) -> f64 {
        -self.sigma
    }

    /// One step from grid phase j to j+1 (with `per_post`: each post's sums added to it).
    #[allow(clippy::too_many_arguments)]
    fn step(
        &self,
        j: usize,
        v: f64,
        s: f64,
        h: f64,
        state: &mut TipState,
        ints: &mut Integrals,
        stats: &mut SolverStats,
        per_post: Option<&mut PostSums>,
    ) -> Result<()> {
        let m = self.normals.len();
        let n = self.kx.len();
        let normal = &self.normals[(j + 1) % m];
        let (cos0, cos1) = (&self.wave_cos[j], &self.wave_cos[j + 1]);
        let du = DVector::from_fn(n, |i, _| self.sigma * self.a_t * (cos1[i] - cos0[i]) / s);
        let b = &state.compliance_force + &du - DVector::from_element(n, v * h);
        let slip_tolerance = 1e-9 * (du.amax() + v.abs() * h).max(1e-300);
        let solution = self.solve_step(j, v, normal, &b, slip_tolerance, state, stats)?;
        let step = StepMotion {
            normal,
            du: &du,
            v,
            h,
            slip_tolerance,
        };
        self.book_step(&step, &solution, state, ints, per_post);
        self.update_modes(&step, &solution.lambda, state, ints);
        let force = solution.x;
        if matches!(self.ct, Tangential::Operator { .. }) {
            state.change = &force - &state.force;
        }
        state.force = force;
        state.compliance_force = solution.ax;
        Ok(())
    }

    /// The step's box QP with the bounds μ_i N_i: μ_k for a post that slipped in the previous
    /// step, else μ_s; a post that slips with μ_s drops to μ_k and the step is solved again.
    #[allow(clippy::too_many_arguments)]
    fn solve_step(
        &self,
        j: usize,
        v: f64,
        normal: &DVector<f64>,
        b: &DVector<f64>,
        slip_tolerance: f64,
        state: &mut TipState,
        stats: &mut SolverStats,
    ) -> Result<boxqp::BoxSolution> {
        let n = self.kx.len();
        let mut mu: Vec<f64> = state
            .mode
            .iter()
            .map(|mode| match mode {
                PostMode::Slip => self.scene.mu_kinetic,
                _ => self.scene.mu_static,
            })
            .collect();
        let tolerance = self.scene.tolerance;
        loop {
            let hi: Vec<f64> = (0..n).map(|i| mu[i] * normal[i].max(0.0)).collect();
            let lo: Vec<f64> = hi.iter().map(|x| -x).collect();
            let scale = hi.iter().fold(b.amax(), |a, &x| a.max(x));
            let solved = match &self.ct {
                Tangential::Dense(ct) => {
                    boxqp::solve(ct, b, &lo, &hi, &mut state.active, scale, tolerance).map_err(
                        |(iterations, residual)| boxqp::Unsolved {
                            iterations,
                            residual,
                            worst: None,
                        },
                    )
                }
                op => boxqp::solve_operator(
                    op,
                    b,
                    &lo,
                    &hi,
                    &mut state.active,
                    &(&state.force + &state.change),
                    scale,
                    tolerance,
                    state.inexact,
                ),
            };
            let solution = solved.map_err(|u| CoupledError::NotConverged {
                what: "frictional contact step",
                iterations: u.iterations,
                residual: u.residual,
                tolerance,
                context: format!(
                    "at speed {:.6e} m/s, grid step {j}{}",
                    -v * self.length_m * self.omega,
                    u.worst
                        .map_or_else(String::new, |k| format!(", {}", self.post_name(k)))
                ),
            })?;
            stats.max_residual = stats.max_residual.max(solution.residual);
            stats.iterations += solution.iterations;
            stats.fallback_steps += usize::from(solution.fallback);
            let mut dropped = false;
            for i in 0..n {
                if normal[i] > 0.0
                    && mu[i] != self.scene.mu_kinetic
                    && solution.lambda[i].abs() > slip_tolerance
                {
                    mu[i] = self.scene.mu_kinetic;
                    dropped = true;
                }
            }
            if !dropped {
                return Ok(solution);
            }
        }
    }

    /// The step's work terms (midpoint force: the discrete gradient of the stored energy) into
    /// `ints`, and each post's into `per_post`.
    fn book_step(
        &self,
        step: &StepMotion<'_>,
        solution: &boxqp::BoxSolution,
        state: &TipState,
        ints: &mut Integrals,
        per_post: Option<&mut PostSums>,
    ) {
        let StepMotion {
            normal,
            du,
            v,
            h,
            slip_tolerance,
        } = *step;
        let force = &solution.x;
        let slip = &solution.lambda;
        let dforce = force - &state.force;
        let compliance_force = &solution.ax;
        let stored_old = 0.5 * state.force.dot(&state.compliance_force);
        let stored_new = 0.5 * force.dot(compliance_force);
        // Discrete gradient of the stored energy ½TᵀĈ_tT (Gonzalez 1996): the midpoint force.
        let mid = 0.5 * (force + &state.force);
        ints.time += h;
        ints.force_time += force.sum() * h;
        ints.stator_work += mid.dot(du);
        if let Some(sums) = per_post {
            sums.stator_work += mid.component_mul(du);
            sums.friction_work += mid.component_mul(slip);
            sums.normal_impulse += normal * h;
            for i in 0..normal.len() {
                if normal[i] > 0.0 {
                    sums.contact_time[i] += h;
                    if slip[i].abs() > slip_tolerance {
                        sums.slip_time[i] += h;
                    }
                }
            }
        }
        ints.power_flow += mid.component_mul(du).abs().sum();
        ints.output_work += mid.sum() * v * h;
        ints.friction += mid.dot(slip);
        ints.right_stator_work += force.dot(du);
        ints.right_output_work += force.sum() * v * h;
        ints.right_friction += force.dot(slip);
        ints.numerical += 0.5 * dforce.dot(&(compliance_force - &state.compliance_force));
        ints.stored_change += stored_new - stored_old;
    }

    /// Each post's contact mode after the step (separated, stuck or slipping by its slip
    /// increment), with the contact and stick times.
    fn update_modes(
        &self,
        step: &StepMotion<'_>,
        slip: &DVector<f64>,
        state: &mut TipState,
        ints: &mut Integrals,
    ) {
        let (normal, h) = (step.normal, step.h);
        for i in 0..normal.len() {
            state.mode[i] = if normal[i] <= 0.0 {
                PostMode::Separated
            } else if slip[i].abs() > step.slip_tolerance {
                PostMode::Slip
            } else {
                PostMode::Stick
            };
            if normal[i] > 0.0 {
                ints.contact_time += h;
                if state.mode[i] == PostMode::Stick {
                    ints.stick_time += h;
                }
            }
        }
    }

    /// Steady state at an imposed speed along the drive direction (m/s); 0 is the v → 0⁺ limit
    /// for separating posts.
    pub fn at_speed(&self, speed_m_per_s: f64) -> Result<CoupledPoint> {
        Ok(self.steady(speed_m_per_s, None)?.0)
    }

    /// [`Self::at_speed`] with the stepping started from `start` (the periodic state of a
    /// neighbouring speed; `None`: zero tangential forces, every post separated), and the
    /// state at the start of the steady period reached. The periodicity rule is the same, so
    /// the point agrees with a cold start's to the rule's tolerance ([`PERIODIC_TOLERANCE`] of
    /// the friction scale) wherever the steady cycle is unique; fewer periods are stepped.
    pub fn at_speed_from(
        &self,
        speed_m_per_s: f64,
        start: Option<&PeriodState>,
    ) -> Result<(CoupledPoint, PeriodState)> {
        let (point, state, ..) = self.steady(speed_m_per_s, start)?;
        Ok((point, PeriodState(state)))
    }

    /// The steady point at `speed_m_per_s` (started from `start`, as [`Self::at_speed_from`])
    /// and the time-mean stator power each post draws over one further steady period (W, whole
    /// slider: the strip post's power over the strip share, so that the posts' sum is the
    /// slider's stator power): P_i = ⟨T̄_i·Δu_i⟩ with the midpoint force, the same bookkeeping
    /// as `stator_power_w`. The further period repeats the steady one to the periodicity
    /// tolerance, so Σ P_i equals `stator_power_w` to ≈ 1e-11 of the power flow.
    pub fn post_stator_power_from(
        &self,
        speed_m_per_s: f64,
        start: Option<&PeriodState>,
    ) -> Result<(CoupledPoint, Vec<f64>, PeriodState)> {
        let (point, means, period_start) = self.post_means_from(speed_m_per_s, start)?;
        Ok((point, means.stator_power_w, period_start))
    }

    /// The steady point at `speed_m_per_s` (started from `start`, as [`Self::at_speed_from`])
    /// and every post's time means over one further steady period ([`PostMeans`]: normal force,
    /// slip and contact fractions, friction and stator power, whole slider: a strip post's
    /// powers and forces over the strip share), with the state at that period's start. The
    /// powers use the midpoint force as the point's (Σ friction_power_w = friction_dissipation_w
    /// and Σ stator_power_w = stator_power_w to the periodicity tolerance).
    pub fn post_means_from(
        &self,
        speed_m_per_s: f64,
        start: Option<&PeriodState>,
    ) -> Result<(CoupledPoint, PostMeans, PeriodState)> {
        let (point, means, _, period_start) =
            self.post_means_and_histories_from(speed_m_per_s, start, &[])?;
        Ok((point, means, period_start))
    }

    /// [`Self::post_means_from`] with the histories of the posts `posts` over the same further
    /// period ([`Self::post_histories_of`]'s samples): one steady solve for both.
    pub fn post_means_and_histories_from(
        &self,
        speed_m_per_s: f64,
        start: Option<&PeriodState>,
        posts: &[usize],
    ) -> Result<(CoupledPoint, PostMeans, PostHistories, PeriodState)> {
        self.check_posts(posts)?;
        let (point, mut state, v, s, h) = self.steady(speed_m_per_s, start)?;
        let period_start = PeriodState(state.clone());
        let m = self.normals.len();
        let mut ints = Integrals::default();
        let mut stats = SolverStats::default();
        let mut sums = PostSums::new(self.kx.len());
        let mut histories = PostHistories {
            speed_m_per_s,
            ..PostHistories::default()
        };
        for j in 0..m {
            self.step(
                j,
                v,
                s,
                h,
                &mut state,
                &mut ints,
                &mut stats,
                Some(&mut sums),
            )?;
            if !posts.is_empty() {
                self.record_sample(&mut histories, j, h, &state, posts);
            }
        }
        count_period();
        let means = self.post_means(speed_m_per_s, &ints, &sums);
        Ok((point, means, histories, period_start))
    }

    /// The time means of one period's per-post sums, whole slider (SI).
    fn post_means(&self, speed_m_per_s: f64, ints: &Integrals, sums: &PostSums) -> PostMeans {
        let share = self.scene.strip_share;
        let power = self.force_n * self.length_m * self.omega / ints.time / share;
        PostMeans {
            speed_m_per_s,
            mean_normal_force_n: sums
                .normal_impulse
                .iter()
                .map(|x| x / ints.time * self.force_n / share)
                .collect(),
            slip_fraction: sums
                .slip_time
                .iter()
                .zip(&sums.contact_time)
                .map(|(s, c)| if *c > 0.0 { s / c } else { 0.0 })
                .collect(),
            contact_fraction: sums.contact_time.iter().map(|c| c / ints.time).collect(),
            friction_power_w: sums.friction_work.iter().map(|w| w * power).collect(),
            stator_power_w: sums.stator_work.iter().map(|w| w * power).collect(),
        }
    }

    /// Every post's normal and tangential force and contact mode over one steady period at
    /// `speed_m_per_s` (one sample per step, at the step's end), with the steady point itself
    /// (the [`Self::at_speed`] result, which the histories' solve has already found).
    pub fn post_histories(&self, speed_m_per_s: f64) -> Result<(CoupledPoint, PostHistories)> {
        let all: Vec<usize> = (0..self.kx.len()).collect();
        self.post_histories_of(speed_m_per_s, &all)
    }

    /// [`Self::post_histories`] of the posts `posts` only (scene indices, in that order in
    /// every sample): the whole slider's 10⁴ posts × M samples would be 10⁶ values per force.
    pub fn post_histories_of(
        &self,
        speed_m_per_s: f64,
        posts: &[usize],
    ) -> Result<(CoupledPoint, PostHistories)> {
        self.check_posts(posts)?;
        let (point, mut state, v, s, h) = self.steady(speed_m_per_s, None)?;
        let m = self.normals.len();
        let mut ints = Integrals::default();
        let mut stats = SolverStats::default();
        let mut out = PostHistories {
            speed_m_per_s,
            ..PostHistories::default()
        };
        for j in 0..m {
            self.step(j, v, s, h, &mut state, &mut ints, &mut stats, None)?;
            self.record_sample(&mut out, j, h, &state, posts);
        }
        count_period();
        Ok((point, out))
    }

    /// Post indices must name posts of the scene.
    fn check_posts(&self, posts: &[usize]) -> Result<()> {
        match posts.iter().find(|&&p| p >= self.kx.len()) {
            Some(&p) => Err(CoupledError::InvalidParameter {
                parameter: "posts",
                value: p as f64,
                requirement: format!("post indices below {}", self.kx.len()),
            }),
            None => Ok(()),
        }
    }

    /// The sample at the end of step j (to grid phase j + 1) of the posts `posts`.
    fn record_sample(
        &self,
        out: &mut PostHistories,
        j: usize,
        h: f64,
        state: &TipState,
        posts: &[usize],
    ) {
        let m = self.normals.len();
        let time_unit = 1.0 / self.omega;
        out.time_s.push((j + 1) as f64 * h * time_unit);
        let normal = &self.normals[(j + 1) % m];
        out.normal_force_n
            .push(posts.iter().map(|&i| normal[i] * self.force_n).collect());
        out.tangential_force_n.push(
            posts
                .iter()
                .map(|&i| -self.sigma * state.force[i] * self.force_n)
                .collect(),
        );
        out.mode
            .push(posts.iter().map(|&i| state.mode[i]).collect());
    }

    /// The steady state at a speed: the period average, the state at a period start, the
    /// scaled velocity, phase rate and step.
    fn steady(
        &self,
        speed_m_per_s: f64,
        start: Option<&PeriodState>,
    ) -> Result<(CoupledPoint, TipState, f64, f64, f64)> {
        if !speed_m_per_s.is_finite() {
            return Err(CoupledError::InvalidParameter {
                parameter: "speed_m_per_s",
                value: speed_m_per_s,
                requirement: "must be finite".into(),
            });
        }
        let m = self.normals.len();
        let v = self.scaled_velocity(speed_m_per_s);
        let s = 1.0 - self.doppler * self.sigma * v;
        let h = 2.0 * PI / (m as f64 * s);
        let mut state = start.map_or_else(|| self.rest_state(), |p| p.0.clone());
        let friction_scale = self.friction_scale();
        let mut ints = Integrals::default();
        let mut stats = SolverStats::default();
        let mut marks = vec![ints];
        let mut previous = (state.force.clone(), state.mode.clone());
        let mut converged = false;
        let mut periods = 0;
        let mut approach = Approach::default();
        while periods < MAX_PERIODS {
            for j in 0..m {
                self.step(j, v, s, h, &mut state, &mut ints, &mut stats, None)?;
            }
            periods += 1;
            count_period();
            marks.push(ints);
            let difference = &state.force - &previous.0;
            let change = difference.amax();
            state.inexact = inexact_precision(change / friction_scale, self.periodic_tolerance);
            let same_modes = state.mode == previous.1;
            if periods >= 2 && change <= self.periodic_tolerance * friction_scale && same_modes {
                converged = true;
                break;
            }
            if self.extrapolate
                && let Some(jump) = approach.record(difference, same_modes)
            {
                state.force += jump;
                state.compliance_force = self.ct.times(&state.force);
            }
            previous = (state.force.clone(), state.mode.clone());
        }
        let window = if converged {
            marks[periods] - marks[periods - 1]
        } else {
            marks[periods] - marks[periods / 2]
        };
        let point = self.point(speed_m_per_s, v, &window, converged, periods, stats);
        Ok((point, state, v, s, h))
    }

    /// The steady point at `speed_m_per_s` of a model whose amplitude profile α is itself
    /// unknown (the energy-conserving wave, [`crate::attenuation`]), the tips and the profile
    /// solved together. One period maps z = (T, α), the tips' forces at a period start (of the
    /// friction scale) and the profile, to (T after one period on the model of α, the profile
    /// `map` aims at from that period's powers); Anderson acceleration of this joint map
    /// ([`Anderson`]) gives the next period's start and profile. The profile thus moves every
    /// period, its secant information carrying how the tips' relaxation and the profile act on
    /// each other, instead of waiting for the tips to relax before each profile update. Once
    /// the profile is settled (its residual below the map's tolerance) it stays, and the
    /// acceleration runs on the tips alone until the period is periodic; it resumes on both if
    /// the residual grows past the tolerance again. The point is the first period that is
    /// periodic by the rule of [`Self::at_speed`] (two periods stepped, the same modes, forces
    /// within the tolerance) at a settled profile; its powers are that period's. `carried`: the
    /// joint differences a neighbouring speed's solve returned ([`ProfiledSteady::joint`]), the
    /// acceleration's first secant information.
    pub(crate) fn steady_profiled(
        self,
        speed_m_per_s: f64,
        start: Option<&PeriodState>,
        max_periods: usize,
        map: &mut dyn ProfileMap,
        carried: Option<Anderson>,
    ) -> Result<ProfiledSteady> {
        let mut model = self;
        let m = model.normals.len();
        let v = model.scaled_velocity(speed_m_per_s);
        let s = 1.0 - model.doppler * model.sigma * v;
        let h = 2.0 * PI / (m as f64 * s);
        let mut state = start.map_or_else(|| model.rest_state(), |p| p.0.clone());
        let mut stats = SolverStats::default();
        // The tips' part of z in units of the first model's friction scale (fixed over the point).
        let scale = model.friction_scale();
        let mut joint = carried;
        let mut anderson = joint
            .clone()
            .unwrap_or_else(|| Anderson::new(map.relaxation()));
        let mut was_settled = false;
        for period in 1..=max_periods {
            let (start_force, start_modes) = (state.force.clone(), state.mode.clone());
            let (ints, power_w) = model.profiled_period(v, s, h, &mut state, &mut stats)?;
            let alpha = model.profile();
            let (residual, target) = map.target(&alpha, &power_w)?;
            let within = residual < map.tolerance();
            let settled = match was_settled {
                true => within,
                false => residual < PROFILE_SETTLE_SHARE * map.tolerance(),
            };
            let (change, friction) = ((&state.force - &start_force).amax(), model.friction_scale());
            state.inexact = inexact_precision(change / friction, model.periodic_tolerance);
            let periodic = period >= 2
                && change <= model.periodic_tolerance * friction
                && state.mode == start_modes;
            if within && periodic {
                let point = model.point(speed_m_per_s, v, &ints, true, period, stats);
                return Ok(ProfiledSteady {
                    model,
                    point,
                    post_power_w: power_w,
                    end_state: PeriodState(state),
                    joint,
                });
            }
            if settled != was_settled {
                if settled {
                    joint = Some(anderson.carried());
                }
                anderson = Anderson::new(map.relaxation());
                was_settled = settled;
            }
            let n = start_force.len();
            let mut z: Vec<f64> = start_force.iter().map(|t| t / scale).collect();
            let mut residual_z: Vec<f64> = (0..n)
                .map(|i| (state.force[i] - start_force[i]) / scale)
                .collect();
            if !settled {
                z.extend_from_slice(&alpha);
                residual_z.extend(target.iter().zip(&alpha).map(|(t, a)| t - a));
            }
            let next = anderson.next(&z, &residual_z);
            if !settled {
                let profile: Vec<f64> = next[n..].iter().map(|a| a.max(0.0)).collect();
                model = map.model(&profile, &model)?;
            }
            state.force = DVector::from_iterator(n, next[..n].iter().map(|t| t * scale));
            state.compliance_force = model.ct.times(&state.force);
        }
        Err(CoupledError::NotConverged {
            what: "steady period with the energy-conserving wave",
            iterations: max_periods,
            residual: f64::NAN,
            tolerance: model.periodic_tolerance,
            context: format!("at speed {speed_m_per_s:.6e} m/s"),
        })
    }

    /// One period of [`Self::steady_profiled`] from `state`: its sums and each post's time-mean
    /// stator power (W, whole slider, as [`Self::post_stator_power_from`]).
    fn profiled_period(
        &self,
        v: f64,
        s: f64,
        h: f64,
        state: &mut TipState,
        stats: &mut SolverStats,
    ) -> Result<(Integrals, Vec<f64>)> {
        let mut ints = Integrals::default();
        let mut sums = PostSums::new(self.kx.len());
        for j in 0..self.normals.len() {
            self.step(j, v, s, h, state, &mut ints, stats, Some(&mut sums))?;
        }
        count_period();
        let power = self.force_n * self.length_m * self.omega / ints.time;
        let power_w = sums
            .stator_work
            .iter()
            .map(|w| w * power / self.scene.strip_share)
            .collect();
        Ok((ints, power_w))
    }

    /// The model's amplitude profile A_i/A₀ (ones for the constant-amplitude wave).
    fn profile(&self) -> Vec<f64> {
        if self.scene.amplitude_scale.is_empty() {
            vec![1.0; self.kx.len()]
        } else {
            self.scene.amplitude_scale.clone()
        }
    }

    /// Every post's forces and modes over one period at `speed_m_per_s` from `start`, the
    /// state at the start of a steady period of this model (e.g. [`ProfiledSteady::end_state`]):
    /// the histories of that steady period, without stepping to periodicity again.
    pub(crate) fn histories_from_periodic(
        &self,
        speed_m_per_s: f64,
        start: &PeriodState,
    ) -> Result<PostHistories> {
        let m = self.normals.len();
        let v = self.scaled_velocity(speed_m_per_s);
        let s = 1.0 - self.doppler * self.sigma * v;
        let h = 2.0 * PI / (m as f64 * s);
        let posts: Vec<usize> = (0..self.kx.len()).collect();
        let mut state = start.0.clone();
        let (mut ints, mut stats) = (Integrals::default(), SolverStats::default());
        let mut out = PostHistories {
            speed_m_per_s,
            ..PostHistories::default()
        };
        for j in 0..m {
            self.step(j, v, s, h, &mut state, &mut ints, &mut stats, None)?;
            self.record_sample(&mut out, j, h, &state, &posts);
        }
        count_period();
        Ok(out)
    }

    /// Zero tangential forces, every post separated: the start of a cold stepping.
    fn rest_state(&self) -> TipState {
        let n = self.kx.len();
        TipState {
            force: DVector::zeros(n),
            compliance_force: DVector::zeros(n),
            mode: vec![PostMode::Separated; n],
            active: ActiveSet::new(n),
            change: DVector::zeros(n),
            inexact: inexact_precision(f64::INFINITY, self.periodic_tolerance),
        }
    }

    /// μ_s times the largest normal force on the grid (solver units), floored above zero: the
    /// scale of the periodicity rule.
    fn friction_scale(&self) -> f64 {
        let largest = self.normals.iter().map(|x| x.amax()).fold(0.0, f64::max);
        (self.scene.mu_static * largest).max(1e-300)
    }

    fn point(
        &self,
        speed_m_per_s: f64,
        v: f64,
        i: &Integrals,
        converged: bool,
        periods: usize,
        stats: SolverStats,
    ) -> CoupledPoint {
        let share = self.scene.strip_share;
        let power = self.force_n * self.length_m * self.omega / i.time / share;
        let stator = i.stator_work * power;
        let output = i.output_work * power;
        let flow = i
            .power_flow
            .max(i.stator_work.abs())
            .max(i.friction.abs())
            .max(1e-300);
        let balance = i.stator_work - i.output_work - i.friction - i.stored_change;
        let right = i.right_stator_work - i.right_output_work - i.right_friction - i.stored_change;
        let _ = v;
        CoupledPoint {
            speed_m_per_s,
            thrust_n: -self.sigma * i.force_time / i.time * self.force_n / share,
            output_power_w: output,
            stator_power_w: stator,
            friction_dissipation_w: i.friction * power,
            numerical_dissipation_w: i.numerical * power,
            efficiency: if stator > 0.0 && output > 0.0 {
                output / stator
            } else {
                0.0
            },
            stick_fraction: if i.contact_time > 0.0 {
                i.stick_time / i.contact_time
            } else {
                0.0
            },
            contact_fraction: i.contact_time / (i.time * self.kx.len() as f64),
            energy_balance_residual: balance / flow,
            right_endpoint_balance_residual: right / flow,
            energy_identity_residual: (right - i.numerical) / flow,
            converged,
            periods,
            max_solver_residual: stats.max_residual,
            solver_iterations: stats.iterations,
            fallback_steps: stats.fallback_steps,
        }
    }

    /// Stall thrust F(0⁺) (N).
    pub fn stall_thrust_n(&self) -> Result<f64> {
        Ok(self.at_speed(0.0)?.thrust_n)
    }

    /// No-load speed F(v₀) = 0 (m/s), Illinois regula falsi on [0, crest]; 0 if F(0⁺) ≤ 0.
    pub fn no_load_speed_m_per_s(&self, stall_n: f64) -> Result<f64> {
        Ok(self.no_load_search(stall_n)?.0)
    }

    /// [`Self::no_load_speed_m_per_s`] with the periodic state of its last evaluation (`None`
    /// if there was none). Each evaluation starts from the previous one's periodic state.
    pub fn no_load_search(&self, stall_n: f64) -> Result<(f64, Option<PeriodState>)> {
        let mut warm: Option<PeriodState> = None;
        let mut thrust = |speed: f64| -> Result<f64> {
            let (point, state) = self.at_speed_from(speed, warm.as_ref())?;
            warm = Some(state);
            Ok(point.thrust_n)
        };
        let speed = self.regula_falsi(stall_n, &mut thrust)?;
        Ok((speed, warm))
    }

    /// The no-load speed from a predicted one, `guess_m_per_s` (e.g. the lumped model's), to
    /// `tolerance` of the crest speed, each evaluation started from the previous one's periodic
    /// state (the first from `start`): a secant through the guess and a probe
    /// [`NO_LOAD_PROBE`] beyond it towards the root, kept inside the bracket once one is found
    /// (regula falsi where the secant leaves it). Near the root the thrust is smooth, so it
    /// converges superlinearly from a guess within a few per cent: 4–6 evaluations of
    /// neighbouring speeds instead of [`Self::no_load_search`]'s ≈ 10 from the crest speed.
    /// Returns the speed and the last evaluation's periodic state; 0 if F(0⁺) ≤ 0.
    pub fn no_load_search_near(
        &self,
        stall_n: f64,
        guess_m_per_s: f64,
        tolerance: f64,
        start: Option<&PeriodState>,
    ) -> Result<(f64, Option<PeriodState>)> {
        let mut warm: Option<PeriodState> = start.cloned();
        let mut thrust = |speed: f64| -> Result<f64> {
            let (point, state) = self.at_speed_from(speed, warm.as_ref())?;
            warm = Some(state);
            Ok(point.thrust_n)
        };
        let crest = self.crest_speed_m_per_s();
        let speed = secant_root(stall_n, guess_m_per_s, crest, tolerance, &mut thrust)?;
        Ok((speed, warm))
    }

    /// The no-load speed by Illinois regula falsi with `thrust(v)` (N).
    pub(crate) fn regula_falsi(
        &self,
        stall_n: f64,
        thrust: &mut dyn FnMut(f64) -> Result<f64>,
    ) -> Result<f64> {
        if stall_n <= 0.0 {
            return Ok(0.0);
        }
        let crest = self.crest_speed_m_per_s();
        let (mut a, mut fa) = (0.0, stall_n);
        let mut b = crest;
        let mut fb = thrust(b)?;
        let mut expansions = 0;
        while fb > 0.0 {
            if expansions == 6 {
                return Err(CoupledError::NotConverged {
                    what: "bracket of the no-load speed",
                    iterations: expansions,
                    residual: fb,
                    tolerance: 0.0,
                    context: "thrust still positive at 11× the crest speed".into(),
                });
            }
            a = b;
            fa = fb;
            b *= 1.5;
            fb = thrust(b)?;
            expansions += 1;
        }
        let mut side = 0;
        for _ in 0..200 {
            let c = (a * fb - b * fa) / (fb - fa);
            if (b - a).abs() <= SPEED_TOLERANCE * crest {
                return Ok(c);
            }
            let fc = thrust(c)?;
            if fc == 0.0 {
                return Ok(c);
            }
            if (fc > 0.0) == (fa > 0.0) {
                a = c;
                fa = fc;
                if side == -1 {
                    fb *= 0.5;
                }
                side = -1;
            } else {
                b = c;
                fb = fc;
                if side == 1 {
                    fa *= 0.5;
                }
                side = 1;
            }
            if (b - a).abs() <= SPEED_TOLERANCE * crest {
                return Ok(0.5 * (a + b));
            }
        }
        Ok(0.5 * (a + b))
    }
}

/// Relative distance of the second evaluation of [`CoupledModel::no_load_search_near`] from
/// the guess, towards the root. Default 0.005.
pub const NO_LOAD_PROBE: f64 = 0.005;
/// Evaluations of [`secant_root`] at most. Default 40.
const SECANT_EVALUATIONS: usize = 40;

/// The root of a falling `thrust(v)` (N) with F(0) = `stall_n` > 0, from `guess` (m/s):
/// secant steps, regula falsi inside the bracket when a secant step leaves it, until a step is
/// below `tolerance` × `crest` (m/s). Errors: no sign change up to 11× the crest speed, or no
/// convergence within [`SECANT_EVALUATIONS`].
pub(crate) fn secant_root(
    stall_n: f64,
    guess: f64,
    crest: f64,
    tolerance: f64,
    thrust: &mut dyn FnMut(f64) -> Result<f64>,
) -> Result<f64> {
    if stall_n <= 0.0 {
        return Ok(0.0);
    }
    let ceiling = 11.0 * crest;
    let mut lo = (0.0, stall_n);
    let mut hi: Option<(f64, f64)> = None;
    let x0 = if guess.is_finite() && guess > 0.0 {
        guess.min(ceiling)
    } else {
        0.5 * crest
    };
    let f0 = thrust(x0)?;
    if f0 == 0.0 {
        return Ok(x0);
    }
    let mut prev = (x0, f0);
    if f0 > 0.0 {
        lo = prev;
    } else {
        hi = Some(prev);
    }
    let mut x = x0
        * if f0 > 0.0 {
            1.0 + NO_LOAD_PROBE
        } else {
            1.0 - NO_LOAD_PROBE
        };
    for _ in 0..SECANT_EVALUATIONS {
        if let Some(h) = hi
            && !(x > lo.0 && x < h.0)
        {
            x = (lo.0 * h.1 - h.0 * lo.1) / (h.1 - lo.1);
        }
        if hi.is_none() && x > ceiling {
            return Err(CoupledError::NotConverged {
                what: "bracket of the no-load speed",
                iterations: 0,
                residual: prev.1,
                tolerance: 0.0,
                context: "thrust still positive at 11× the crest speed".into(),
            });
        }
        let f = thrust(x)?;
        if f == 0.0 {
            return Ok(x);
        }
        if f > 0.0 {
            lo = (x, f);
        } else {
            hi = Some((x, f));
        }
        let next = x - f * (x - prev.0) / (f - prev.1);
        prev = (x, f);
        if let Some(h) = hi
            && h.0 - lo.0 <= tolerance * crest
        {
            return Ok(0.5 * (lo.0 + h.0));
        }
        if next.is_finite() && (next - x).abs() <= tolerance * crest {
            return Ok(next);
        }
        x = if next.is_finite() { next } else { 2.0 * x };
    }
    Err(CoupledError::NotConverged {
        what: "no-load speed (secant)",
        iterations: SECANT_EVALUATIONS,
        residual: prev.1,
        tolerance,
        context: format!("last speed {:.6e} m/s", prev.0),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 24 posts 0.37 λ apart, coupled through a dense compliance (diagonal springs plus an
    /// exponentially decaying half-space-like coupling), instant preload balance, amplitude
    /// profile `alpha`.
    fn coupled_row(alpha: &[f64]) -> CoupledScene {
        let wave = stick_slip::Wave::paper_default();
        let n = alpha.len();
        let x = (0..n)
            .map(|i| 0.37 * wave.wavelength_m() * i as f64)
            .collect();
        let mut scene = CoupledScene::independent_posts(wave, x, 1.8e6, 1.5e6, 0.3, 0.3, 0.4);
        let coupling = |i: usize, j: usize| 0.2 / 1.8e6 * (-(i.abs_diff(j) as f64) / 3.0).exp();
        scene.normal_compliance_m_per_n =
            DMatrix::from_fn(n, n, |i, j| coupling(i, j)) + DMatrix::identity(n, n) / 1.8e6;
        scene.preload_balance = PreloadBalance::Instant;
        scene.steps_per_period = 32;
        scene.amplitude_scale = alpha.to_vec();
        scene
    }

    #[test]
    fn a_model_from_a_nearby_profile_has_the_cold_models_normal_forces() {
        let n = 24;
        let first: Vec<f64> = (0..n).map(|i| 1.0 - 0.012 * i as f64).collect();
        let second: Vec<f64> = (0..n).map(|i| 1.0 - 0.013 * i as f64).collect();
        let start = CoupledModel::new(&coupled_row(&first)).unwrap();
        let warm = CoupledModel::new_from(&coupled_row(&second), Some(&start)).unwrap();
        let again = CoupledModel::new_from(&coupled_row(&second), Some(&warm)).unwrap();
        let cold = CoupledModel::new(&coupled_row(&second)).unwrap();
        let reused = again.normal_factors.iter().filter(|f| f.is_some()).count();
        assert!(
            reused > 0,
            "the contact sets stay on some phases and their factors are reused"
        );
        for (model, what) in [
            (&warm, "from the first profile"),
            (&again, "from its own factors"),
        ] {
            for j in 0..cold.normals.len() {
                let scale = cold.normals[j].amax();
                let difference = (&model.normals[j] - &cold.normals[j]).amax();
                assert!(
                    difference <= 1e-10 * scale,
                    "{what}: phase {j} normal forces differ by {difference:e} of {scale:e}"
                );
                assert!((model.approach[j] - cold.approach[j]).abs() <= 1e-10);
            }
        }
    }

    #[test]
    fn the_secant_search_finds_a_smooth_falling_roots_from_a_guess_on_either_side() {
        // F(v) = 12 (1 − (v/0.84)^1.7) − 0.3 v: a concave curve like the motor's.
        let f = |v: f64| 12.0 * (1.0 - (v / 0.84f64).powf(1.7)) - 0.3 * v;
        let mut root = 0.84;
        for _ in 0..60 {
            root -= f(root) / (-12.0 * 1.7 / 0.84 * (root / 0.84f64).powf(0.7) - 0.3);
        }
        for guess in [0.7, 0.8, 0.9, 1.5] {
            let mut evaluations = 0;
            let mut thrust = |v: f64| -> Result<f64> {
                evaluations += 1;
                Ok(f(v))
            };
            let found = secant_root(f(0.0), guess, 1.1, 1e-10, &mut thrust).unwrap();
            assert!(
                (found - root).abs() < 1e-9,
                "no-load speed {found} from the guess {guess}, root {root}"
            );
            assert!(
                evaluations <= 8,
                "{evaluations} evaluations from the guess {guess}"
            );
        }
    }

    /// Period-start forces x_k = x* + ρᵏ d approaching x* geometrically.
    fn geometric(k: i32) -> DVector<f64> {
        let limit = DVector::from_vec(vec![1.0, -2.0, 0.5, 0.0]);
        let mode = DVector::from_vec(vec![0.3, 0.1, -0.2, 0.05]);
        limit + mode * 0.4f64.powi(k)
    }

    #[test]
    fn a_geometric_approach_is_extrapolated_to_its_limit() {
        let mut approach = Approach::default();
        let mut jump = None;
        for k in 1..=3 {
            assert!(jump.is_none(), "no jump before three changes");
            jump = approach.record(geometric(k) - geometric(k - 1), true);
        }
        let extrapolated = geometric(3) + jump.expect("three geometric changes are extrapolated");
        let limit = geometric(200);
        assert!(
            (extrapolated - &limit).amax() < 1e-14,
            "extrapolated period-start forces reach the periodic state"
        );
    }

    #[test]
    fn a_mode_change_or_an_irregular_approach_is_not_extrapolated() {
        let mut approach = Approach::default();
        let d = |k: i32| geometric(k) - geometric(k - 1);
        assert!(approach.record(d(1), true).is_none(), "one change");
        assert!(approach.record(d(2), true).is_none(), "two changes");
        assert!(
            approach.record(d(3), false).is_none(),
            "the modes changed in the third period"
        );
        assert!(
            approach.record(d(4), true).is_none(),
            "restarted: one change"
        );
        assert!(
            approach.record(d(5), true).is_none(),
            "restarted: two changes"
        );
        assert!(
            approach.record(d(6) * 3.0, true).is_none(),
            "a change whose ratio jumps is not geometric"
        );
        assert!(
            approach.record(-d(7), true).is_none(),
            "a change that turns back is not geometric"
        );
    }
}
