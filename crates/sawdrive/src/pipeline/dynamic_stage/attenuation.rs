//! The energy-conserving wave of the dynamic stage (`wave.attenuation`, docs/physics.md §5.5):
//! the wave power that enters under the post array, the `auto` decision, the wave's books of
//! every curve point, and the coupled models' attenuated curves put into their results.
//!
//! Formula: P_in = (power per unit beam width of the stator cut's Rayleigh wave at the scene's
//! amplitude and frequency, `scene::crystal`) × min(post-array width, `wave.aperture`): the part
//! of the beam that runs under the posts. Every curve point reports P_in and
//! P_out = P_in − (stator power the posts draw); with attenuation on, P_out ≥ 0 and the books
//! close to 1e-6 of P_in (the models' own fixed points); with it off, P_out < 0 says the
//! constant-amplitude wave has been asked for more power than it carries.
//! `auto` turns attenuation on when the constant-amplitude posts draw more than 1 %
//! (`stick_slip::AUTO_DRAW_FRACTION`) of P_in at stall. Range of validity: the models' (steady
//! state, no reflection at the slider's edges, diffraction neglected, the wave's velocity under
//! the slider unchanged). Every dynamic model honours it: the coupled strip, the period average
//! and the transient (whose profile converges inside each run).

use serde::Serialize;
use stick_slip::{
    AttenuationSetting, DynamicResult, DynamicScene, ModelKind, PeriodicAverageModel,
    TransientModel,
};

use super::PipelineError;
use crate::scene::Scene;

/// The decision on the energy-conserving wave, reported in `dynamic --json` and summaries.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WaveAttenuation {
    /// `on` or `off`: whether the reported curve is the energy-conserving one.
    pub state: &'static str,
    /// Why (the setting, or the `auto` evidence).
    pub reason: String,
    /// Wave power entering under the post array (W).
    pub power_in_w: f64,
}

impl WaveAttenuation {
    /// Whether the reported curve is attenuated.
    pub fn on(&self) -> bool {
        self.state == "on"
    }
}

/// Wave power entering under the post array (W): the cut's power per beam width at the scene's
/// amplitude and frequency times min(array width, aperture).
pub fn wave_power_under_array_w(scene: &Scene) -> f64 {
    let wave = &scene.motor.wave;
    let width_m = scene.motor.posts.array_y_m.min(wave.aperture_m);
    scene
        .crystal_wave
        .power_per_width_w_per_m(wave.normal_amplitude_m, wave.frequency_hz)
        * width_m
}

/// The decision for a scene whose reported model draws `stall_draw_w` (W) at stall under the
/// constant-amplitude wave.
pub fn decide(scene: &Scene, stall_draw_w: f64) -> Result<WaveAttenuation, PipelineError> {
    let power_in_w = wave_power_under_array_w(scene);
    let setting = scene.wave_attenuation;
    let prescribed =
        scene.motor.wave.decay_length_m.is_some() || scene.motor.wave.burst_periods.is_some();
    let (on, reason) = match setting {
        AttenuationSetting::Auto if prescribed => (
            false,
            "auto: the scene prescribes the wave along the slider (wave.decay_length or \
             wave.burst_periods)"
                .to_string(),
        ),
        _ => setting.resolve(stall_draw_w, power_in_w),
    };
    Ok(WaveAttenuation {
        state: if on { "on" } else { "off" },
        reason,
        power_in_w,
    })
}

/// Stator power the lumped posts draw at stall under the constant-amplitude wave (W), from the
/// period average (the transient agrees with it to 2e-5 on the default motor; it is the `auto`
/// evidence, not a reported figure). `None` where the period average does not apply (a decaying
/// or burst wave, which `auto` leaves alone anyway).
pub fn lumped_stall_draw_w(scene: &DynamicScene) -> Result<Option<f64>, PipelineError> {
    if scene.wave.decay_length_m.is_some() || scene.wave.burst_periods.is_some() {
        return Ok(None);
    }
    let model = PeriodicAverageModel::new(scene)?;
    Ok(Some(model.at_speed(0.0)?.stator_power_w))
}

/// Whether the lumped model that runs is the transient.
pub fn is_transient(kind: ModelKind) -> bool {
    kind == ModelKind::Transient
}

/// The energy-conserving wave for a reported lumped result (`result` of the lumped model on
/// `dynamic`, the scene's dynamic input): the decision and, when on (the period average), the
/// result replaced by the self-consistent one; the books of every curve point. The one home of
/// this branch: the dynamic stage and the studies' evaluator both call it.
pub fn attenuate_lumped(
    scene: &Scene,
    dynamic: &DynamicScene,
    result: &mut DynamicResult,
) -> Result<LumpedAttenuation, PipelineError> {
    let transient = is_transient(result.model);
    let stall_draw_w = lumped_stall_draw_w(dynamic)?;
    let wave = decide(scene, stall_draw_w.unwrap_or(0.0))?;
    if wave.on() {
        let options = stick_slip::AttenuationOptions::new(wave.power_in_w);
        let (solved, books, stall_profile) = solve_lumped_attenuated(dynamic, transient, &options)?;
        let mut attenuated = solved;
        let mut warnings = result.warnings.clone();
        for w in attenuated.warnings.drain(..) {
            if !warnings.contains(&w) {
                warnings.push(w);
            }
        }
        attenuated.warnings = warnings;
        attenuated.model_reason = format!(
            "{}; energy-conserving wave ({})",
            result.model_reason, wave.reason
        );
        *result = attenuated;
        return Ok(LumpedAttenuation {
            wave,
            books,
            stall_profile,
        });
    }
    Ok(LumpedAttenuation {
        books: constant_books(&wave, dynamic, result, transient, stall_draw_w)?,
        wave,
        stall_profile: None,
    })
}

/// The lumped model of `dynamic` (transient or period average) on the energy-conserving wave:
/// its result, the wave's books of every curve point and the amplitude profile at stall. The
/// transient's stator power is P_in − P_out of its books, the period average's the posts' draw
/// (equal to round-off: the books close by construction).
fn solve_lumped_attenuated(
    dynamic: &DynamicScene,
    transient: bool,
    options: &stick_slip::AttenuationOptions,
) -> Result<(DynamicResult, Vec<WaveBooks>, Option<AmplitudeProfile>), PipelineError> {
    if transient {
        let solved = TransientModel::new(dynamic)?.solve_attenuated(options)?;
        let (books, stall) = books_and_stall(
            &solved.points,
            |p| (&p.x_m, &p.amplitude_scale),
            |p| {
                (
                    p.wave_power_in_w - p.wave_power_out_w,
                    p.wave_power_in_w,
                    p.wave_power_out_w,
                )
            },
        );
        Ok((solved.result, books, stall))
    } else {
        let solved = solve_periodic(dynamic, options)?;
        let (books, stall) = books_and_stall(
            &solved.points,
            |p| (&p.x_m, &p.amplitude_scale),
            |p| {
                (
                    p.sample.stator_power_w,
                    p.wave_power_in_w,
                    p.wave_power_out_w,
                )
            },
        );
        Ok((solved.result, books, stall))
    }
}

/// The books of every point (stator, wave in, wave out; W) and the first point's (stall's)
/// amplitude profile (x, A/A₀) of an attenuated lumped solve.
fn books_and_stall<P>(
    points: &[P],
    profile: impl Fn(&P) -> (&Vec<f64>, &Vec<f64>),
    powers: impl Fn(&P) -> (f64, f64, f64),
) -> (Vec<WaveBooks>, Option<AmplitudeProfile>) {
    let books = points
        .iter()
        .map(|p| {
            let (stator_power_w, wave_power_in_w, wave_power_out_w) = powers(p);
            WaveBooks {
                stator_power_w,
                wave_power_in_w,
                wave_power_out_w,
            }
        })
        .collect();
    let stall = points.first().map(|p| {
        let (x, a) = profile(p);
        AmplitudeProfile::of(x, a)
    });
    (books, stall)
}

/// What `attenuate_lumped` decided and solved: the decision, the wave's books of every curve
/// point, and with attenuation on the amplitude profile at stall.
#[derive(Debug, Clone, PartialEq)]
pub struct LumpedAttenuation {
    pub wave: WaveAttenuation,
    pub books: Vec<WaveBooks>,
    /// A/A₀ along the slider at stall (`None`: attenuation off).
    pub stall_profile: Option<AmplitudeProfile>,
}

/// The local amplitude along the slider: A/A₀ at positions x (m, relative to the slider's centre,
/// ascending: the order the wave reaches them).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AmplitudeProfile {
    pub x_m: Vec<f64>,
    pub amplitude_scale: Vec<f64>,
}

impl AmplitudeProfile {
    /// The profile of a lumped model's bins or columns (x ascending, A/A₀ each).
    pub fn of(x_m: &[f64], amplitude_scale: &[f64]) -> Self {
        Self {
            x_m: x_m.to_vec(),
            amplitude_scale: amplitude_scale.to_vec(),
        }
    }

    /// A/A₀ at `x_m` (relative to the slider's centre): linear between the profile's points,
    /// its end values beyond them.
    pub fn at(&self, x_m: f64) -> f64 {
        let (xs, a) = (&self.x_m, &self.amplitude_scale);
        match xs.iter().position(|&x| x >= x_m) {
            None => *a.last().unwrap_or(&1.0),
            Some(0) => a[0],
            Some(k) => {
                let t = (x_m - xs[k - 1]) / (xs[k] - xs[k - 1]);
                a[k - 1] + t * (a[k] - a[k - 1])
            }
        }
    }
}

/// The period average on the energy-conserving wave (its fixed point settles loosely, with a
/// warning, where stick/slip switching keeps it from `tolerance`: `AttenuationOptions::loose_tolerance`).
fn solve_periodic(
    dynamic: &DynamicScene,
    options: &stick_slip::AttenuationOptions,
) -> Result<stick_slip::AttenuatedResult, PipelineError> {
    Ok(stick_slip::AttenuatedPeriodicModel::new(dynamic, options)?.solve()?)
}

/// The stall profile alone of the lumped model on `dynamic` with the energy-conserving wave,
/// for the passes of a fixed point that needs only it (`pipeline::local_amplitude`): the
/// period average's stall point warm-started from `warm` (a previous pass's profile), or the
/// transient's whole curve (it has no stall point of its own). `Err` with the reason when `auto`
/// turns the wave off at this scene.
pub fn lumped_stall_profile(
    scene: &Scene,
    dynamic: &DynamicScene,
    transient: bool,
    warm: Option<&AmplitudeProfile>,
) -> Result<Result<AmplitudeProfile, String>, PipelineError> {
    let stall_draw_w = lumped_stall_draw_w(dynamic)?;
    let wave = decide(scene, stall_draw_w.unwrap_or(0.0))?;
    if !wave.on() {
        return Ok(Err(wave.reason));
    }
    let options = stick_slip::AttenuationOptions::new(wave.power_in_w);
    if transient {
        let solved = TransientModel::new(dynamic)?.solve_attenuated(&options)?;
        let stall = solved
            .points
            .first()
            .ok_or_else(|| PipelineError::Unsupported {
                stage: "dynamic (energy-conserving wave)",
                message: "the transient's attenuated curve has no points".into(),
            })?;
        return Ok(Ok(AmplitudeProfile::of(&stall.x_m, &stall.amplitude_scale)));
    }
    let model = stick_slip::AttenuatedPeriodicModel::new(dynamic, &options)?;
    let stall = model.at_speed(0.0, warm.map(|w| w.amplitude_scale.as_slice()))?;
    Ok(Ok(AmplitudeProfile::of(&stall.x_m, &stall.amplitude_scale)))
}

/// The books of a constant-wave lumped curve: the period average's stator power at each speed;
/// the transient's from its output and efficiency, at stall from the period average (the
/// `auto` evidence).
fn constant_books(
    wave: &WaveAttenuation,
    dynamic: &DynamicScene,
    result: &DynamicResult,
    transient: bool,
    stall_draw_w: Option<f64>,
) -> Result<Vec<WaveBooks>, PipelineError> {
    if let (false, Some(_)) = (transient, stall_draw_w) {
        let model = PeriodicAverageModel::new(dynamic)?;
        return result
            .curve
            .iter()
            .map(|p| {
                let draw = model.at_speed(p.speed_m_per_s)?.stator_power_w;
                Ok(WaveBooks::of(wave.power_in_w, draw))
            })
            .collect();
    }
    Ok(result
        .curve
        .iter()
        .map(|p| {
            let draw = if p.efficiency > 0.0 {
                p.output_power_w / p.efficiency
            } else {
                stall_draw_w.unwrap_or(f64::NAN)
            };
            WaveBooks::of(wave.power_in_w, draw)
        })
        .collect())
}

/// The wave's books of one curve point: `wave_power_in_w`, `wave_power_out_w` beside
/// `stator_power_w` (W).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WaveBooks {
    pub stator_power_w: f64,
    pub wave_power_in_w: f64,
    pub wave_power_out_w: f64,
}

impl WaveBooks {
    /// The books of a point that draws `stator_power_w` from a wave that brings `power_in_w`.
    pub fn of(power_in_w: f64, stator_power_w: f64) -> Self {
        Self {
            stator_power_w,
            wave_power_in_w: power_in_w,
            wave_power_out_w: power_in_w - stator_power_w,
        }
    }
}

/// Puts the energy-conserving wave's `curve` into a constant-amplitude coupled result `r` (the
/// strip's or the whole slider's): stall thrust, no-load speed, curve, energy balance,
/// efficiency and stick fraction; η_dyn stays as it is. Returns each point's wave power leaving.
pub(super) fn take_attenuated_curve(
    r: &mut coupled_dynamics::CoupledResult,
    curve: &coupled_dynamics::AttenuatedCurve,
) -> Vec<Option<f64>> {
    r.stall_thrust_n = curve.stall_thrust_n;
    r.no_load_speed_m_per_s = curve.no_load_speed_m_per_s;
    r.curve = curve.curve.iter().map(|p| p.point.clone()).collect();
    r.energy_balance_residual = r
        .curve
        .iter()
        .map(|p| p.energy_balance_residual.abs())
        .fold(0.0, f64::max);
    r.efficiency = r.curve.iter().map(|p| p.efficiency).fold(0.0, f64::max);
    r.stick_fraction = r.curve.first().map_or(0.0, |p| p.stick_fraction);
    curve
        .curve
        .iter()
        .map(|p| Some(p.wave_power_out_w))
        .collect()
}
