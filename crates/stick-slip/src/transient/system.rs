//! The transient system in solver units (length A_n, time 1/ω, force N_eff k_n A_n for the
//! slider, k_n A_n per post) and what every stepper shares.

use crate::error::Result;
use crate::post::Mode;
use crate::scene::DynamicScene;
use crate::slider::VerticalModel;
use crate::wave::ScaledWave;

use super::groups::{Groups, Phases, flat_equilibrium, running_wave_equilibrium};

/// The slider equations' constants, scaled.
#[derive(Debug, Clone)]
pub(crate) struct System {
    pub groups: Groups,
    pub wave: ScaledWave,
    /// ρ = k_t/k_n.
    pub rho: f64,
    pub mu_s: f64,
    pub mu_k: f64,
    /// M̂ = M ω²/(N_eff k_n).
    pub mass: f64,
    /// P̂ = P/(N_eff k_n A_n).
    pub preload: f64,
    /// L̂ = external load/(N_eff k_n A_n), pushing along +x.
    pub load: f64,
    /// Vertical damping Ĉ = 2ζ√M̂ if the vertical motion is dynamic.
    pub vertical_damping: Option<f64>,
    /// m̂ = m_p ω²/k_n, if posts have mass.
    pub post_mass: Option<f64>,
    /// Tip height of the running-wave equilibrium (quasi-static z, and the dynamic start).
    pub z_equilibrium: f64,
    /// Tip height of the static equilibrium on the flat stator (start of a burst).
    pub z_flat: f64,
    /// Start time: 0 for a continuous wave, just before the burst reaches the first post.
    pub t_start: f64,
}

impl System {
    /// The system of `scene` at external load `load_n` (N), with an amplitude factor per column
    /// (`profile`, `Groups::build_with_profile`) or the scene's own wave.
    pub fn new(scene: &DynamicScene, load_n: f64, profile: Option<&[f64]>) -> Self {
        let groups = Groups::build_with_profile(scene, profile);
        let wave = crate::wave::scaled(&scene.wave);
        let omega = scene.wave.angular_frequency_rad_per_s();
        let n_eff = scene.slider.effective_post_count();
        let k_n = scene.contact.k_n_n_per_m;
        let force = n_eff * k_n * scene.wave.normal_amplitude_m;
        let mass = scene.slider.mass_kg * omega * omega / (n_eff * k_n);
        let preload = scene.slider.preload_n / force;
        let z_equilibrium = running_wave_equilibrium(&groups, preload);
        let z_flat = flat_equilibrium(&groups, preload);
        let t_start = match wave.burst_phase_end {
            // The front θ = 0 reaches group g at t = φ_g (slider at x = 0); start half a radian
            // before the first arrival.
            Some(_) => groups.phase.iter().copied().fold(f64::INFINITY, f64::min) - 0.5,
            None => 0.0,
        };
        let vertical_damping = match scene.slider.vertical {
            VerticalModel::PeriodMean => None,
            VerticalModel::Dynamic { damping_ratio } => Some(2.0 * damping_ratio * mass.sqrt()),
        };
        Self {
            groups,
            wave,
            rho: scene.contact.k_t_n_per_m / k_n,
            mu_s: scene.contact.mu_static,
            mu_k: scene.contact.mu_kinetic,
            mass,
            preload,
            load: load_n / force,
            vertical_damping,
            post_mass: scene.contact.post_mass_kg.map(|m| m * omega * omega / k_n),
            z_equilibrium,
            z_flat,
            t_start,
        }
    }

    /// Replace the amplitude of every group by the profile's factor (one per column, the
    /// groups of `Groups::build_with_profile` with a profile) and move the quasi-static tip
    /// height to the running-wave equilibrium that carries the preload under it. Only for the
    /// energy-conserving wave: its scenes have no decay or burst (the factor is the amplitude).
    pub fn set_profile(&mut self, profile: &[f64]) {
        debug_assert_eq!(profile.len(), self.groups.len());
        debug_assert!(self.wave.decay_length.is_none() && self.wave.burst_phase_end.is_none());
        self.groups.amplitude.copy_from_slice(profile);
        self.z_equilibrium = running_wave_equilibrium(&self.groups, self.preload);
    }

    /// Initial tip height: flat-stator equilibrium before a burst, else the running-wave one.
    pub fn initial_height(&self) -> f64 {
        if self.wave.burst_phase_end.is_some() && self.vertical_damping.is_some() {
            self.z_flat
        } else {
            self.z_equilibrium
        }
    }

    /// Normal force of group g given the phases and tip height.
    #[inline]
    pub fn normal(&self, phases: &Phases, g: usize, z: f64) -> f64 {
        (phases.drive[g] * phases.sin[g] - z - self.groups.gap[g]).max(0.0)
    }

    /// Tangential velocity of the stator particle under group g (along +x).
    #[inline]
    pub fn particle_velocity(&self, phases: &Phases, g: usize) -> f64 {
        -self.wave.tangential_ratio * phases.drive[g] * phases.sin[g]
    }

    /// Σ_g w_g (ρ e_g, N_g): the total tangential (x) and normal contact force of posts whose
    /// tangential force is their spring force ρ e (the fixed-step schemes).
    pub fn spring_totals(&self, deflection: &[f64], normal: &[f64]) -> (f64, f64) {
        (0..self.groups.len()).fold((0.0, 0.0), |(f, nn), g| {
            let w = self.groups.weight[g];
            (f + w * self.rho * deflection[g], nn + w * normal[g])
        })
    }
}

/// The slider's kinematic state (solver units).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct SliderState {
    pub t: f64,
    /// Position along x.
    pub x: f64,
    /// Velocity along x.
    pub v: f64,
    /// Tip height.
    pub z: f64,
    /// Vertical velocity.
    pub w: f64,
}

/// Sums over an interval, weighted over groups (solver units).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Sums {
    pub time: f64,
    /// ∫ ΣwF dt (x-component).
    pub force_time: f64,
    /// ∫ ΣwN dt.
    pub normal_time: f64,
    /// ∫ Σw F·u̇ dt.
    pub stator_work: f64,
    /// ∫ Σw |F·u̇| dt (scale of the power flow).
    pub power_flow: f64,
    /// ∫ ΣwF·v dt.
    pub output_work: f64,
    /// Friction dissipation.
    pub dissipation: f64,
    /// ∫ Σ_stick w dt.
    pub stick_time: f64,
    /// ∫ Σ_contact w dt.
    pub contact_time: f64,
}

impl std::ops::AddAssign for Sums {
    fn add_assign(&mut self, o: Self) {
        self.time += o.time;
        self.force_time += o.force_time;
        self.normal_time += o.normal_time;
        self.stator_work += o.stator_work;
        self.power_flow += o.power_flow;
        self.output_work += o.output_work;
        self.dissipation += o.dissipation;
        self.stick_time += o.stick_time;
        self.contact_time += o.contact_time;
    }
}

/// A transient time stepper.
pub(crate) trait Stepper {
    /// Current slider state.
    fn state(&self) -> SliderState;
    /// Advance by one internal step (fixed, or up to the next event), never beyond `t_limit`;
    /// adds the step's integrals to `sums`.
    fn step(&mut self, t_limit: f64, sums: &mut Sums) -> Result<()>;
    /// Stored energy of the posts (springs, and tip kinetic energy with post mass), weighted.
    fn stored_energy(&self) -> f64;
    /// Normal force, tangential force (x) and mode of group g at the current state.
    fn group(&self, g: usize) -> (f64, f64, Mode);
    /// Total tangential (x) and normal contact force at the current state.
    fn totals(&self) -> (f64, f64);
    /// Steps taken.
    fn steps(&self) -> u64;
    /// Integrator name.
    fn name(&self) -> &'static str;
    /// Stator work Σ w F·Δu of each group since the start (weighted, solver units), for the
    /// energy-conserving wave; `None` where the stepper does not keep it per group.
    fn group_stator_work(&self) -> Option<&[f64]>;
    /// The system being integrated (with the current amplitude profile).
    fn system(&self) -> &System;
    /// Change the amplitude profile from the current state on (`System::set_profile`): the
    /// posts keep their deflections and modes, the slider its state. `false` where the stepper
    /// cannot (the event-driven one, whose event functions assume a fixed wave).
    fn retune(&mut self, _profile: &[f64]) -> bool {
        false
    }
}
