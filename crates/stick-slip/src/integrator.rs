//! The integrators, their orders and their stability limits.
//!
//! | integrator | posts | friction | order | stability limit |
//! |---|---|---|---|---|
//! | `event-driven` | massless | exact Coulomb, transitions located by root finding | exact (period-average: closed-form segments); 4 (transient: RK4 between events) | period-average: none; transient: h·ω_max < 2.78 (RK4 on the stuck slider modes) |
//! | `return-mapping` | massless | exact Coulomb, implicit clamp (Moreau's catching-up) | 1 | none (unconditionally stable); accuracy needs h ≪ T |
//! | `regularized-explicit` | mass m_p | μN·tanh(slip/v_reg) | 1 (symplectic Euler) | h·γ + (h·ω_p)²/2 < 2, γ = μN_max/(m_p v_reg), ω_p = √(k_t/m_p) |
//! | `post-mass` | mass m_p | exact Coulomb impulses (Moreau–Jean) | 1 | h·ω_p < 2 |
//!
//! A step above the limit is refused ([`StabilityPolicy::Refuse`], the default) or run with a
//! warning naming the limit ([`StabilityPolicy::Warn`], for stability studies only).

use serde::{Deserialize, Serialize};

use crate::error::{Result, StickSlipError, Warning};

/// RK4's stability boundary on the imaginary axis, |h·ω| < 2√2 ≈ 2.83, rounded down (the
/// stuck slider modes are undamped oscillators). Default 2.78.
pub const RK4_STABILITY_BOUND: f64 = 2.78;
/// Return mapping: steps per wave period below which the first-order error exceeds ≈ 1 % of
/// the thrust (measured in validation/stick-slip). A coarser step is warned about. Default 50.
pub const RETURN_MAPPING_MIN_STEPS_PER_PERIOD: f64 = 50.0;
/// Steps per wave period of the transient's default (`auto`) return mapping: thrust and speed
/// within ≈ 1e-4 of the converged value on the paper scene (validation/stick-slip). Default 256.
pub const TRANSIENT_DEFAULT_STEPS_PER_PERIOD: f64 = 256.0;
/// Default number of event-driven RK4 steps per wave period (upper bound on the step; events
/// shorten steps further). Default 64.
pub const EVENT_DRIVEN_STEPS_PER_PERIOD: f64 = 64.0;

/// The integrators by name, without their step settings: what a scene chooses
/// (`model.lumped.integrator`); [`Integrator`] carries the steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IntegratorKind {
    /// [`Integrator::Auto`].
    Auto,
    /// [`Integrator::EventDriven`].
    EventDriven,
    /// [`Integrator::ReturnMapping`].
    ReturnMapping,
    /// [`Integrator::RegularizedExplicit`].
    Regularized,
    /// [`Integrator::PostMass`].
    PostMass,
}

impl IntegratorKind {
    /// Each kind by its scene name.
    pub const NAMES: [(&'static str, Self); 5] = [
        ("auto", Self::Auto),
        ("event-driven", Self::EventDriven),
        ("return-mapping", Self::ReturnMapping),
        ("regularized", Self::Regularized),
        ("post-mass", Self::PostMass),
    ];
}

/// Time-stepping scheme (serde tag `kind`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Integrator {
    /// The model's default: `event-driven` (closed form) for the period average,
    /// `return-mapping` with T/[`TRANSIENT_DEFAULT_STEPS_PER_PERIOD`] for the transient (the
    /// event-driven transient costs one RK4 restart per event, ≈ 4 per post group per period).
    #[default]
    Auto,
    /// Massless posts, exact Coulomb friction, stick/slip transitions located exactly.
    EventDriven {
        /// Largest RK4 step of the transient model (s); `None`: T/64 (or less if the slider
        /// modes need it). Unused by the period-average model, which is closed-form.
        #[serde(default)]
        max_step_s: Option<f64>,
    },
    /// Massless posts, fixed-step implicit return mapping (first order, unconditionally stable).
    ReturnMapping {
        /// Time step (s).
        dt_s: f64,
    },
    /// Posts with mass, tanh-regularised friction, explicit symplectic Euler.
    RegularizedExplicit {
        /// Time step (s).
        dt_s: f64,
        /// Regularisation speed v_reg (m/s): F = μN·tanh(slip velocity / v_reg).
        regularization_speed_m_per_s: f64,
    },
    /// Posts with mass, exact Coulomb friction as impulses (Moreau–Jean), explicit spring.
    PostMass {
        /// Time step (s).
        dt_s: f64,
    },
}

impl Integrator {
    /// Kebab-case name, as in scene files.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::EventDriven { .. } => "event-driven",
            Self::ReturnMapping { .. } => "return-mapping",
            Self::RegularizedExplicit { .. } => "regularized-explicit",
            Self::PostMass { .. } => "post-mass",
        }
    }

    /// The concrete scheme `auto` stands for in `model` (others map to themselves).
    pub fn resolve(&self, model: crate::model_kind::ModelKind, period_s: f64) -> Self {
        match (self, model) {
            (Self::Auto, crate::model_kind::ModelKind::PeriodicAverage) => {
                Self::EventDriven { max_step_s: None }
            }
            (Self::Auto, crate::model_kind::ModelKind::Transient) => Self::ReturnMapping {
                dt_s: period_s / TRANSIENT_DEFAULT_STEPS_PER_PERIOD,
            },
            (other, _) => *other,
        }
    }

    /// Whether the scheme needs `contact.post_mass_kg`.
    pub fn needs_post_mass(&self) -> bool {
        matches!(
            self,
            Self::RegularizedExplicit { .. } | Self::PostMass { .. }
        )
    }

    /// The fixed time step (s), if the scheme has one.
    pub fn fixed_step_s(&self) -> Option<f64> {
        match *self {
            Self::Auto | Self::EventDriven { .. } => None,
            Self::ReturnMapping { dt_s }
            | Self::PostMass { dt_s }
            | Self::RegularizedExplicit { dt_s, .. } => Some(dt_s),
        }
    }

    /// The largest stable step for this scheme in the given setting, with its criterion.
    /// `None`: unconditionally stable.
    pub fn stability_limit(&self, setting: &StabilitySetting) -> Option<StabilityLimit> {
        let slider_limit = |bound: f64, scheme: &str| {
            (setting.slider_mode_rad_per_s > 0.0).then(|| StabilityLimit {
                limit_s: bound / setting.slider_mode_rad_per_s,
                criterion: format!(
                    "{scheme}: h·ω_slider < {bound}, ω_slider = {:.3e} rad/s (slider on the stuck contact springs)",
                    setting.slider_mode_rad_per_s
                ),
            })
        };
        let tightest = |a: Option<StabilityLimit>, b: Option<StabilityLimit>| match (a, b) {
            (Some(a), Some(b)) => Some(if a.limit_s <= b.limit_s { a } else { b }),
            (a, b) => a.or(b),
        };
        match *self {
            Self::Auto => None,
            Self::EventDriven { .. } => slider_limit(RK4_STABILITY_BOUND, "RK4"),
            Self::ReturnMapping { .. } => None,
            Self::PostMass { .. } => {
                let post = setting.post_mode_rad_per_s().map(|omega_p| StabilityLimit {
                    limit_s: 2.0 / omega_p,
                    criterion: format!(
                        "symplectic Euler on the post resonance: h·ω_p < 2, ω_p = √(k_t/m_p) = {omega_p:.3e} rad/s ({:.0} MHz)",
                        omega_p / (2.0 * std::f64::consts::PI) / 1e6
                    ),
                });
                tightest(post, slider_limit(2.0, "symplectic Euler"))
            }
            Self::RegularizedExplicit {
                regularization_speed_m_per_s,
                ..
            } => {
                let post = setting.post_mode_rad_per_s().map(|omega_p| {
                    let mass = setting.post_mass_kg.unwrap_or(f64::NAN);
                    let gamma = setting.mu_kinetic * setting.peak_normal_force_n / (mass * regularization_speed_m_per_s);
                    // Largest h with h·γ + (h·ω_p)²/2 = 2 (Jury criterion of symplectic Euler on a
                    // damped oscillator), in the cancellation-free form.
                    let limit = 4.0 / (gamma + (gamma * gamma + 4.0 * omega_p * omega_p).sqrt());
                    StabilityLimit {
                        limit_s: limit,
                        criterion: format!(
                            "symplectic Euler with tanh friction: h·γ + (h·ω_p)²/2 < 2, γ = μN_max/(m_p v_reg) = {gamma:.3e} 1/s, ω_p = {omega_p:.3e} rad/s"
                        ),
                    }
                });
                tightest(post, slider_limit(2.0, "symplectic Euler"))
            }
        }
    }

    /// Check the step against its stability limit (typed error or warning per `policy`) and
    /// against accuracy limits (warnings). `period_s` is the wave period.
    pub fn check(
        &self,
        setting: &StabilitySetting,
        period_s: f64,
        policy: StabilityPolicy,
    ) -> Result<Vec<Warning>> {
        let mut warnings = Vec::new();
        if self.needs_post_mass() && setting.post_mass_kg.is_none() {
            return Err(StickSlipError::MissingPostMass {
                integrator: self.name(),
            });
        }
        let (parameter, step) = match *self {
            Self::EventDriven {
                max_step_s: Some(h),
            } => ("integrator.max_step_s", h),
            Self::Auto | Self::EventDriven { max_step_s: None } => return Ok(warnings),
            Self::ReturnMapping { dt_s }
            | Self::PostMass { dt_s }
            | Self::RegularizedExplicit { dt_s, .. } => ("integrator.dt_s", dt_s),
        };
        crate::error::require_positive(parameter, step)?;
        if let Self::RegularizedExplicit {
            regularization_speed_m_per_s,
            ..
        } = *self
        {
            crate::error::require_positive(
                "integrator.regularization_speed_m_per_s",
                regularization_speed_m_per_s,
            )?;
        }
        if let Some(limit) = self.stability_limit(setting)
            && step > limit.limit_s
        {
            match policy {
                    StabilityPolicy::Refuse => {
                        return Err(StickSlipError::StepAboveStabilityLimit {
                            integrator: self.name(),
                            parameter,
                            step_s: step,
                            limit_s: limit.limit_s,
                            criterion: limit.criterion,
                        });
                    }
                    StabilityPolicy::Warn => warnings.push(Warning::new(
                        parameter,
                        format!(
                            "{step:.3e} s exceeds the stability limit {:.3e} s ({}); results may be garbage",
                            limit.limit_s, limit.criterion
                        ),
                    )),
                }
        }
        if matches!(self, Self::ReturnMapping { .. })
            && step > period_s / RETURN_MAPPING_MIN_STEPS_PER_PERIOD
        {
            warnings.push(Warning::new(
                parameter,
                format!(
                    "{step:.3e} s is more than T/{RETURN_MAPPING_MIN_STEPS_PER_PERIOD} = {:.3e} s: first-order error above ≈ 1 % of the thrust",
                    period_s / RETURN_MAPPING_MIN_STEPS_PER_PERIOD
                ),
            ));
        }
        if step > period_s / 4.0 {
            warnings.push(Warning::new(
                parameter,
                format!("{step:.3e} s does not resolve the wave period {period_s:.3e} s"),
            ));
        }
        Ok(warnings)
    }
}

/// What a scheme's stability depends on, in SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StabilitySetting {
    /// Tangential stiffness of one post (N/m).
    pub k_t_n_per_m: f64,
    /// Post mass (kg), if any.
    pub post_mass_kg: Option<f64>,
    /// Largest normal force on one post (N).
    pub peak_normal_force_n: f64,
    /// Kinetic friction coefficient.
    pub mu_kinetic: f64,
    /// Fastest slider mode on the fully stuck contact springs, √(N_eff·max(k_n, k_t)/M)
    /// (rad/s); 0 for the period-average model (imposed speed).
    pub slider_mode_rad_per_s: f64,
}

impl StabilitySetting {
    /// Tangential post resonance ω_p = √(k_t/m_p) (rad/s), if a mass is set.
    pub fn post_mode_rad_per_s(&self) -> Option<f64> {
        self.post_mass_kg.map(|m| (self.k_t_n_per_m / m).sqrt())
    }
}

/// A largest stable step and the criterion that sets it.
#[derive(Debug, Clone, PartialEq)]
pub struct StabilityLimit {
    /// Largest stable step (s).
    pub limit_s: f64,
    /// Human-readable criterion, with the mode that sets it.
    pub criterion: String,
}

/// What to do with a step above the stability limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum StabilityPolicy {
    /// Refuse with [`StickSlipError::StepAboveStabilityLimit`] (default).
    #[default]
    Refuse,
    /// Run anyway and attach a warning with the limit (stability studies).
    Warn,
}
