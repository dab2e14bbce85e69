//! The energy-conserving wave under the slider: the posts draw the power they take from the
//! wave, so the amplitude falls along the propagation direction.
//!
//! Model (steady state): the wave power entering under the post array at the slider's leading
//! edge, P_in (W; the caller's power per beam width at the scene's amplitude times
//! min(array width, aperture), `saw-wave`), flows along the propagation direction; the
//! time-mean stator power the posts draw up to x leaves it,
//! P(x) = P_in − ∫₀ˣ p_drawn dx, and the local amplitude (normal and tangential together, their
//! ratio fixed by the cut) is A(x) = A₀ √(P(x)/P_in) (the Rayleigh wave's power flux ∝ |A|²).
//! Discretised on the strip's posts in the order the wave reaches them: post i sees the power
//! after the posts before it and half its own draw (midpoint rule),
//! P_i = P_in − Σ_{j before i} p_j − ½ p_i, and P_out = P_in − Σ p_j, so
//! P_in − P_out = Σ p_j = the slider's stator power exactly. The strip is one row of the array;
//! p_j is the whole slider's draw at that x (the strip post's power over the strip share), so
//! each of the count_y rows shares P_in equally. The strip must be a whole row along x for the
//! profile to cover the slider's length.
//!
//! Self-consistency: p_j depends on every post's amplitude (through the preload distribution
//! and the wave each post sees), so the profile α_i = A_i/A₀ is the fixed point of
//! α = g(α) = √(max(P_i, 0)/P_in). It is solved together with the tips' periodic state, in
//! one stepping (`CoupledModel::steady_profiled`): a period maps z = (T, α), the tips' forces
//! at the period start (of the friction scale) and the profile, to (the forces after one
//! period on the model of α, the marching update of α from that period's powers — each post's
//! draw scaled with its own amplitude, `marching_profile`, a near-Newton step where the posts'
//! coupling through the preload is weak, with the fixed point of g), and Anderson acceleration
//! of this joint map (depth 5, no damping, Walker & Ni 2011) gives the next period's start and
//! profile: the profile moves every period, and the secant differences carry how the tips'
//! relaxation and the profile act on each other, instead of the profile waiting for the tips to
//! relax before each update. The normal problem is re-solved on each new profile from the old
//! one's contact sets and factors. Once max|g(α) − α| < ½ `tolerance`
//! (`model::PROFILE_SETTLE_SHARE`: the residual drifts as the tips relax, and a profile that
//! stayed just below the tolerance crossed it again) the profile stays and the
//! acceleration runs on the tips alone (it resumes on both if the residual grows past the
//! tolerance). The point is the first period that is periodic by the coupled model's rule
//! (two periods stepped, the same modes, forces within 1e-11 of the friction scale) at a
//! profile with max|g(α) − α| < `tolerance` (default 1e-6: the thrust then moves by about
//! 1e-6 relative, three orders below the time step's error of 0.4 % on the default row).
//! Stall starts from α = 1 (the constant-amplitude wave), the other points from the linear
//! prediction of their converged neighbours, the no-load search (regula falsi, or secant steps
//! from a guess such as the constant wave's no-load speed) from its previous evaluation.
//! On the default strip (the default run's coupled model: 100 posts, 64 steps per period,
//! 40 N, 50 points) the curve with its no-load search and the history point steps 620 periods
//! (7–22 per point; 1119 when each profile update waited for the tips to relax) against the
//! constant-amplitude curve's 418 (2–12 per point); each point starts from its neighbour's
//! secant differences as well as its state. A period costs about 1.7× the constant wave's (the
//! normal problem re-solved on each new profile, the per-post powers booked).
//! A post that would draw more than what remains is the case the clamp handles: P(x) ≥ 0, and
//! a post at zero amplitude draws nothing.
//!
//! Assumptions: steady state; no reflection at the slider's edges; beam diffraction neglected
//! (the beam's power stays in the aperture); the wave's velocity and phase under the slider
//! unchanged (only its amplitude falls: mass loading and the posts' stiffness do not shift the
//! velocity). Stops holding when the drawn power changes the wave's form (a slider that
//! reflects, a strongly loaded surface), over distances where diffraction spreads the beam
//! (Fresnel length a²/λ ≈ 200 mm for the 9 mm beam, far above the slider), or in transients
//! shorter than the transit time under the slider (L/c ≈ 1 µs).

use crate::anderson::Anderson;
use crate::error::{CoupledError, Result};
use crate::model::{
    CoupledModel, CoupledPoint, PeriodState, PostHistories, ProfileMap, SPEED_TOLERANCE,
};
use crate::scene::{CoupledScene, WaveDirection};
use serde::Serialize;

/// Default tolerance of the fixed point: max |Δα| (of A₀). Default 1e-6 (module docs).
pub const DEFAULT_AMPLITUDE_TOLERANCE: f64 = 1e-6;
/// Default mixing β of the Anderson acceleration of the joint map of tips and profile (1: no
/// damping). Default 1 (the marching update needs no damping).
pub const DEFAULT_RELAXATION: f64 = 1.0;
/// Default iteration limit. Default 200.
pub const DEFAULT_MAX_ITERATIONS: usize = 200;

/// Settings of the energy-conserving wave.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AttenuationOptions {
    /// Wave power entering under the post array at the leading edge (W), whole slider.
    pub power_in_w: f64,
    /// Fixed-point tolerance on max |Δα| (α = A/A₀).
    pub tolerance: f64,
    /// Mixing β of the joint Anderson acceleration, in (0, 1] (1: none).
    pub relaxation: f64,
    /// Iteration limit.
    pub max_iterations: usize,
    /// A guess of the no-load speed (m/s), e.g. the constant-amplitude wave's: the no-load
    /// search then runs secant steps from it ([`CoupledModel::no_load_search_near`]'s method)
    /// instead of the regula falsi from the crest speed, to the same tolerance. `None`: regula
    /// falsi.
    pub no_load_guess_m_per_s: Option<f64>,
}

impl AttenuationOptions {
    /// Default tolerance, relaxation and iteration limit for `power_in_w`.
    pub fn new(power_in_w: f64) -> Self {
        Self {
            power_in_w,
            tolerance: DEFAULT_AMPLITUDE_TOLERANCE,
            relaxation: DEFAULT_RELAXATION,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            no_load_guess_m_per_s: None,
        }
    }
}

/// The self-consistent steady point at one speed with the energy-conserving wave.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttenuatedPoint {
    /// The steady point at the converged amplitude profile.
    pub point: CoupledPoint,
    /// Wave power entering under the array (W).
    pub wave_power_in_w: f64,
    /// Wave power leaving at the trailing edge (W): P_in − Σ p_i.
    pub wave_power_out_w: f64,
    /// A_i/A₀ at each post (scene order).
    pub amplitude_scale: Vec<f64>,
    /// Stator power each post draws (W, whole slider at that x; scene order).
    pub post_power_w: Vec<f64>,
    /// Fixed-point iterations.
    pub iterations: usize,
    /// max |Δα| of the last iteration.
    pub last_change: f64,
    /// |P_in − P_out − stator_power_w| / P_in.
    pub balance_residual: f64,
}

/// The steady point at `speed_m_per_s` with the energy-conserving wave (module docs): the
/// amplitude profile iterated to self-consistency from the constant-amplitude wave. Errors: bad
/// options (named), a solve of the coupled model, or no convergence within `max_iterations`.
pub fn attenuated_at_speed(
    scene: &CoupledScene,
    speed_m_per_s: f64,
    options: &AttenuationOptions,
) -> Result<AttenuatedPoint> {
    check_options(options)?;
    Ok(iterate_profile(&StripModels::new(scene), speed_m_per_s, options, None)?.0)
}

/// What a converged point hands to the next one: its amplitude profile, the tips' state at
/// the start of its steady period and its model (whose normal contact sets start the next
/// model's normal solves).
#[derive(Clone)]
pub(crate) struct WarmStart {
    pub(crate) alpha: Vec<f64>,
    pub(crate) state: PeriodState,
    pub(crate) model: CoupledModel,
    /// The joint acceleration's differences: the joint map's Jacobian changes little between
    /// neighbouring speeds, so the next point starts with its secant information.
    anderson: Option<Anderson>,
}

impl WarmStart {
    /// The start of a point from `alpha`, the tips' `state` and `model`, without secant
    /// differences.
    pub(crate) fn new(alpha: Vec<f64>, state: PeriodState, model: CoupledModel) -> Self {
        Self {
            alpha,
            state,
            model,
            anderson: None,
        }
    }
}

pub(crate) fn check_options(o: &AttenuationOptions) -> Result<()> {
    let check = |parameter: &'static str, value: f64, ok: bool, requirement: &str| {
        if ok {
            Ok(())
        } else {
            Err(CoupledError::InvalidParameter {
                parameter,
                value,
                requirement: requirement.into(),
            })
        }
    };
    check(
        "power_in_w",
        o.power_in_w,
        o.power_in_w.is_finite() && o.power_in_w > 0.0,
        "must be finite and > 0",
    )?;
    check(
        "tolerance",
        o.tolerance,
        o.tolerance > 0.0 && o.tolerance < 1e-2,
        "must lie in (0, 1e-2)",
    )?;
    check(
        "relaxation",
        o.relaxation,
        o.relaxation > 0.0 && o.relaxation <= 1.0,
        "must lie in (0, 1]",
    )
}

/// The paths the wave's power flows along under the slider (module docs), in the model's post
/// order: each lane's posts in the order the wave reaches them (σx ascending; ties keep the
/// model's order) and its share of P_in. The strip is one lane (its draws are the whole
/// slider's at that x, so the lane carries all of P_in); the whole slider one lane per lattice
/// row along x ([`crate::slider`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Lanes(Vec<(Vec<usize>, f64)>);

impl Lanes {
    /// Lanes of the posts `lane_posts` (model indices, any order), each with its share of P_in;
    /// the posts of each lane sorted in the order the wave reaches them.
    pub(crate) fn new(
        lane_posts: Vec<(Vec<usize>, f64)>,
        post_x_m: &[f64],
        wave_direction: WaveDirection,
    ) -> Self {
        let sigma = wave_direction.sign();
        let lanes = lane_posts
            .into_iter()
            .map(|(mut posts, share)| {
                posts.sort_by(|&a, &b| (sigma * post_x_m[a]).total_cmp(&(sigma * post_x_m[b])));
                (posts, share)
            })
            .collect();
        Self(lanes)
    }

    /// One lane of every post of `scene`, carrying all of P_in (the strip).
    fn strip(scene: &CoupledScene) -> Self {
        let all = (0..scene.post_x_m.len()).collect();
        Self::new(vec![(all, 1.0)], &scene.post_x_m, scene.wave_direction)
    }
}

/// The target profile g(α) of the fixed point from the posts' draws (module docs, midpoint
/// rule), each lane's posts visited in the order the wave reaches them from the lane's power
/// P_in × share.
fn target_profile(lanes: &Lanes, power_w: &[f64], power_in_w: f64) -> Vec<f64> {
    let mut target = vec![0.0; power_w.len()];
    for (order, share) in &lanes.0 {
        let lane_in = power_in_w * share;
        let mut remaining = lane_in;
        for &i in order {
            let at_post = remaining - 0.5 * power_w[i];
            target[i] = (at_post.max(0.0) / lane_in).sqrt();
            remaining -= power_w[i];
        }
    }
    target
}

/// The marching update of the profile: the target profile with each post's draw scaled with
/// its own amplitude, p_j(α) = p_j (α/α_j)^e about the iterate α_j (the stator power a post
/// draws grows with the wave it sees), solved post by post in the order the wave reaches them
/// along each lane (the midpoint rule of [`target_profile`]; closed form for e = 2:
/// α_i² = R_i / (P_lane + ½ p_i/α_i²), R_i the power left before post i). Its fixed point is
/// the fixed point of `target_profile` (at α = α_j the scaled draws are the draws), but it
/// sees the drop of a post's draw with its own amplitude, which the plain map leaves to the
/// iteration: the update is close to a Newton step where the posts' coupling through the
/// preload is weak. A post whose draw cannot be scaled (α_j = 0, or a returned power that
/// would leave no positive denominator) keeps its draw.
fn marching_profile(lanes: &Lanes, power_w: &[f64], alpha: &[f64], power_in_w: f64) -> Vec<f64> {
    let mut target = vec![0.0; power_w.len()];
    for (order, share) in &lanes.0 {
        let lane_in = power_in_w * share;
        let mut remaining = lane_in;
        for &i in order {
            let scalable = alpha[i] > 1e-12;
            let slope = if scalable {
                power_w[i] / (alpha[i] * alpha[i])
            } else {
                0.0
            };
            let denominator = lane_in + 0.5 * slope;
            if scalable && denominator > 0.5 * lane_in {
                let a2 = remaining.max(0.0) / denominator;
                target[i] = a2.sqrt();
                remaining -= slope * a2;
            } else {
                let at_post = remaining - 0.5 * power_w[i];
                target[i] = (at_post.max(0.0) / lane_in).sqrt();
                remaining -= power_w[i];
            }
        }
    }
    target
}

/// Where the models of the amplitude profiles come from: the strip's dense model of its scene
/// ([`StripModels`]) or the whole slider's lattice model ([`crate::slider`]), with the lanes
/// the wave's power flows along.
pub(crate) trait ProfiledModels: Sync {
    /// The lanes of the model's posts.
    fn lanes(&self) -> &Lanes;
    /// Posts of the model.
    fn posts(&self) -> usize;
    /// The model at the amplitude profile `alpha` (A_i/A₀, model order), its normal solves
    /// started from `from` (a model of a nearby profile) if given. `accuracy`: how far `alpha`
    /// may still lie from the fixed point (max |Δα|, of A₀; 0 for a profile taken as it is):
    /// a model may resolve its normal forces no finer than a profile that uncertain fixes them
    /// (the strip's exact normal solves do not use it).
    fn model(
        &self,
        alpha: &[f64],
        from: Option<&CoupledModel>,
        accuracy: f64,
    ) -> Result<CoupledModel>;
    /// Relative tolerance of the no-load speed's secant search (of the crest speed): what the
    /// models' thrust is known to. Default the strip's [`SPEED_TOLERANCE`].
    fn speed_tolerance(&self) -> f64 {
        SPEED_TOLERANCE
    }
    /// Whether [`Self::model`] resolves a model only to its `accuracy` (else exactly whatever
    /// the accuracy). Default false.
    fn rough_models(&self) -> bool {
        false
    }
}

/// The strip's models: [`CoupledModel::new_from`] on the scene with each profile.
struct StripModels<'a> {
    scene: &'a CoupledScene,
    lanes: Lanes,
}

impl<'a> StripModels<'a> {
    fn new(scene: &'a CoupledScene) -> Self {
        Self {
            scene,
            lanes: Lanes::strip(scene),
        }
    }
}

impl ProfiledModels for StripModels<'_> {
    fn lanes(&self) -> &Lanes {
        &self.lanes
    }
    fn posts(&self) -> usize {
        self.scene.post_x_m.len()
    }
    fn model(&self, alpha: &[f64], from: Option<&CoupledModel>, _: f64) -> Result<CoupledModel> {
        CoupledModel::new_from(&with_profile(self.scene, alpha), from)
    }
}

/// The start of the point at `speed` from the converged `warm` one (at `warm_speed`): its profile
/// extrapolated linearly through the point before it (`before`: speed, profile), kept ≥ 0.
fn predicted(
    warm: &WarmStart,
    before: Option<&(f64, Vec<f64>)>,
    warm_speed: f64,
    speed: f64,
) -> WarmStart {
    let mut start = warm.clone();
    if let Some((v0, alpha0)) = before.filter(|(v0, _)| (warm_speed - v0).abs() > 0.0) {
        let t = (speed - warm_speed) / (warm_speed - v0);
        for (a, a0) in start.alpha.iter_mut().zip(alpha0) {
            *a = (*a + t * (*a - a0)).max(0.0);
        }
    }
    start
}

/// The profile's side of the joint stepping ([`ProfileMap`]): the target profile's residual
/// (module docs), the marching update as the profile's part of the joint map, and the model of
/// each new profile from the last one, counting the profile updates against the limit. A
/// profile at least [`ROUGH_PROFILE`] tolerances from the fixed point gets a model to its
/// residual ([`ProfiledModels::model`]'s `accuracy`); a profile whose model is that rough does
/// not settle (its residual counts at least the tolerance), so the settled model is resolved
/// as finely as without it.
struct Profile<'a> {
    models: &'a dyn ProfiledModels,
    options: &'a AttenuationOptions,
    speed_m_per_s: f64,
    updates: usize,
    last_change: f64,
    /// Whether the current model was made to a trial profile's accuracy.
    rough: bool,
}

/// Residual, in profile tolerances, above which a trial profile's model is made only to the
/// profile's accuracy (the whole slider's normal grid to a share of it: the CG iterations of
/// the grid re-solves fall by ≈ 2× on the paper's slider). Default 100.
pub const ROUGH_PROFILE: f64 = 100.0;

impl ProfileMap for Profile<'_> {
    fn target(&mut self, alpha: &[f64], power_w: &[f64]) -> Result<(f64, Vec<f64>)> {
        let lanes = self.models.lanes();
        let target = target_profile(lanes, power_w, self.options.power_in_w);
        self.last_change = target
            .iter()
            .zip(alpha)
            .fold(0.0, |m, (t, a)| f64::max(m, (t - a).abs()));
        let marched = marching_profile(lanes, power_w, alpha, self.options.power_in_w);
        let residual = match self.rough {
            true => self.last_change.max(self.options.tolerance),
            false => self.last_change,
        };
        Ok((residual, marched))
    }

    fn tolerance(&self) -> f64 {
        self.options.tolerance
    }

    fn relaxation(&self) -> f64 {
        self.options.relaxation
    }

    fn model(&mut self, alpha: &[f64], from: &CoupledModel) -> Result<CoupledModel> {
        if self.updates >= self.options.max_iterations {
            return Err(CoupledError::NotConverged {
                what: "energy-conserving wave amplitude (fixed point)",
                iterations: self.options.max_iterations,
                residual: self.last_change,
                tolerance: self.options.tolerance,
                context: format!("at speed {:.6e} m/s", self.speed_m_per_s),
            });
        }
        self.updates += 1;
        self.rough =
            self.models.rough_models() && self.last_change > ROUGH_PROFILE * self.options.tolerance;
        let accuracy = if self.rough { self.last_change } else { 0.0 };
        self.models.model(alpha, Some(from), accuracy)
    }
}

/// The scene with the amplitude profile `alpha`.
fn with_profile(scene: &CoupledScene, alpha: &[f64]) -> CoupledScene {
    let mut local = scene.clone();
    local.amplitude_scale = alpha.to_vec();
    local
}

/// The fixed point of the amplitude profile at one speed, from `warm` (a neighbouring
/// converged point) or from the constant-amplitude wave: the tips and the profile stepped
/// together ([`CoupledModel::steady_profiled`]) until a period is periodic at a profile settled
/// to the tolerance.
pub(crate) fn iterate_profile(
    models: &dyn ProfiledModels,
    speed_m_per_s: f64,
    o: &AttenuationOptions,
    warm: Option<&WarmStart>,
) -> Result<(AttenuatedPoint, WarmStart)> {
    let n = models.posts();
    let warm_fits = warm.filter(|w| w.alpha.len() == n);
    let alpha = warm_fits.map_or_else(|| vec![1.0; n], |w| w.alpha.clone());
    let model = models.model(&alpha, warm_fits.map(|w| &w.model), 0.0)?;
    let mut profile = Profile {
        models,
        options: o,
        speed_m_per_s,
        updates: 0,
        last_change: f64::INFINITY,
        rough: false,
    };
    let periods = o.max_iterations + crate::model::MAX_PERIODS;
    let steady = model.steady_profiled(
        speed_m_per_s,
        warm_fits.map(|w| &w.state),
        periods,
        &mut profile,
        warm_fits.and_then(|w| w.anderson.clone()),
    )?;
    let drawn: f64 = steady.post_power_w.iter().sum();
    let out = o.power_in_w - drawn;
    let point = steady.point;
    let alpha = steady.model.scene().amplitude_scale.clone();
    let alpha = if alpha.is_empty() {
        vec![1.0; n]
    } else {
        alpha
    };
    let converged = AttenuatedPoint {
        balance_residual: (o.power_in_w - out - point.stator_power_w).abs() / o.power_in_w,
        point,
        wave_power_in_w: o.power_in_w,
        wave_power_out_w: out,
        amplitude_scale: alpha.clone(),
        post_power_w: steady.post_power_w,
        iterations: profile.updates + 1,
        last_change: profile.last_change,
    };
    let next = WarmStart {
        alpha,
        state: steady.end_state,
        model: steady.model,
        anderson: steady.joint,
    };
    Ok((converged, next))
}

/// Stall thrust, no-load speed and the speed–thrust curve with the energy-conserving wave,
/// every point self-consistent on its own (the profile depends on the operating point).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttenuatedCurve {
    /// F(0⁺) at the self-consistent profile (N); 0 if the slider is locked.
    pub stall_thrust_n: f64,
    /// Speed where the self-consistent thrust vanishes (m/s), Illinois regula falsi.
    pub no_load_speed_m_per_s: f64,
    /// Stall, then `curve_points` − 1 speeds up to the no-load speed.
    pub curve: Vec<AttenuatedPoint>,
    /// Most fixed-point iterations of a curve point.
    pub max_iterations: usize,
    /// Largest |P_in − P_out − stator power| / P_in over the curve.
    pub max_balance_residual: f64,
}

/// [`attenuated_at_speed`] at stall, the no-load speed and the scene's `curve_points` speeds
/// (k v₀/(points − 1)), each point iterated to self-consistency. Each point starts from a
/// converged neighbour (its profile, period state and normal contact sets): the no-load search
/// (regula falsi, or secant steps from `no_load_guess_m_per_s`) from its last evaluation; the
/// curve in two chains, up from stall and down from the no-load point, run side by side
/// (rayon::join). Each chain is sequential, so the bits do not depend on the thread count.
pub fn solve_attenuated(
    scene: &CoupledScene,
    options: &AttenuationOptions,
) -> Result<AttenuatedCurve> {
    Ok(solve_chains(&StripModels::new(scene), options)?.curve)
}

/// [`solve_attenuated`] and the steady period at `history_fraction` of its no-load speed (the
/// self-consistent point there and every post's forces and modes over its steady period,
/// [`CoupledModel::post_histories`]'s samples). The history point starts from the converged
/// curve point nearest its speed (the two chains end on either side of half the no-load speed)
/// and its histories are the next period from its periodic state: the same steady period as a
/// start from rest gives, to the periodicity tolerance, where the steady cycle is unique.
pub fn solve_attenuated_with_histories(
    scene: &CoupledScene,
    options: &AttenuationOptions,
    history_fraction: f64,
) -> Result<(AttenuatedCurve, AttenuatedPoint, PostHistories)> {
    if !(history_fraction.is_finite() && (0.0..=1.0).contains(&history_fraction)) {
        return Err(CoupledError::InvalidParameter {
            parameter: "history_fraction",
            value: history_fraction,
            requirement: "must lie in [0, 1]".into(),
        });
    }
    let models = StripModels::new(scene);
    let chains = solve_chains(&models, options)?;
    let speed = history_fraction * chains.curve.no_load_speed_m_per_s;
    let (point, warm) = iterate_profile(&models, speed, options, chains.nearest_end(speed))?;
    let curve = chains.curve;
    let histories = warm.model.histories_from_periodic(speed, &warm.state)?;
    Ok((curve, point, histories))
}

/// The attenuated curve with the converged stall and the last converged point of each chain.
pub(crate) struct Chains {
    pub(crate) curve: AttenuatedCurve,
    /// The stall point's warm start.
    pub(crate) stall: WarmStart,
    /// Each chain's last point: (speed, warm start).
    pub(crate) ends: Vec<(f64, WarmStart)>,
}

impl Chains {
    /// The chain end nearest `speed_m_per_s` (the two chains end on either side of the middle
    /// of the curve), the start of a point there.
    pub(crate) fn nearest_end(&self, speed_m_per_s: f64) -> Option<&WarmStart> {
        let distance = |v: f64| (v - speed_m_per_s).abs();
        self.ends
            .iter()
            .min_by(|a, b| distance(a.0).total_cmp(&distance(b.0)))
            .map(|(_, w)| w)
    }
}

/// The attenuated curve of `models` ([`solve_attenuated`]'s sequence).
pub(crate) fn solve_chains(
    models: &dyn ProfiledModels,
    options: &AttenuationOptions,
) -> Result<Chains> {
    check_options(options)?;
    let (stall, stall_warm) = iterate_profile(models, 0.0, options, None)?;
    let stall_n = stall.point.thrust_n;
    // The no-load search's last evaluation lies nearest the no-load speed: the high chain's start.
    let mut last = Some(stall_warm.clone());
    let mut last_speed = 0.0;
    let mut thrust = |speed: f64| -> Result<f64> {
        let (point, warm) = iterate_profile(models, speed, options, last.as_ref())?;
        last = Some(warm);
        last_speed = speed;
        Ok(point.point.thrust_n)
    };
    let settings = stall_warm.model.scene();
    let crest = settings.wave.crest_speed_m_per_s();
    let no_load = match options.no_load_guess_m_per_s {
        Some(guess) => {
            let tolerance = models.speed_tolerance();
            crate::model::secant_root(stall_n, guess, crest, tolerance, &mut thrust)?
        }
        None => stall_warm.model.regula_falsi(stall_n, &mut thrust)?,
    };
    let points = settings.curve_points;
    let speed = |k: usize| no_load * k as f64 / (points - 1) as f64;
    let middle = (points / 2).max(1);
    let chain = |ks: Vec<usize>, mut warm: Option<WarmStart>, from_speed: f64| {
        let mut out = Vec::with_capacity(ks.len());
        // The profile of the point before the warm one, for the linear predictor.
        let mut before: Option<(f64, Vec<f64>)> = None;
        let mut warm_speed = from_speed;
        for k in ks {
            let v = speed(k);
            let start = warm
                .as_ref()
                .map(|w| predicted(w, before.as_ref(), warm_speed, v));
            let (point, next) = iterate_profile(models, v, options, start.as_ref())?;
            before = warm.map(|w| (warm_speed, w.alpha));
            warm = Some(next);
            warm_speed = v;
            out.push((k, point));
        }
        Ok::<_, CoupledError>((out, warm.map(|w| (warm_speed, w))))
    };
    let stall_start = stall_warm.clone();
    let (low, high) = rayon::join(
        || chain((1..middle).collect(), Some(stall_start), 0.0),
        || chain((middle..points).rev().collect(), last, last_speed),
    );
    let ((low, low_end), (high, high_end)) = (low?, high?);
    let mut rest: Vec<(usize, AttenuatedPoint)> = low.into_iter().chain(high).collect();
    rest.sort_by_key(|(k, _)| *k);
    let mut curve = vec![stall];
    curve.extend(rest.into_iter().map(|(_, p)| p));
    let ends = low_end.into_iter().chain(high_end).collect();
    Ok(Chains {
        curve: AttenuatedCurve {
            stall_thrust_n: stall_n.max(0.0),
            no_load_speed_m_per_s: no_load,
            max_iterations: curve.iter().map(|p| p.iterations).max().unwrap_or(0),
            max_balance_residual: curve.iter().map(|p| p.balance_residual).fold(0.0, f64::max),
            curve,
        },
        stall: stall_warm,
        ends,
    })
}
