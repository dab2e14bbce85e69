//! The energy-conserving wave under the whole slider: every post sees its local amplitude.
//!
//! Model: the strip's ([`crate::attenuation`], whose fixed point, joint stepping of tips and
//! profile, warm chains and no-load search run unchanged) with the wave's power flowing along
//! **lanes**, one per lattice row along x: the beam is taken uniform over the array's width,
//! so each of the n_y rows carries P_in/n_y from the leading edge, and row j's posts, in the
//! order the wave reaches them, each see P_{ij} = P_in/n_y − Σ_{k before i} p_{kj} − ½ p_{ij}
//! and the amplitude A_{ij} = A₀ √(P_{ij} n_y / P_in) (midpoint rule). Σ over every post of
//! p_{ij} is the slider's stator power, so P_in − P_out = stator power exactly, as on the
//! strip. A y-mirror fold ([`super::Mirror`]) keeps its rows: a folded row stands for a row
//! and its image, carries 2 P_in/n_y, and its draws are the pair's.
//!
//! Each new profile re-solves the normal contact of every grid phase on the new obstacle
//! h_i = δ_i + α_i A_n sin(θ − σ k x_i) (the static stage's own solve, started from the previous
//! profile's forces) and keeps the tangential operator, which the amplitude does not change.
//! [`SliderDynamics::solve_attenuated`] runs the curve; [`SliderProfiles`] one speed at a time
//! from a neighbour's [`ProfiledState`] (a study's search, which picks its own speeds).
//!
//! Assumptions beyond the strip's: no power crosses between rows (no diffraction within the
//! slider: its rows are ≈ 0.1 mm apart, and the beam's Fresnel length is ≈ 200 mm); the beam's
//! power is uniform over the array's width (a narrower beam would leave rows outside it
//! without wave, which neither wave model describes).

use serde::Serialize;

use super::{NormalContact, NormalGrid, SliderDynamics, SliderMaps};
use crate::attenuation::{
    AttenuatedCurve, AttenuatedPoint, AttenuationOptions, Lanes, ProfiledModels, WarmStart,
    check_options, iterate_profile, solve_chains,
};
use crate::error::Result;
use crate::model::{CoupledModel, PeriodState, PostHistories};

/// The whole slider's run on the energy-conserving wave: the self-consistent curve (amplitude
/// profiles and per-post draws on the full lattice), the maps at stall and at half the no-load
/// speed, and the middle row's histories over the latter's steady period.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttenuatedSlider {
    /// Stall, no-load speed and curve at the self-consistent profiles.
    pub curve: AttenuatedCurve,
    /// Maps at stall and at half the no-load speed (with each post's local amplitude).
    pub maps: Vec<SliderMaps>,
    /// Lattice indices of the posts in [`Self::histories`] (the middle row, x ascending).
    pub history_posts: Vec<usize>,
    /// Forces and modes of those posts over the steady period at half the no-load speed.
    pub histories: PostHistories,
    /// Normal solves of the phase grid made (one per profile the fixed point tried).
    pub normal_grids: usize,
}

impl AttenuatedSlider {
    /// The largest |α − g(α)| over the posts of curve point `point`: each post's amplitude
    /// against what its row's lane leaves it (the midpoint rule on the posts' own draws, from
    /// P_in/n_y with `power_in_w` the whole array's P_in; module docs). The fixed point's
    /// residual as a user can recompute it from the point's outputs; `None` for no such point.
    pub fn lane_residual(&self, point: usize, power_in_w: f64) -> Option<f64> {
        let p = self.curve.curve.get(point)?;
        let map = self.maps.first()?;
        let (nx, ny) = (map.posts_x, map.posts_y);
        let lane_in = power_in_w / ny as f64;
        let mut worst: f64 = 0.0;
        for j in 0..ny {
            let mut remaining = lane_in;
            for k in (0..nx).map(|i| i * ny + j) {
                let at_post = remaining - 0.5 * p.post_power_w[k];
                let target = (at_post.max(0.0) / lane_in).sqrt();
                worst = worst.max((p.amplitude_scale[k] - target).abs());
                remaining -= p.post_power_w[k];
            }
        }
        Some(worst)
    }
}

/// Tolerance of a trial profile's normal solves (their scaled complementarity residual, which
/// measures forces of the mean force and gaps of the wave amplitude) over the profile's own
/// residual max |Δα|: a profile that far from the fixed point moves every obstacle by up to
/// |Δα| A₀, and so every normal force by about that share, so resolving the forces finer than
/// a tenth of it only costs CG iterations. The static model's tolerance applies where it is
/// looser (a profile near the fixed point). Default 0.1.
pub const PROFILE_NORMAL_SHARE: f64 = 0.1;

/// The models of the whole slider's amplitude profiles and the lanes of its rows.
struct SliderModels<'a> {
    dynamics: &'a SliderDynamics,
    normal: &'a dyn NormalContact,
    lanes: Lanes,
    grids: std::sync::atomic::AtomicUsize,
}

impl<'a> SliderModels<'a> {
    /// One lane per (folded) row of the model's posts, i·rows + j.
    fn new(dynamics: &'a SliderDynamics, normal: &'a dyn NormalContact) -> Self {
        let g = &dynamics.scene.geometry;
        let (rows, share) = match dynamics.mirror {
            Some(fold) => (fold.half_posts_y(), 2.0 / g.posts_y as f64),
            None => (g.posts_y, 1.0 / g.posts_y as f64),
        };
        let lanes = (0..rows)
            .map(|j| ((0..g.posts_x).map(|i| i * rows + j).collect(), share))
            .collect();
        let settings = dynamics.model.scene();
        Self {
            dynamics,
            normal,
            lanes: Lanes::new(lanes, &settings.post_x_m, settings.wave_direction),
            grids: std::sync::atomic::AtomicUsize::new(0),
        }
    }

    /// The full lattice's profile of a model-order one.
    fn full(&self, alpha: &[f64]) -> Vec<f64> {
        match self.dynamics.mirror {
            Some(fold) => fold.expand(alpha),
            None => alpha.to_vec(),
        }
    }
}

impl ProfiledModels for SliderModels<'_> {
    fn lanes(&self) -> &Lanes {
        &self.lanes
    }
    /// The constant wave's [`super::SLIDER_SPEED_TOLERANCE`]: the slider's step solves know the
    /// thrust to ≈ 1e-8 of the friction scale, so a tighter root only costs secant steps.
    fn speed_tolerance(&self) -> f64 {
        super::SLIDER_SPEED_TOLERANCE
    }
    fn posts(&self) -> usize {
        self.dynamics.model.scene().post_x_m.len()
    }
    fn rough_models(&self) -> bool {
        true
    }
    /// The normal grid to [`PROFILE_NORMAL_SHARE`] of the profile's `accuracy` where that is
    /// looser than the static model's tolerance.
    fn model(
        &self,
        alpha: &[f64],
        from: Option<&CoupledModel>,
        accuracy: f64,
    ) -> Result<CoupledModel> {
        let mut scene = self.dynamics.scene.clone();
        scene.amplitude_scale = self.full(alpha);
        // The nearby profile's normal forces start each phase's solve.
        let start = from.map(|m| {
            (0..scene.steps_per_period)
                .map(|j| self.full(&m.normal_forces_n(j)))
                .collect::<Vec<_>>()
        });
        let tolerance = (accuracy > 0.0).then_some(PROFILE_NORMAL_SHARE * accuracy);
        let grid = NormalGrid::solve(&scene, self.normal, start.as_deref(), tolerance)?;
        self.grids
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let on = SliderDynamics::on_grid(
            &scene,
            grid,
            self.dynamics.tangential.clone(),
            self.dynamics.mirror,
            Some(from.unwrap_or(&self.dynamics.model)),
        )?;
        Ok(on.model)
    }
}

/// A converged point's state on the energy-conserving wave: its amplitude profile, the tips'
/// periodic state, its model (whose normal forces start the next model's contact solves) and
/// the joint acceleration's secant differences. Hand it to [`SliderProfiles::at_speed_from`]
/// at a nearby speed, or at the same speed of a nearby slider of the same lattice (a study's
/// next sample): the point is the same to the fixed point's and the periodicity rule's
/// tolerances, in fewer periods.
#[derive(Clone)]
pub struct ProfiledState(WarmStart);

impl ProfiledState {
    /// The tips' state at the start of the steady period.
    pub fn period_state(&self) -> &PeriodState {
        &self.0.state
    }
}

impl std::fmt::Debug for ProfiledState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ProfiledState")
            .field("posts", &self.0.alpha.len())
            .finish_non_exhaustive()
    }
}

/// The whole slider's points on the energy-conserving wave one speed at a time, each from a
/// converged neighbour's [`ProfiledState`]: what a search that picks its own speeds needs (a
/// study's curve). [`SliderDynamics::solve_attenuated`] runs the whole curve.
pub struct SliderProfiles<'a> {
    models: SliderModels<'a>,
    options: AttenuationOptions,
}

impl SliderProfiles<'_> {
    /// The self-consistent point at `speed_m_per_s` (per-post vectors on the full lattice)
    /// and its state, started from `from` (else from the constant wave, α = 1, tips at rest).
    /// A state of another lattice size is ignored.
    pub fn at_speed_from(
        &self,
        speed_m_per_s: f64,
        from: Option<&ProfiledState>,
    ) -> Result<(AttenuatedPoint, ProfiledState)> {
        let warm = from.map(|s| &s.0);
        let (mut point, next) = iterate_profile(&self.models, speed_m_per_s, &self.options, warm)?;
        self.models.dynamics.expand_point(&mut point);
        Ok((point, ProfiledState(next)))
    }

    /// Normal solves of the phase grid made so far (one per profile tried).
    pub fn normal_grids(&self) -> usize {
        self.models.grids.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Crest speed of the wave (m/s).
    pub fn crest_speed_m_per_s(&self) -> f64 {
        self.models.dynamics.model().crest_speed_m_per_s()
    }

    /// The state of a constant-wave point of this slider (α = 1, the tips' periodic `state`
    /// of [`SliderDynamics::model`]): the start of the energy-conserving wave's point at the
    /// same speed.
    pub fn constant_state(&self, state: &PeriodState) -> ProfiledState {
        let model = self.models.dynamics.model();
        let posts = model.scene().post_x_m.len();
        ProfiledState(WarmStart::new(
            vec![1.0; posts],
            state.clone(),
            model.clone(),
        ))
    }
}

impl std::fmt::Debug for SliderProfiles<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SliderProfiles")
            .field("options", &self.options)
            .field("normal_grids", &self.normal_grids())
            .finish_non_exhaustive()
    }
}

impl SliderDynamics {
    /// The whole slider's points on the energy-conserving wave of `options`, one speed at a
    /// time ([`SliderProfiles`]); `normal` as in [`Self::solve_attenuated`]. Errors: bad
    /// options, named.
    pub fn profiles<'a>(
        &'a self,
        normal: &'a dyn NormalContact,
        options: &AttenuationOptions,
    ) -> Result<SliderProfiles<'a>> {
        check_options(options)?;
        Ok(SliderProfiles {
            models: SliderModels::new(self, normal),
            options: *options,
        })
    }
}

impl SliderDynamics {
    /// The whole slider on the energy-conserving wave (module docs) of `options` (P_in of the
    /// whole array, the no-load guess e.g. the constant wave's): stall, no-load speed and
    /// curve at each point's self-consistent profile, the maps at stall and at half the
    /// no-load speed, the middle row's histories there. `normal` is the static stage's contact
    /// this model was built on (it re-solves the phase grid for every profile).
    pub fn solve_attenuated(
        &self,
        normal: &dyn NormalContact,
        options: &AttenuationOptions,
    ) -> Result<AttenuatedSlider> {
        check_options(options)?;
        let models = SliderModels::new(self, normal);
        let chains = solve_chains(&models, options)?;
        let half = 0.5 * chains.curve.no_load_speed_m_per_s;
        let nearest = chains.nearest_end(half);
        let history_posts = self.middle_row_posts();
        let (stall, at_half) = rayon::join(
            || self.profiled_maps(&chains.stall, 0.0, &[]),
            || -> Result<_> {
                let (_, warm) = iterate_profile(&models, half, options, nearest)?;
                self.profiled_maps(&warm, half, &self.model_posts(&history_posts))
            },
        );
        let ((stall_maps, _), (half_maps, histories)) = (stall?, at_half?);
        let mut curve = chains.curve;
        for p in &mut curve.curve {
            self.expand_point(p);
        }
        Ok(AttenuatedSlider {
            curve,
            maps: vec![stall_maps, half_maps],
            history_posts,
            histories,
            normal_grids: models.grids.into_inner(),
        })
    }

    /// The maps (and the histories of `posts`, model indices) of a converged point's model over
    /// one further steady period from its periodic state.
    fn profiled_maps(
        &self,
        warm: &WarmStart,
        speed_m_per_s: f64,
        posts: &[usize],
    ) -> Result<(SliderMaps, PostHistories)> {
        let (point, means, histories, _) =
            warm.model
                .post_means_and_histories_from(speed_m_per_s, Some(&warm.state), posts)?;
        let mut maps = self.maps(point, means);
        maps.amplitude_scale = match self.mirror {
            Some(fold) => fold.expand(&warm.alpha),
            None => warm.alpha.clone(),
        };
        Ok((maps, histories))
    }

    /// A curve point's per-post vectors on the full lattice (a folded pair's draw halved).
    fn expand_point(&self, p: &mut AttenuatedPoint) {
        if let Some(fold) = self.mirror {
            p.amplitude_scale = fold.expand(&p.amplitude_scale);
            p.post_power_w = fold
                .expand(&p.post_power_w)
                .iter()
                .map(|w| 0.5 * w)
                .collect();
        }
    }
}
