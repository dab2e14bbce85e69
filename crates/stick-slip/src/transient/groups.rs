//! Phase groups: posts that see the same wave move together and are simulated once, weighted
//! by their count. Without decay or burst, posts with equal x mod λ share a phase (a square
//! n × n array has n columns; columns a whole number of wavelengths apart merge further); with
//! decay or a burst, equal x is needed. Posts with different gaps never share a group.
//!
//! With a tabulated amplitude profile (the energy-conserving wave, `crate::attenuation`) every
//! column is its own group (columns with equal x mod λ see different amplitudes), and the
//! profile's factor multiplies the group's amplitude; without one the groups and their
//! amplitudes are exactly those of the exponential decay (or the constant wave).
//!
//! Effective contact ratio: each group's weight is its share of the posts, count/N, and all
//! forces are in units of N_eff k_n A_n, so the slider sees N_eff = η·N posts (equivalently:
//! every group's post count scaled by η).

use crate::scene::DynamicScene;
use crate::wave::ScaledWave;

/// Relative tolerance (of λ) for two posts' x mod λ to count as one phase.
const PHASE_MERGE_TOLERANCE: f64 = 1e-9;

/// Phase groups in solver units, structure of arrays.
#[derive(Debug, Clone, Default)]
pub(crate) struct Groups {
    /// Share of the effective posts, Σ weight = 1.
    pub weight: Vec<f64>,
    /// Number of real posts in the group.
    pub count: Vec<f64>,
    /// Phase offset φ = k x (rad), unwrapped.
    pub phase: Vec<f64>,
    pub cos_phase: Vec<f64>,
    pub sin_phase: Vec<f64>,
    /// Amplitude factor at slider position 0, exp(−x/L) (1 without decay).
    pub amplitude: Vec<f64>,
    /// Initial gap over A_n.
    pub gap: Vec<f64>,
}

impl Groups {
    /// Build the groups of a scene (positions scaled by A_n).
    pub fn build(scene: &DynamicScene) -> Self {
        Self::build_with_profile(scene, None)
    }

    /// Build the groups with an amplitude factor per column (`profile[j]` for the j-th of
    /// [`columns`], ascending x); `None`: the scene's own wave (decay or constant).
    pub fn build_with_profile(scene: &DynamicScene, profile: Option<&[f64]>) -> Self {
        let lambda = scene.wave.wavelength_m();
        let k = scene.wave.wavenumber_rad_per_m();
        let a_n = scene.wave.normal_amplitude_m;
        let by_phase = scene.wave.decay_length_m.is_none()
            && scene.wave.burst_periods.is_none()
            && profile.is_none();
        let mut columns = scene
            .slider
            .layout
            .columns(lambda, scene.options.transient.uniform_phase_groups);
        if by_phase {
            // Merge columns whose x agree mod λ (keep the first x as representative).
            for c in &mut columns {
                c.0 = c.0.rem_euclid(lambda);
                if lambda - c.0 < PHASE_MERGE_TOLERANCE * lambda {
                    c.0 = 0.0;
                }
            }
            columns.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
            let mut merged: Vec<(f64, f64, f64)> = Vec::with_capacity(columns.len());
            for c in columns {
                match merged.last_mut() {
                    Some(last)
                        if (c.0 - last.0).abs() <= PHASE_MERGE_TOLERANCE * lambda
                            && c.1 == last.1 =>
                    {
                        last.2 += c.2
                    }
                    _ => merged.push(c),
                }
            }
            columns = merged;
        }
        let total: f64 = columns.iter().map(|c| c.2).sum();
        let mut groups = Self::default();
        for (j, (x, gap, count)) in columns.into_iter().enumerate() {
            let phase = k * x;
            groups.weight.push(count / total);
            groups.count.push(count);
            groups.phase.push(phase);
            groups.cos_phase.push(phase.cos());
            groups.sin_phase.push(phase.sin());
            groups
                .amplitude
                .push(scene.wave.decay_length_m.map_or(1.0, |l| (-x / l).exp()));
            if let Some(profile) = profile {
                groups.amplitude[j] *= profile[j];
            }
            groups.gap.push(gap / a_n);
        }
        groups
    }

    pub fn len(&self) -> usize {
        self.weight.len()
    }
}

/// Wave seen by every group at one instant: sin θ, cos θ and the drive factor
/// (amplitude × burst envelope), θ = t − φ − κ x_s.
#[derive(Debug, Clone, Default)]
pub(crate) struct Phases {
    pub sin: Vec<f64>,
    pub cos: Vec<f64>,
    pub drive: Vec<f64>,
}

impl Phases {
    pub fn new(n: usize) -> Self {
        Self {
            sin: vec![0.0; n],
            cos: vec![0.0; n],
            drive: vec![0.0; n],
        }
    }

    /// Fill for time `t` and slider position `x` (solver units).
    pub fn fill(&mut self, groups: &Groups, wave: &ScaledWave, t: f64, x: f64) {
        let alpha = t - wave.doppler * x;
        let (sa, ca) = alpha.sin_cos();
        let decay = wave.amplitude_at(x);
        for g in 0..groups.len() {
            let (cp, sp) = (groups.cos_phase[g], groups.sin_phase[g]);
            self.sin[g] = sa * cp - ca * sp;
            self.cos[g] = ca * cp + sa * sp;
            let on = wave.burst_phase_end.is_none() || wave.is_on(alpha - groups.phase[g]);
            self.drive[g] = if on { groups.amplitude[g] * decay } else { 0.0 };
        }
    }
}

/// The columns the amplitude profile is tabulated on: (x (m), post count) in ascending x, every
/// column of the layout (equal x and gap merged, never by phase).
pub(crate) fn columns(scene: &DynamicScene) -> Vec<(f64, f64)> {
    scene
        .slider
        .layout
        .columns(
            scene.wave.wavelength_m(),
            scene.options.transient.uniform_phase_groups,
        )
        .into_iter()
        .map(|(x, _, count)| (x, count))
        .collect()
}

/// Period-mean total normal force Σ w ⟨N⟩ at tip height z (running wave), in units of
/// N_eff k_n A_n.
pub(crate) fn mean_total_normal(groups: &Groups, z: f64) -> f64 {
    use crate::mean_normal::{TipHeight, mean_normal};
    (0..groups.len())
        .map(|g| {
            let (a, w) = (groups.amplitude[g], groups.weight[g]);
            if a > 0.0 {
                // (w·a)·⟨N⟩ in this order: the decay path's bits.
                w * a * mean_normal(TipHeight::from_c((z + groups.gap[g]) / a))
            } else {
                w * mean_normal_at(a, z + groups.gap[g])
            }
        })
        .sum()
}

/// Period-mean normal force of one post under a wave of amplitude `a` (of A_n) at tip height
/// `z` (+ gap), in k_n A_n: a⟨N⟩(z/a), and ⟨−z⟩₊ on the still stator (a = 0).
pub(crate) fn mean_normal_at(a: f64, z: f64) -> f64 {
    use crate::mean_normal::{TipHeight, mean_normal};
    if a > 0.0 {
        a * mean_normal(TipHeight::from_c(z / a))
    } else {
        (-z).max(0.0)
    }
}

/// Tip height z with Σ w ⟨N⟩(z) = `preload` (running wave), by bisection-safeguarded secant
/// on the decreasing function.
pub(crate) fn running_wave_equilibrium(groups: &Groups, preload: f64) -> f64 {
    let a_max = groups.amplitude.iter().copied().fold(0.0, f64::max);
    let gap_max = groups.gap.iter().copied().fold(0.0, f64::max);
    // Above a_max nothing touches; well below, everything is pressed in by at least `preload`.
    let hi = a_max;
    let lo = -preload - a_max - gap_max - 1.0;
    crate::math::decreasing_root(
        |z| mean_total_normal(groups, z) - preload,
        lo,
        hi,
        1e-15 * (1.0 + preload),
    )
}

/// Tip height z on a flat (wave-free) stator with Σ w ⟨−z − g⟩₊ = `preload`.
pub(crate) fn flat_equilibrium(groups: &Groups, preload: f64) -> f64 {
    let gap_max = groups.gap.iter().copied().fold(0.0, f64::max);
    let total = |z: f64| {
        (0..groups.len())
            .map(|g| groups.weight[g] * (-z - groups.gap[g]).max(0.0))
            .sum::<f64>()
    };
    crate::math::decreasing_root(
        |z| total(z) - preload,
        -preload - gap_max - 1.0,
        0.0,
        1e-15 * (1.0 + preload),
    )
}
