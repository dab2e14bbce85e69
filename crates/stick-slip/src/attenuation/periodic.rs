//! The period average with the energy-conserving wave: the posts binned along x (columns, or
//! merged neighbouring columns), each bin one period-averaged post at its own amplitude, all
//! at the common tip height that carries the preload, Σ_b w_b α_b ⟨N̂⟩(z/α_b) = P/(N_eff k_n A_n)
//! (a still stator, α = 0, presses with ⟨−z⟩₊). A bin at amplitude α is the unit post at
//! z/α and scaled speed v̂/α with forces × α and powers × α² (module docs of
//! `crate::attenuation`); a bin under a still stator slips at μ_k N against the slider and draws
//! nothing. Equal amplitudes are evaluated once (the first iteration from α = 1 costs one post).

use std::collections::HashMap;
use std::f64::consts::PI;
use std::time::Instant;

use serde::Serialize;

use super::{AttenuationOptions, ProfileSolution, check_scene, solve_amplitude_profile};
use crate::error::{Result, StickSlipError, Warning};
use crate::math::bracketed_root;
use crate::mean_normal::TipHeight;
use crate::periodic::{PeriodicAverageModel, SpeedSample};
use crate::post::{PeriodIntegrals, PostParams};
use crate::result::DynamicResult;
use crate::scene::{DynamicScene, ModelKind};
use crate::transient::groups::mean_normal_at;

/// Relative tolerance (of the crest speed) of the attenuated no-load and load speeds: a few
/// times the fixed point's tolerance effect on the thrust. Default 1e-9.
const ATTENUATED_SPEED_TOLERANCE: f64 = 1e-9;
/// Amplitude factor below which a bin sees a still stator. Default 1e-12.
const STILL_STATOR_AMPLITUDE: f64 = 1e-12;

/// One self-consistent steady point of the period average with the energy-conserving wave.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttenuatedSample {
    /// The slider's steady behaviour at the converged profile (`stator_power_w` = Σ draws).
    pub sample: SpeedSample,
    /// Wave power entering under the array (W).
    pub wave_power_in_w: f64,
    /// Wave power leaving at the trailing edge (W): P_in − Σ draws.
    pub wave_power_out_w: f64,
    /// Centre x of each bin relative to the slider centre (m), ascending (the wave's order).
    pub x_m: Vec<f64>,
    /// A/A₀ of each bin.
    pub amplitude_scale: Vec<f64>,
    /// Stator power each bin draws (W, whole slider).
    pub bin_power_w: Vec<f64>,
    /// Common tip height z_s (m).
    pub tip_height_m: f64,
    /// Fixed-point evaluations.
    pub iterations: usize,
    /// max |T(α) − α| at the reported profile.
    pub last_change: f64,
    /// Whether the profile settled only to the options' `loose_tolerance`, not `tolerance`.
    pub settled_loosely: bool,
    /// |P_in − P_out − stator power| / P_in.
    pub balance_residual: f64,
}

/// The attenuated period-average result: the usual result at the self-consistent profiles plus
/// the wave's books of every curve point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttenuatedResult {
    /// Stall, no-load speed, curve, operating point, efficiency: all attenuated.
    pub result: DynamicResult,
    /// Wave power under the array (W).
    pub power_in_w: f64,
    /// One per point of `result.curve`, in its order.
    pub points: Vec<AttenuatedSample>,
    /// At the external load (`None` if it exceeds the stall thrust).
    pub operating: Option<AttenuatedSample>,
    /// Largest balance residual over the points.
    pub max_balance_residual: f64,
    /// Most fixed-point evaluations of a point.
    pub max_iterations: usize,
    /// Steady-post solves spent on the whole result (the cost measure).
    pub post_solves: usize,
}

/// The period-average model with the energy-conserving wave.
#[derive(Debug, Clone)]
pub struct AttenuatedPeriodicModel {
    base: PeriodicAverageModel,
    options: AttenuationOptions,
    /// Bin centres (m), ascending.
    x_m: Vec<f64>,
    /// Share of the posts, Σ = 1.
    weight: Vec<f64>,
    /// Steady-post solves so far.
    solves: std::cell::Cell<usize>,
}

/// Merge ascending columns (x, count) into at most `bins` bins of about equal post count:
/// centre = post-weighted mean x.
fn bin_columns(columns: &[(f64, f64)], bins: Option<usize>) -> (Vec<f64>, Vec<f64>) {
    let total: f64 = columns.iter().map(|c| c.1).sum();
    let n = bins.unwrap_or(columns.len()).min(columns.len()).max(1);
    let (mut x_m, mut weight) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let (mut sum_x, mut sum_w, mut seen) = (0.0, 0.0, 0.0);
    for (j, &(x, count)) in columns.iter().enumerate() {
        sum_x += x * count;
        sum_w += count;
        seen += count;
        let boundary = (x_m.len() + 1) as f64 * total / n as f64;
        if seen >= boundary * (1.0 - 1e-12) || j + 1 == columns.len() {
            x_m.push(sum_x / sum_w);
            weight.push(sum_w / total);
            (sum_x, sum_w) = (0.0, 0.0);
        }
    }
    (x_m, weight)
}

impl AttenuatedPeriodicModel {
    /// The period average of `scene` with the energy-conserving wave of `options` (typed errors
    /// for bad options and scenes the attenuation cannot describe).
    pub fn new(scene: &DynamicScene, options: &AttenuationOptions) -> Result<Self> {
        options.validate()?;
        check_scene(scene, "periodic-average with the energy-conserving wave")?;
        let base = PeriodicAverageModel::new(scene)?;
        let columns = crate::transient::groups::columns(scene);
        let (x_m, weight) = bin_columns(&columns, options.bins);
        Ok(Self {
            base,
            options: *options,
            x_m,
            weight,
            solves: std::cell::Cell::new(0),
        })
    }

    /// The constant-amplitude model underneath.
    pub fn constant(&self) -> &PeriodicAverageModel {
        &self.base
    }

    /// Bin centres (m), ascending.
    pub fn bin_x_m(&self) -> &[f64] {
        &self.x_m
    }

    /// Tip height z/A_n carrying the preload at profile `alpha`.
    fn tip_height(&self, alpha: &[f64]) -> f64 {
        if alpha.iter().all(|&a| a == 1.0) {
            return self.base.params.height.c;
        }
        let preload = self.base.scene.slider.preload_n / (self.base.n_eff * self.base.force_n);
        let total = |z: f64| {
            alpha
                .iter()
                .zip(&self.weight)
                .map(|(&a, &w)| w * mean_normal_at(a, z))
                .sum::<f64>()
        };
        let a_max = alpha.iter().copied().fold(0.0, f64::max);
        crate::math::decreasing_root(
            |z| total(z) - preload,
            -preload - a_max - 1.0,
            a_max,
            1e-15 * (1.0 + preload),
        )
    }

    /// Period integrals of one post under amplitude `a` at tip height `z` and scaled velocity
    /// `v`, in the unit post's units (forces × a, works × a² already applied).
    fn bin_integrals(&self, a: f64, z: f64, v: f64) -> Result<(PeriodIntegrals, bool)> {
        let p = self.base.params;
        if a < STILL_STATOR_AMPLITUDE {
            // Still stator: pressed with ⟨−z⟩₊, slipping at μ_k N against the slider (v ≤ 0 is
            // the drive direction; the v → 0⁺ limit slips the same way).
            let normal = (-z).max(0.0);
            let force = if v <= 0.0 { 1.0 } else { -1.0 } * p.mu_kinetic * normal;
            let time = 2.0 * PI;
            let contact = if normal > 0.0 { time } else { 0.0 };
            let integrals = PeriodIntegrals {
                time,
                force_time: force * time,
                normal_time: normal * time,
                output_work: force * v * time,
                dissipation: -force * v * time,
                power_flow: (force * v * time).abs(),
                contact_time: contact,
                ..Default::default()
            };
            return Ok((integrals, true));
        }
        let params = PostParams {
            doppler: p.doppler * a,
            height: TipHeight::from_c(z / a),
            ..p
        };
        self.solves.set(self.solves.get() + 1);
        let steady = self.base.steady_with(params, v / a)?;
        let i = steady.integrals;
        let (a1, a2) = (a, a * a);
        let scaled = PeriodIntegrals {
            time: i.time,
            force_time: i.force_time * a1,
            normal_time: i.normal_time * a1,
            stator_work: i.stator_work * a2,
            power_flow: i.power_flow * a2,
            output_work: i.output_work * a2,
            dissipation: i.dissipation * a2,
            stick_time: i.stick_time,
            contact_time: i.contact_time,
            stored_energy_change: i.stored_energy_change * a2,
        };
        Ok((scaled, steady.converged))
    }

    /// The slider's steady behaviour at `speed_m_per_s` under the profile `alpha`: the sample,
    /// each bin's draw (W) and the tip height (of A_n).
    fn evaluate(
        &self,
        speed_m_per_s: f64,
        alpha: &[f64],
    ) -> Result<(Vec<f64>, (SpeedSample, f64))> {
        let b = &self.base;
        let v = b.scaled_velocity(speed_m_per_s);
        let z = self.tip_height(alpha);
        let mut cache: HashMap<u64, (PeriodIntegrals, bool)> = HashMap::new();
        let power_unit = b.force_n * b.length_m * b.omega * b.n_eff;
        let mut draws = Vec::with_capacity(alpha.len());
        let (mut force, mut normal, mut output, mut dissipation) = (0.0, 0.0, 0.0, 0.0);
        let (mut stick, mut contact, mut residual, mut converged) = (0.0, 0.0, 0.0f64, true);
        for (&a, &w) in alpha.iter().zip(&self.weight) {
            let (i, ok) = match cache.get(&a.to_bits()) {
                Some(hit) => *hit,
                None => {
                    let fresh = self.bin_integrals(a, z, v)?;
                    cache.insert(a.to_bits(), fresh);
                    fresh
                }
            };
            let t = i.time;
            force += w * i.force_time / t;
            normal += w * i.normal_time / t;
            output += w * i.output_work / t;
            dissipation += w * i.dissipation / t;
            stick += w * i.stick_time / t;
            contact += w * i.contact_time / t;
            converged &= ok;
            if i.power_flow > 0.0 {
                residual = residual.max(i.energy_balance_residual().abs());
            }
            draws.push(w * i.stator_work / t * power_unit);
        }
        let output_w = output * power_unit;
        let dissipation_w = dissipation * power_unit;
        let delivered = output_w + dissipation_w.max(0.0);
        let sample = SpeedSample {
            speed_m_per_s,
            thrust_n: -force * b.force_n * b.n_eff,
            output_power_w: output_w,
            stator_power_w: draws.iter().sum(),
            friction_dissipation_w: dissipation_w,
            efficiency: if delivered > 0.0 && output_w > 0.0 {
                output_w / delivered
            } else {
                0.0
            },
            stick_fraction: if contact > 0.0 { stick / contact } else { 0.0 },
            contact_fraction: contact,
            mean_normal_force_n: normal * b.force_n * b.n_eff,
            energy_balance_residual: residual,
            converged,
        };
        Ok((draws, (sample, z)))
    }

    /// The self-consistent steady point at `speed_m_per_s` (m/s, drive direction), the fixed
    /// point started from `warm` (a neighbouring point's profile) or α = 1. Where it does not
    /// settle to `tolerance` in `max_iterations`, it goes on from its last profile to
    /// `loose_tolerance` and the sample says so (`settled_loosely`). Errors: a post solve, or
    /// no convergence to `loose_tolerance` either (`NotConverged`).
    pub fn at_speed(&self, speed_m_per_s: f64, warm: Option<&[f64]>) -> Result<AttenuatedSample> {
        crate::error::require_finite("speed_m_per_s", speed_m_per_s)?;
        let start = match warm {
            Some(w) if w.len() == self.x_m.len() => w.to_vec(),
            _ => vec![1.0; self.x_m.len()],
        };
        let profile = |options: &AttenuationOptions, start: Vec<f64>| {
            solve_amplitude_profile(options, start, |alpha| self.evaluate(speed_m_per_s, alpha))
        };
        let mut solution: ProfileSolution<(SpeedSample, f64)> = profile(&self.options, start)?;
        let settled_loosely = !solution.converged;
        if settled_loosely {
            let loose = AttenuationOptions {
                tolerance: self.options.loose_tolerance,
                ..self.options
            };
            let iterations = solution.iterations;
            solution = profile(&loose, solution.alpha)?;
            solution.iterations += iterations;
        }
        if !solution.converged {
            return Err(StickSlipError::NotConverged {
                model: "periodic-average with the energy-conserving wave",
                what: "amplitude profile (fixed point of the wave's power balance)",
                iterations: solution.iterations,
                residual: solution.last_change,
            });
        }
        let (sample, z) = solution.value;
        let p_in = self.options.power_in_w;
        let out = p_in - solution.draw_w.iter().sum::<f64>();
        Ok(AttenuatedSample {
            wave_power_in_w: p_in,
            wave_power_out_w: out,
            balance_residual: (p_in - out - sample.stator_power_w).abs() / p_in,
            sample,
            x_m: self.x_m.clone(),
            amplitude_scale: solution.alpha,
            bin_power_w: solution.draw_w,
            tip_height_m: z * self.base.length_m,
            iterations: solution.iterations,
            last_change: solution.last_change,
            settled_loosely,
        })
    }

    /// The speed where the attenuated thrust equals `load_n`, between 0 (thrust `stall_n`) and
    /// the crest speed (expanded if needed), each evaluation warm-started from the last profile.
    fn speed_for_thrust(&self, load_n: f64, stall: &AttenuatedSample) -> Result<AttenuatedSample> {
        let crest = self.base.crest_speed_m_per_s();
        let mut warm = stall.amplitude_scale.clone();
        let mut failure = None;
        let mut last: Option<AttenuatedSample> = None;
        let mut excess = |speed: f64| -> f64 {
            match self.at_speed(speed, Some(&warm)) {
                Ok(s) => {
                    warm.clone_from(&s.amplitude_scale);
                    let value = s.sample.thrust_n - load_n;
                    last = Some(s);
                    value
                }
                Err(e) => {
                    failure.get_or_insert(e);
                    -1.0
                }
            }
        };
        // The attenuated wave is weaker under the trailing bins: the constant-amplitude speed at
        // the load is a close upper bracket (expanded if not).
        let mut hi = match self.base.at_load(load_n)? {
            Some(s) if s.speed_m_per_s > 0.0 => s.speed_m_per_s,
            _ => crest,
        };
        let mut expansions = 0;
        while excess(hi) > 0.0 {
            if expansions == 12 {
                return Err(StickSlipError::NotConverged {
                    model: "periodic-average with the energy-conserving wave",
                    what: "bracket of the load speed (thrust still positive beyond the crest speed)",
                    iterations: expansions,
                    residual: hi,
                });
            }
            hi *= 1.25;
            expansions += 1;
        }
        let root = bracketed_root(&mut excess, 0.0, hi, ATTENUATED_SPEED_TOLERANCE * crest);
        if let Some(e) = failure {
            return Err(e);
        }
        match last {
            Some(s) if s.sample.speed_m_per_s == root => Ok(s),
            _ => self.at_speed(root, Some(&warm)),
        }
    }

    /// The full attenuated result: stall, no-load speed, `options.curve_points` points evenly
    /// from 0⁺ to the no-load speed (each warm-started from the previous), the operating point.
    pub fn solve(&self) -> Result<AttenuatedResult> {
        let started = Instant::now();
        self.solves.set(0);
        let b = &self.base;
        let mut warnings: Vec<Warning> = b.warnings.clone();
        let stall = self.at_speed(0.0, None)?;
        let points_wanted = b.scene.options.curve_points.max(2);
        let mut points = vec![stall.clone()];
        if stall.sample.thrust_n > 0.0 {
            let end = self.speed_for_thrust(0.0, &stall)?;
            let v0 = end.sample.speed_m_per_s;
            for k in 1..points_wanted - 1 {
                let warm = points.last().map(|p| p.amplitude_scale.clone());
                let speed = v0 * k as f64 / (points_wanted - 1) as f64;
                points.push(self.at_speed(speed, warm.as_deref())?);
            }
            points.push(end);
        } else {
            warnings.push(Warning::new(
                "slider.preload_n",
                format!(
                    "the slider is locked under the attenuated wave: F(0⁺) = {:.4} N ≤ 0",
                    stall.sample.thrust_n
                ),
            ));
            points[0].sample.thrust_n = 0.0;
        }
        let stall_n = points[0].sample.thrust_n;
        let load = b.scene.slider.external_load_n;
        let operating = if load > stall_n {
            warnings.push(Warning::new(
                "slider.external_load_n",
                format!("load {load} N exceeds the attenuated stall thrust {stall_n:.4} N: the slider does not advance"),
            ));
            None
        } else if load == 0.0 {
            points.last().cloned()
        } else {
            Some(self.speed_for_thrust(load, &points[0])?)
        };
        if points
            .iter()
            .chain(operating.iter())
            .any(|p| p.settled_loosely)
        {
            warnings.push(Warning::new(
                "wave.attenuation",
                format!(
                    "the amplitude profile settled only to max|Δα| < {} (not {:e}) at some \
                     speeds: the draws switch between stick/slip states from one iterate to \
                     the next",
                    self.options.loose_tolerance, self.options.tolerance
                ),
            ));
        }
        let samples: Vec<SpeedSample> = points.iter().map(|p| p.sample).collect();
        let result = self.assemble(&samples, operating.as_ref(), warnings, started);
        Ok(AttenuatedResult {
            result,
            power_in_w: self.options.power_in_w,
            max_balance_residual: points
                .iter()
                .chain(operating.iter())
                .map(|p| p.balance_residual)
                .fold(0.0, f64::max),
            max_iterations: points.iter().map(|p| p.iterations).max().unwrap_or(0),
            post_solves: self.solves.get(),
            points,
            operating,
        })
    }

    fn assemble(
        &self,
        samples: &[SpeedSample],
        operating: Option<&AttenuatedSample>,
        mut warnings: Vec<Warning>,
        started: Instant,
    ) -> DynamicResult {
        let b = &self.base;
        if samples
            .iter()
            .chain(operating.map(|o| &o.sample))
            .any(|s| !s.converged)
        {
            warnings.push(Warning::new(
                "steady state",
                "some bins reached no exactly periodic cycle (quasi-periodic stick/slip); their values are averages over many cycles",
            ));
        }
        let reference = operating.map_or(samples[0], |o| o.sample);
        let load = b.scene.slider.external_load_n;
        DynamicResult {
            model: ModelKind::PeriodicAverage,
            model_reason: format!("{}; energy-conserving wave", b.reason),
            integrator: match b.scheme {
                None => "event-driven (closed-form segments) per amplitude bin".into(),
                Some(_) => b
                    .scene
                    .integrator
                    .resolve(ModelKind::PeriodicAverage, b.scene.wave.period_s())
                    .name()
                    .to_string(),
            },
            stall_thrust_n: samples[0].thrust_n,
            no_load_speed_m_per_s: samples.last().map_or(0.0, |s| s.speed_m_per_s),
            curve: samples.iter().map(SpeedSample::curve_point).collect(),
            stick_fraction: reference.stick_fraction,
            contact_fraction: reference.contact_fraction,
            efficiency: samples.iter().map(|s| s.efficiency).fold(0.0, f64::max),
            max_output_power_w: samples.iter().map(|s| s.output_power_w).fold(0.0, f64::max),
            operating_point: operating.map(|o| o.sample.operating_point(load)),
            effective_post_count: b.n_eff,
            mean_normal_force_per_post_n: b.scene.mean_normal_force_per_post_n(),
            tip_height_m: operating.map_or(b.tip_height_m(), |o| o.tip_height_m),
            friction_limit_n: b.scene.contact.mu_kinetic * b.scene.slider.preload_n,
            crest_speed_m_per_s: b.crest_speed_m_per_s(),
            wall_time_s: started.elapsed().as_secs_f64(),
            warnings,
            transient: None,
        }
    }
}
