//! The complete input of a dynamic run ([`DynamicScene`]), its validation, and the automatic
//! choice between the period-average and the transient model ("model no more than the scene
//! needs", docs/physics.md §5.1).

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use crate::contact::PostContact;
use crate::error::{Result, StickSlipError, Warning};
use crate::integrator::{Integrator, StabilityPolicy, StabilitySetting};
use crate::mean_normal::tip_height_for_mean_normal;
use crate::slider::{PostLayout, Slider, VerticalModel};
use crate::wave::{Wave, WaveLimits};

/// Default number of points on the speed–thrust curve.
pub const DEFAULT_CURVE_POINTS: usize = 50;
/// Harmonics checked for the phase uniformity of the posts (m = 1..8): the single-post force
/// waveform's content beyond the 8th harmonic is below ≈ 1 % of its mean.
pub const PHASE_HARMONICS: usize = 8;
/// Phase sums |S_m| at or below this are treated as exactly uniform (round-off of the sum over
/// the posts). Default 1e-9.
const NEGLIGIBLE_PHASE_SUM: f64 = 1e-9;
/// Largest estimated slider speed ripple, relative to the crest speed A_t ω, accepted by the
/// period-average model under `auto` ([`DynamicScene::speed_ripple_estimate`]; the period
/// average's speed and thrust are off by about this much). Default 1e-2.
pub const SPEED_RIPPLE_LIMIT: f64 = 1e-2;
/// Largest estimated vertical bounce of the slider, relative to A_n, accepted by the
/// period-average model under `auto` for a `dynamic` vertical model
/// ([`DynamicScene::bounce_estimate`]). Default 1e-2.
pub const BOUNCE_LIMIT: f64 = 1e-2;

/// Which model to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ModelChoice {
    /// Period-average when the scene allows it, else transient (the reason is reported).
    #[default]
    Auto,
    /// One post period-averaged at imposed speed (posts uniform over the phase, heavy slider).
    PeriodicAverage,
    /// All phase groups and the slider integrated in time.
    Transient,
}

impl ModelChoice {
    /// Each choice by its scene name (`model.dynamics`).
    pub const NAMES: [(&'static str, Self); 3] = [
        ("auto", Self::Auto),
        ("periodic-average", Self::PeriodicAverage),
        ("transient", Self::Transient),
    ];
}

pub use crate::model_kind::ModelKind;

/// Where the transient starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum TransientStart {
    /// From the period-average estimate of the steady speed (fast settling).
    #[default]
    Estimate,
    /// From rest (step response).
    Rest,
}

/// Options of the transient model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TransientOptions {
    /// Simulated wave periods per run.
    pub periods: f64,
    /// Trailing periods averaged for the steady speed and thrust.
    pub average_periods: f64,
    /// Initial slider speed.
    pub start: TransientStart,
    /// Loads on the transient speed–thrust curve (between 0 and the stall estimate).
    pub curve_loads: usize,
    /// Locate the transient stall thrust by bisection on the load (several runs).
    pub find_stall: bool,
    /// Relative tolerance of the stall-thrust search (of the stall thrust).
    pub stall_tolerance: f64,
    /// Phase groups used for a `uniform-phase` layout.
    pub uniform_phase_groups: usize,
}

impl Default for TransientOptions {
    fn default() -> Self {
        Self {
            periods: 400.0,
            average_periods: 100.0,
            start: TransientStart::Estimate,
            curve_loads: 6,
            find_stall: true,
            stall_tolerance: 2e-3,
            uniform_phase_groups: 64,
        }
    }
}

/// Options of the time histories (Fig. 6-style charts).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HistoryOptions {
    /// Wave periods shown.
    pub periods: f64,
    /// Samples per wave period.
    pub samples_per_period: usize,
}

impl Default for HistoryOptions {
    fn default() -> Self {
        Self {
            periods: 3.0,
            samples_per_period: 256,
        }
    }
}

/// Numerical options.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolveOptions {
    /// Points on the speed–thrust curve (≥ 2).
    pub curve_points: usize,
    /// Refuse or warn on steps above the stability limit.
    pub stability: StabilityPolicy,
    /// Physical bounds of the wave.
    pub wave_limits: WaveLimits,
    /// Transient model options.
    pub transient: TransientOptions,
    /// Time-history options.
    pub history: HistoryOptions,
    /// Largest estimated memory of a run (bytes), checked before allocating.
    pub max_memory_bytes: f64,
    /// Largest estimated work of a run (post-steps), checked before integrating.
    pub max_post_steps: f64,
}

impl Default for SolveOptions {
    fn default() -> Self {
        Self {
            curve_points: DEFAULT_CURVE_POINTS,
            stability: StabilityPolicy::Refuse,
            wave_limits: WaveLimits::default(),
            transient: TransientOptions::default(),
            history: HistoryOptions::default(),
            max_memory_bytes: crate::limits::MAX_RUN_MEMORY_BYTES,
            max_post_steps: crate::limits::MAX_POST_STEPS,
        }
    }
}

/// Everything a dynamic run needs, SI units throughout.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicScene {
    /// The stator's wave.
    pub wave: Wave,
    /// One post's contact.
    pub contact: PostContact,
    /// The slider.
    pub slider: Slider,
    /// Model choice.
    #[serde(default)]
    pub model: ModelChoice,
    /// Integrator.
    #[serde(default)]
    pub integrator: Integrator,
    /// Numerical options.
    #[serde(default)]
    pub options: SolveOptions,
}

impl DynamicScene {
    /// The paper's scene with the given post springs (N/m): wave of docs/physics.md §1, μ = 0.3,
    /// Si slider 5 × 5 × 0.5 mm with 100 × 100 posts at 40 µm, η = 0.36, preload 40 N.
    pub fn paper_default(k_n_n_per_m: f64, k_t_n_per_m: f64) -> Self {
        Self {
            wave: Wave::paper_default(),
            contact: PostContact::new(
                k_n_n_per_m,
                k_t_n_per_m,
                crate::contact::PAPER_FRICTION_COEFFICIENT,
            ),
            slider: Slider::paper_default(),
            model: ModelChoice::Auto,
            integrator: Integrator::default(),
            options: SolveOptions::default(),
        }
    }

    /// Validate every part; returns the warnings.
    pub fn validate(&self) -> Result<Vec<Warning>> {
        let mut warnings = crate::wave::validate(&self.wave, &self.options.wave_limits)?;
        warnings.extend(self.contact.validate()?);
        warnings.extend(self.slider.validate()?);
        if self.options.curve_points < 2 {
            return Err(StickSlipError::InvalidParameter {
                parameter: "options.curve_points",
                value: self.options.curve_points as f64,
                requirement: "must be ≥ 2".into(),
            });
        }
        let t = &self.options.transient;
        crate::error::require_positive("options.transient.periods", t.periods)?;
        crate::error::require_positive("options.transient.average_periods", t.average_periods)?;
        crate::error::require_positive("options.transient.stall_tolerance", t.stall_tolerance)?;
        if t.average_periods > t.periods {
            return Err(StickSlipError::InvalidParameter {
                parameter: "options.transient.average_periods",
                value: t.average_periods,
                requirement: format!("must not exceed options.transient.periods = {}", t.periods),
            });
        }
        crate::error::require_positive("options.history.periods", self.options.history.periods)?;
        if self.options.history.samples_per_period < 8 {
            return Err(StickSlipError::InvalidParameter {
                parameter: "options.history.samples_per_period",
                value: self.options.history.samples_per_period as f64,
                requirement: "must be ≥ 8".into(),
            });
        }
        let model = self.resolve_model()?.0;
        let setting = self.stability_setting(model);
        let integrator = self.integrator.resolve(model, self.wave.period_s());
        self.check_size(model, &integrator)?;
        warnings.extend(integrator.check(
            &setting,
            self.wave.period_s(),
            self.options.stability,
        )?);
        Ok(warnings)
    }

    /// Mean normal force per effective post (N), P/N_eff.
    pub fn mean_normal_force_per_post_n(&self) -> f64 {
        self.slider.preload_n / self.slider.effective_post_count()
    }

    /// Peak normal force on one post at the period-mean equilibrium (N): k_n A_n (1 − c)
    /// (largest wave amplitude under the slider if the wave decays).
    pub fn peak_normal_force_n(&self) -> f64 {
        let k_n_a = self.contact.k_n_n_per_m * self.wave.normal_amplitude_m;
        let height = tip_height_for_mean_normal(self.mean_normal_force_per_post_n() / k_n_a);
        let amplitude = match self.wave.decay_length_m {
            Some(l) => {
                let columns = self.slider.layout.columns(self.wave.wavelength_m(), 1);
                let x_min = columns.iter().map(|c| c.0).fold(f64::INFINITY, f64::min);
                (-x_min.min(0.0) / l).exp()
            }
            None => 1.0,
        };
        k_n_a * (amplitude - height.c)
    }

    /// What the integrator's stability depends on, for the given model.
    pub fn stability_setting(&self, model: ModelKind) -> StabilitySetting {
        let slider_mode = match model {
            ModelKind::PeriodicAverage => 0.0,
            ModelKind::Transient => {
                let k = self.contact.k_n_n_per_m.max(self.contact.k_t_n_per_m);
                (self.slider.effective_post_count() * k / self.slider.mass_kg).sqrt()
            }
        };
        StabilitySetting {
            k_t_n_per_m: self.contact.k_t_n_per_m,
            post_mass_kg: self.contact.post_mass_kg,
            peak_normal_force_n: self.peak_normal_force_n(),
            mu_kinetic: self.contact.mu_kinetic,
            slider_mode_rad_per_s: slider_mode,
        }
    }

    /// Phase sums of the posts |S_m| = |Σ_i w_i e^{i m k x_i}| / Σ_i w_i for m = 1..8
    /// (`PHASE_HARMONICS`): 0 when the posts are uniform over the phase at harmonic m, 1 when all
    /// are in phase.
    pub fn phase_harmonics(&self) -> [f64; PHASE_HARMONICS] {
        let mut sums = [0.0; PHASE_HARMONICS];
        if matches!(self.slider.layout, PostLayout::UniformPhase { .. }) {
            return sums;
        }
        let k = self.wave.wavenumber_rad_per_m();
        let columns = self.slider.layout.columns(self.wave.wavelength_m(), 1);
        let total: f64 = columns.iter().map(|c| c.2).sum();
        for (i, sum) in sums.iter_mut().enumerate() {
            let m = (i + 1) as f64;
            let (re, im) = columns.iter().fold((0.0, 0.0), |(re, im), &(x, _, w)| {
                let phase = m * k * x;
                (re + w * phase.cos(), im + w * phase.sin())
            });
            *sum = re.hypot(im) / total;
        }
        sums
    }

    /// Phase non-uniformity of the posts, max over m = 1..8 of |S_m| ([`Self::phase_harmonics`]).
    /// Reported with the model choice; the choice itself depends on its effect
    /// ([`Self::speed_ripple_estimate`], [`Self::bounce_estimate`]).
    pub fn phase_nonuniformity(&self) -> f64 {
        self.phase_harmonics().into_iter().fold(0.0, f64::max)
    }

    /// Estimated slider speed ripple relative to the crest speed A_t ω, an upper bound of the
    /// forced response of the slider to the harmonics of the summed post forces (docs/physics.md
    /// §5.1):
    ///
    /// δv / (A_t ω) ≤ Σ_{m=1..8} 2 μ_s |S_m| P / (D_m · A_t ω),  D_m = max(M m ω − K_t/(m ω), 0),
    ///
    /// because every post sees the same signal shifted in phase, so the m-th harmonic of the
    /// summed tangential force is |S_m| times N_eff times one post's, whose amplitude is at most
    /// 2 μ_s ⟨N⟩ = 2 μ_s P/N_eff (|F_t| ≤ μ_s N). The slider responds as a mass M held by at most
    /// the fully stuck stiffness K_t = N_eff k_t; D_m = 0 (a possible resonance) gives ∞.
    /// Range of validity: steady running, continuous uniform wave, harmonics above the 8th of
    /// one post's force below ≈ 1 % of its mean. The period average's speed and thrust are off by
    /// about this ripple (first order).
    pub fn speed_ripple_estimate(&self) -> f64 {
        let omega = self.wave.angular_frequency_rad_per_s();
        let stiffness = self.slider.effective_post_count() * self.contact.k_t_n_per_m;
        let crest = self.wave.crest_speed_m_per_s().max(f64::MIN_POSITIVE);
        let amplitude = 2.0 * self.contact.mu_static * self.slider.preload_n;
        self.harmonic_response(|m| {
            let m_omega = m * omega;
            (self.slider.mass_kg * m_omega - stiffness / m_omega).max(0.0)
        }) * amplitude
            / crest
    }

    /// Estimated vertical bounce of the slider relative to A_n under the `dynamic` vertical model
    /// (`None` for the period-mean model, which has no bounce): the forced response of the
    /// vertical mode to the harmonics of the summed normal force (amplitude ≤ 2 |S_m| P, as for
    /// [`Self::speed_ripple_estimate`]),
    ///
    /// δz / A_n ≤ Σ_{m=1..8} 2 |S_m| P / (|D_m| A_n),  |D_m|² = max(M (mω)² − K_n, 0)² + (c m ω)²,
    ///
    /// with K_n = N_eff k_n (contact stiffness at most fully engaged) and c = 2ζ√(M K_n). The
    /// normal forces, hence the friction bound, change by k_n δz, i.e. the result by about δz/A_n
    /// of ⟨N⟩-relative terms (first order). Range of validity as for the speed ripple.
    pub fn bounce_estimate(&self) -> Option<f64> {
        let VerticalModel::Dynamic { damping_ratio } = self.slider.vertical else {
            return None;
        };
        let omega = self.wave.angular_frequency_rad_per_s();
        let mass = self.slider.mass_kg;
        let stiffness = self.slider.effective_post_count() * self.contact.k_n_n_per_m;
        let damping = 2.0 * damping_ratio * (mass * stiffness).sqrt();
        let amplitude = 2.0 * self.slider.preload_n;
        let response = self.harmonic_response(|m| {
            let m_omega = m * omega;
            (mass * m_omega * m_omega - stiffness)
                .max(0.0)
                .hypot(damping * m_omega)
        });
        Some(response * amplitude / self.wave.normal_amplitude_m)
    }

    /// Σ_m |S_m| / D(m) over m = 1..8 (∞ where |S_m| > 0 and D(m) = 0).
    fn harmonic_response(&self, denominator: impl Fn(f64) -> f64) -> f64 {
        self.phase_harmonics()
            .into_iter()
            .enumerate()
            .filter(|(_, s)| *s > NEGLIGIBLE_PHASE_SUM)
            .map(|(i, s)| s / denominator((i + 1) as f64))
            .sum()
    }

    /// The model to run and why.
    pub fn resolve_model(&self) -> Result<(ModelKind, String)> {
        let needs_transient = self.transient_reasons();
        match self.model {
            ModelChoice::Transient => Ok((ModelKind::Transient, "requested".into())),
            ModelChoice::PeriodicAverage => {
                if let Some(reason) = needs_transient.iter().find(|r| r.1) {
                    return Err(StickSlipError::ModelNotApplicable {
                        model: "periodic-average",
                        reason: reason.0.clone(),
                    });
                }
                Ok((ModelKind::PeriodicAverage, "requested".into()))
            }
            ModelChoice::Auto => Ok(match needs_transient.first() {
                Some((reason, _)) => (ModelKind::Transient, format!("auto: {reason}")),
                None => (ModelKind::PeriodicAverage, self.period_average_reason()),
            }),
        }
    }

    /// Why `auto` chose the period average: the estimated effects and their tolerances.
    fn period_average_reason(&self) -> String {
        let bounce = match self.bounce_estimate() {
            Some(b) => format!(", slider bounce ≈ {b:.1e} of A_n ≤ {BOUNCE_LIMIT:.0e}"),
            None => String::new(),
        };
        format!(
            "auto: continuous wave without decay; effect of the post phases (non-uniformity {:.3}) on a {:.3e} kg slider: speed ripple ≈ {:.1e} of A_t ω ≤ {SPEED_RIPPLE_LIMIT:.0e}{bounce}",
            self.phase_nonuniformity(),
            self.slider.mass_kg,
            self.speed_ripple_estimate(),
        )
    }

    /// Scene features the period-average model cannot represent, with whether they forbid it
    /// outright (true) or only make it approximate (false).
    fn transient_reasons(&self) -> Vec<(String, bool)> {
        let mut reasons = Vec::new();
        if self.wave.burst_periods.is_some() {
            reasons.push(("finite burst drive".into(), true));
        }
        if self.wave.decay_length_m.is_some() {
            reasons.push(("wave decays along x under the slider".into(), true));
        }
        if self.slider.layout.has_gaps() {
            reasons.push(("posts with initial gaps (height scatter)".into(), true));
        }
        let nonuniformity = self.phase_nonuniformity();
        let ripple = self.speed_ripple_estimate();
        if ripple.is_nan() || ripple > SPEED_RIPPLE_LIMIT {
            reasons.push((
                format!(
                    "speed ripple ≈ {ripple:.1e} of A_t ω > {SPEED_RIPPLE_LIMIT:.0e} (a {:.3e} kg slider, post phase non-uniformity {nonuniformity:.3})",
                    self.slider.mass_kg
                ),
                false,
            ));
        }
        if let Some(bounce) = self.bounce_estimate()
            && (bounce.is_nan() || bounce > BOUNCE_LIMIT)
        {
            reasons.push((
                format!(
                    "dynamic vertical slider motion: bounce ≈ {bounce:.1e} of A_n > {BOUNCE_LIMIT:.0e} (post phase non-uniformity {nonuniformity:.3})"
                ),
                false,
            ));
        }
        reasons
    }

    /// Wavelength-normalised phase of the posts, for reports: distinct x positions mod λ.
    pub fn distinct_phase_count(&self) -> usize {
        let lambda = self.wave.wavelength_m();
        let mut phases: Vec<f64> = self
            .slider
            .layout
            .columns(lambda, self.options.transient.uniform_phase_groups)
            .iter()
            .map(|c| (c.0 / lambda).rem_euclid(1.0) * 2.0 * PI)
            .collect();
        phases.sort_by(f64::total_cmp);
        phases.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        phases.len()
    }
}
