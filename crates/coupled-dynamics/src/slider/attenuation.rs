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
//! h_i = δ_i + α_i A_n sin(θ − σ k x_i) (the static stage's own solve, cold) and keeps the
//! tangential operator, which the amplitude does not change.
//!
//! Assumptions beyond the strip's: no power crosses between rows (no diffraction within the
//! slider: its rows are ≈ 0.1 mm apart, and the beam's Fresnel length is ≈ 200 mm); the beam's
//! power is uniform over the array's width (a narrower beam would leave rows outside it
//! without wave, which neither wave model describes).

use std::sync::Arc;

use serde::Serialize;

use super::{NormalContact, NormalGrid, SliderDynamics, SliderMaps};
use crate::attenuation::{
    AttenuatedCurve, AttenuatedPoint, AttenuationOptions, Lanes, ProfiledModels, WarmStart,
    check_options, iterate_profile, solve_chains,
};
use crate::error::Result;
use crate::model::{ComplianceProduct, CoupledModel, PostHistories};

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

/// The models of the whole slider's amplitude profiles and the lanes of its rows.
struct SliderModels<'a> {
    dynamics: &'a SliderDynamics,
    normal: &'a dyn NormalContact,
    tangential: Arc<dyn ComplianceProduct>,
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
            tangential: dynamics.tangential.clone(),
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
    fn model(&self, alpha: &[f64], from: Option<&CoupledModel>) -> Result<CoupledModel> {
        let mut scene = self.dynamics.scene.clone();
        scene.amplitude_scale = self.full(alpha);
        // The nearby profile's normal forces start each phase's solve.
        let start = from.map(|m| {
            (0..scene.steps_per_period)
                .map(|j| self.full(&m.normal_forces_n(j)))
                .collect::<Vec<_>>()
        });
        let grid = NormalGrid::solve(&scene, self.normal, start.as_deref())?;
        self.grids
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let on =
            SliderDynamics::on_grid(&scene, grid, self.tangential.clone(), self.dynamics.mirror)?;
        Ok(on.model)
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
        let nearest = chains
            .ends
            .iter()
            .min_by(|a, b| (a.0 - half).abs().total_cmp(&(b.0 - half).abs()))
            .map(|(_, w)| w);
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
