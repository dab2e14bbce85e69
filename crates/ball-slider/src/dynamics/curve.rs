//! The speed–thrust curve of the ball: the imposed-speed periodic state in SI units, the free
//! ball's confirmation of each point, stall thrust, no-load speed, the operating point.

use serde::Serialize;

use crate::dynamics::kernel::{Books, Kernel};
use crate::dynamics::run::{Periodic, free, imposed};
use crate::error::{BallError, Result};
use crate::hertz::{self, HertzContact};
use crate::mindlin::{MindlinContact, effective_shear_modulus_pa};
use crate::scene::BallScene;

/// Drive speed standing for the v → 0⁺ limit, as a fraction of the crest speed A_tω.
/// Default 1e-6.
pub const STALL_SPEED_FRACTION: f64 = 1e-6;
/// Speeds sampled over (0, A_tω] to bracket the no-load speed. Default 16.
const NO_LOAD_SCAN_POINTS: usize = 16;
/// Bisection steps on a bracketed root of the thrust (halves the bracket each). Default 48.
const ROOT_BISECTIONS: usize = 48;

/// The contact's periodic state at an imposed drive speed (SI).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpeedPoint {
    /// Imposed speed along the drive direction (−x) (m/s).
    pub speed_m_per_s: f64,
    /// Period-mean thrust along the drive direction (N).
    pub thrust_n: f64,
    /// Power drawn from the wave through the contact, ⟨Q ∂u/∂t + N ∂w/∂t⟩ (W).
    pub stator_power_w: f64,
    /// Friction dissipation in the contact (W).
    pub friction_power_w: f64,
    /// Mechanical output thrust × speed (W).
    pub mechanical_power_w: f64,
    /// Rate of change of the stored energy over the period (W); zero in a periodic state.
    pub stored_power_w: f64,
    /// (stator − friction − mechanical − stored)/max(|terms|) over the period.
    pub energy_residual: f64,
    /// Mechanical over stator power (0 where the wave delivers nothing).
    pub efficiency: f64,
    /// Period-mean normal force (N): the preload.
    pub mean_normal_force_n: f64,
    /// Fraction of the period in contact (< 1: flight phases).
    pub contact_fraction: f64,
    /// Fraction of the period in gross slip (every spring in contact slipping).
    pub gross_slip_fraction: f64,
    /// Periods integrated to reach the periodic state.
    pub periods: usize,
    /// A/A₀ the ball sees (1 at the constant amplitude; below 1 on the energy-conserving wave).
    pub amplitude_scale: f64,
}

/// The free ball integrated from a curve point's state under that point's thrust as load.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FreeCheck {
    /// Mean speed along the drive direction over the second half of the run (m/s).
    pub speed_m_per_s: f64,
    /// Mean speed over the first half (m/s).
    pub first_half_speed_m_per_s: f64,
    /// |second − first| / max(|second|, 10⁻³ A_tω).
    pub drift: f64,
    /// Whether the drift is below `numerics.steady_tolerance`.
    pub steady: bool,
    /// Periods integrated.
    pub periods: usize,
    /// Power from the wave over the run (W).
    pub stator_power_w: f64,
    /// Friction dissipation (W).
    pub friction_power_w: f64,
    /// Work against the load per time (W).
    pub mechanical_power_w: f64,
    /// Rate of change of the stored energy, kinetic included (W).
    pub stored_power_w: f64,
    /// Books' residual over the run, relative.
    pub energy_residual: f64,
}

/// One point of the speed–thrust curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CurvePoint {
    /// Mean speed along the drive direction (m/s).
    pub speed_m_per_s: f64,
    /// Thrust = the load carried at this speed (N).
    pub thrust_n: f64,
    /// Power from the wave (W).
    pub stator_power_w: f64,
    /// Friction dissipation (W).
    pub friction_power_w: f64,
    /// Mechanical output (W).
    pub mechanical_power_w: f64,
    /// Mechanical / stator power.
    pub efficiency: f64,
    /// Relative residual of the period's energy books.
    pub energy_residual: f64,
    /// Fraction of the period in contact.
    pub contact_fraction: f64,
    /// Fraction of the period in gross slip.
    pub gross_slip_fraction: f64,
    /// A/A₀ the ball sees.
    pub amplitude_scale: f64,
    /// The free ball's confirmation (absent when `numerics.free_periods` is 0).
    pub free: Option<FreeCheck>,
}

/// The static contact under the preload and the numbers that set the dynamics' regime.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StaticSummary {
    /// Hertz contact at the preload.
    pub hertz: HertzContact,
    /// Mindlin's contact at the preload.
    pub mindlin: MindlinContact,
    /// Dundurs' β of the ball–stator pair (neglected by the model).
    pub dundurs_beta: f64,
    /// Moving mass (kg).
    pub ball_mass_kg: f64,
    /// Contact resonance √(max(k_n, k_t)/m)/2π at the deepest approach (Hz).
    pub contact_resonance_hz: f64,
    /// Static approach over the normal wave amplitude, δ₀/A_n.
    pub approach_over_amplitude: f64,
    /// Mindlin's full-slip displacement over the tangential amplitude, 3μP/(16G*a)/A_t.
    pub full_slip_over_tangential_amplitude: f64,
    /// k·a: the contact radius against the wavelength (point contact needs ≪ 1).
    pub contact_wavenumber: f64,
    /// Steps per period used.
    pub steps_per_period: usize,
    /// Springs of the bed.
    pub springs: usize,
    /// Extent of the bed (m).
    pub bed_extent_m: f64,
    /// Height of the ball's lowest point at rest on the waving stator (m; negative: pressed in).
    pub equilibrium_height_m: f64,
}

/// The full result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BallResult {
    /// The static contact.
    pub static_contact: StaticSummary,
    /// Whether the wave drives the ball (thrust at 0⁺ > 0).
    pub drives: bool,
    /// Thrust at v → 0⁺ (N); negative: the ball needs a push to move forward.
    pub zero_speed_thrust_n: f64,
    /// Stall thrust max(thrust at 0⁺, 0) (N).
    pub stall_thrust_n: f64,
    /// No-load speed (m/s); 0 where the wave does not drive the ball.
    pub no_load_speed_m_per_s: f64,
    /// Crest speed A_tω (m/s), the bound of the no-load speed.
    pub crest_speed_m_per_s: f64,
    /// μP (N), the bound of the thrust.
    pub friction_limit_n: f64,
    /// Largest mechanical power on the curve (W).
    pub max_mechanical_power_w: f64,
    /// Largest efficiency on the curve.
    pub max_efficiency: f64,
    /// Stall to no load.
    pub curve: Vec<CurvePoint>,
    /// The steady state at the scene's external load; `None` if the ball does not move.
    pub operating_point: Option<CurvePoint>,
    /// Every free check steady.
    pub all_steady: bool,
    /// Largest energy residual over the curve (imposed and free books).
    pub max_energy_residual: f64,
}

/// The ball model of one scene.
#[derive(Debug, Clone)]
pub struct BallModel {
    scene: BallScene,
    kernel: Kernel,
    /// The last settled A/A₀, the next fixed point's warm start (energy-conserving wave).
    last_alpha: std::cell::Cell<Option<f64>>,
}

fn relative_residual(stator: f64, friction: f64, mech: f64, stored: f64) -> f64 {
    let scale = stator
        .abs()
        .max(friction.abs())
        .max(mech.abs())
        .max(stored.abs());
    if scale == 0.0 {
        0.0
    } else {
        (stator - friction - mech - stored) / scale
    }
}

impl BallModel {
    /// Validate the scene and set up the solver.
    pub fn new(scene: &BallScene) -> Result<Self> {
        Ok(Self {
            scene: scene.clone(),
            kernel: Kernel::new(scene)?,
            last_alpha: std::cell::Cell::new(None),
        })
    }

    /// The scene.
    pub fn scene(&self) -> &BallScene {
        &self.scene
    }

    /// Crest speed A_tω (m/s).
    pub fn crest_speed_m_per_s(&self) -> f64 {
        self.scene.wave.crest_speed_m_per_s()
    }

    /// The static contact and regime numbers.
    pub fn static_summary(&self) -> Result<StaticSummary> {
        let s = &self.scene;
        let e_star = hertz::effective_modulus_pa(&s.ball.material, &s.stator);
        let g_star = effective_shear_modulus_pa(&s.ball.material, &s.stator);
        let h = HertzContact::new(s.ball.radius_m(), e_star, s.preload_n)?;
        let m = MindlinContact::new(h, s.friction_coefficient, g_star)?;
        let k = &self.kernel;
        Ok(StaticSummary {
            hertz: h,
            mindlin: m,
            dundurs_beta: hertz::dundurs_beta(&s.ball.material, &s.stator),
            ball_mass_kg: s.ball.mass_kg(),
            contact_resonance_hz: k.resonance_rad_per_s / (2.0 * std::f64::consts::PI),
            approach_over_amplitude: h.approach_m / s.wave.normal_amplitude_m,
            full_slip_over_tangential_amplitude: m.full_slip_displacement_m()
                / s.wave.tangential_amplitude_m,
            contact_wavenumber: s.wave.wavenumber_rad_per_m() * h.contact_radius_m,
            steps_per_period: k.steps,
            springs: k.bed.len(),
            bed_extent_m: k.bed_extent_m,
            equilibrium_height_m: k.z_eq * k.length_m,
        })
    }

    fn periodic(&self, speed_m_per_s: f64) -> Result<Periodic> {
        let speed = crate::error::non_negative("drive speed (m/s)", speed_m_per_s)?;
        imposed(&self.kernel, speed / self.kernel.speed_unit_m_per_s())
    }

    /// The contact's periodic state at imposed drive speed V ≥ 0 (m/s): at A₀, or with the
    /// scene's wave share at the amplitude of the energy-conserving wave's fixed point
    /// ([`crate::dynamics::attenuation`]).
    pub fn at_speed(&self, speed_m_per_s: f64) -> Result<SpeedPoint> {
        let Some(share) = self.scene.wave_share else {
            return self.at_speed_constant(speed_m_per_s);
        };
        let (alpha, point) = share.settle(self.last_alpha.get(), |alpha| {
            // At α = 1 (every fixed point's first evaluation) the scene's own kernel serves.
            let point = if alpha == 1.0 {
                self.at_speed_constant(speed_m_per_s)?
            } else {
                self.at_amplitude(alpha)?.at_speed_constant(speed_m_per_s)?
            };
            Ok((point.stator_power_w, point))
        })?;
        self.last_alpha.set(Some(alpha));
        Ok(SpeedPoint {
            amplitude_scale: alpha,
            ..point
        })
    }

    /// The constant-amplitude model of this scene at αA₀.
    fn at_amplitude(&self, alpha: f64) -> Result<BallModel> {
        let mut scene = self
            .scene
            .clone()
            .with_normal_amplitude(alpha * self.scene.wave.normal_amplitude_m);
        scene.wave_share = None;
        BallModel::new(&scene)
    }

    /// The periodic state at V at the scene's own amplitude.
    fn at_speed_constant(&self, speed_m_per_s: f64) -> Result<SpeedPoint> {
        let p = self.periodic(speed_m_per_s)?;
        Ok(self.speed_point(speed_m_per_s, &p.books, p.stored_change, p.periods))
    }

    fn speed_point(&self, speed: f64, b: &Books, stored: f64, periods: usize) -> SpeedPoint {
        let k = &self.kernel;
        let pu = k.power_unit_w() / b.time;
        let stator = (b.stator_tangential + b.stator_normal) * pu;
        let friction = b.dissipation * pu;
        let mech = b.output * pu;
        let stored = stored * pu;
        SpeedPoint {
            speed_m_per_s: speed,
            thrust_n: -b.force_time / b.time * k.force_n,
            stator_power_w: stator,
            friction_power_w: friction,
            mechanical_power_w: mech,
            stored_power_w: stored,
            energy_residual: relative_residual(stator, friction, mech, stored),
            efficiency: if stator > 0.0 { mech / stator } else { 0.0 },
            mean_normal_force_n: b.normal_time / b.time * k.force_n,
            contact_fraction: b.contact_time / b.time,
            gross_slip_fraction: b.gross_slip_time / b.time,
            periods,
            amplitude_scale: 1.0,
        }
    }

    /// Integrate the free ball from the periodic state at V under load `load_n` (N, along
    /// +x, i.e. opposing the drive) for `periods` periods.
    pub fn free_check(&self, speed_m_per_s: f64, load_n: f64, periods: usize) -> Result<FreeCheck> {
        let p = self.periodic(speed_m_per_s)?;
        let k = &self.kernel;
        let drive = speed_m_per_s / k.speed_unit_m_per_s();
        let h = k.period(drive) / k.steps as f64;
        let half = (periods.max(2) / 2) * k.steps;
        let mut s = p.state;
        let load = load_n / k.force_n;
        let (b1, e1) = free(k, &mut s, load, h, half)?;
        let (b2, e2) = free(k, &mut s, load, h, half)?;
        let su = k.speed_unit_m_per_s();
        let (v1, v2) = (-b1.distance / b1.time * su, -b2.distance / b2.time * su);
        let drift = (v2 - v1).abs() / v2.abs().max(1e-3 * self.crest_speed_m_per_s());
        let pu = k.power_unit_w() / (b1.time + b2.time);
        let stator =
            (b1.stator_tangential + b1.stator_normal + b2.stator_tangential + b2.stator_normal)
                * pu;
        let friction = (b1.dissipation + b2.dissipation) * pu;
        let mech = (b1.output + b2.output) * pu;
        let stored = (e1 + e2) * pu;
        Ok(FreeCheck {
            speed_m_per_s: v2,
            first_half_speed_m_per_s: v1,
            drift,
            steady: drift <= self.scene.numerics.steady_tolerance,
            periods: 2 * (periods.max(2) / 2),
            stator_power_w: stator,
            friction_power_w: friction,
            mechanical_power_w: mech,
            stored_power_w: stored,
            energy_residual: relative_residual(stator, friction, mech, stored),
        })
    }

    /// Mean drive speed per period of the free ball started at rest (released bed, height
    /// z_eq) under load `load_n`, over `periods` periods (m/s each).
    pub fn from_rest(&self, load_n: f64, periods: usize) -> Result<Vec<f64>> {
        let k = &self.kernel;
        let h = k.period(0.0) / k.steps as f64;
        let mut s = k.start(0.0, false);
        let su = k.speed_unit_m_per_s();
        (0..periods)
            .map(|_| {
                let (b, _) = free(k, &mut s, load_n / k.force_n, h, k.steps)?;
                Ok(-b.distance / b.time * su)
            })
            .collect()
    }

    /// The curve point at V: the periodic state and, if asked, its free check.
    pub fn curve_point(&self, speed_m_per_s: f64) -> Result<CurvePoint> {
        let p = self.at_speed(speed_m_per_s)?;
        let periods = self.scene.numerics.free_periods;
        let free = match (periods, self.scene.wave_share) {
            (0, _) => None,
            (_, None) => Some(self.free_check(speed_m_per_s, p.thrust_n, periods)?),
            (_, Some(_)) => Some(self.at_amplitude(p.amplitude_scale)?.free_check(
                speed_m_per_s,
                p.thrust_n,
                periods,
            )?),
        };
        Ok(CurvePoint {
            speed_m_per_s: free.map_or(p.speed_m_per_s, |f| f.speed_m_per_s),
            thrust_n: p.thrust_n,
            stator_power_w: p.stator_power_w,
            friction_power_w: p.friction_power_w,
            mechanical_power_w: p.mechanical_power_w,
            efficiency: p.efficiency,
            energy_residual: p.energy_residual,
            contact_fraction: p.contact_fraction,
            gross_slip_fraction: p.gross_slip_fraction,
            amplitude_scale: p.amplitude_scale,
            free,
        })
    }

    /// The speed standing for 0⁺ (m/s).
    pub fn stall_speed_m_per_s(&self) -> f64 {
        STALL_SPEED_FRACTION * self.crest_speed_m_per_s()
    }

    /// Thrust at imposed speed V (N).
    pub fn thrust_n(&self, speed_m_per_s: f64) -> Result<f64> {
        Ok(self.at_speed(speed_m_per_s)?.thrust_n)
    }

    /// The drive speed in (V_lo, V_hi] where thrust − load changes sign (bisection).
    fn bisect(&self, mut lo: f64, mut hi: f64, load_n: f64) -> Result<f64> {
        for _ in 0..ROOT_BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if self.thrust_n(mid)? > load_n {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Ok(0.5 * (lo + hi))
    }

    /// The no-load speed: the first root of the thrust above 0⁺ (m/s); `None` if the thrust
    /// at 0⁺ is not positive.
    pub fn no_load_speed_m_per_s(&self) -> Result<Option<f64>> {
        self.speed_at_load_n(0.0)
    }

    /// The drive speed at which the thrust equals `load_n` (first crossing above 0⁺); `None`
    /// if the thrust at 0⁺ does not exceed the load (the ball stays put).
    pub fn speed_at_load_n(&self, load_n: f64) -> Result<Option<f64>> {
        let v_min = self.stall_speed_m_per_s();
        if self.thrust_n(v_min)? <= load_n {
            return Ok(None);
        }
        let crest = self.crest_speed_m_per_s();
        let mut lo = v_min;
        for i in 1..=NO_LOAD_SCAN_POINTS {
            let v = crest * i as f64 / NO_LOAD_SCAN_POINTS as f64;
            if self.thrust_n(v)? <= load_n {
                return self.bisect(lo, v, load_n).map(Some);
            }
            lo = v;
        }
        Err(BallError::NoSteadyState {
            what: format!(
                "thrust still above the load {load_n} N at the crest speed {crest} m/s: no steady speed below it"
            ),
        })
    }
}

/// Solve the scene: static contact, stall thrust, no-load speed, the curve with its free
/// checks, and the operating point at the scene's external load.
pub fn solve(scene: &BallScene) -> Result<BallResult> {
    let model = BallModel::new(scene)?;
    let static_contact = model.static_summary()?;
    let v_min = model.stall_speed_m_per_s();
    let zero_speed_thrust = model.thrust_n(v_min)?;
    let no_load = model.no_load_speed_m_per_s()?;
    let mut curve = Vec::new();
    if let Some(v0) = no_load {
        let n = scene.numerics.curve_points;
        for j in 0..n {
            let v = v_min + (v0 - v_min) * j as f64 / (n - 1) as f64;
            curve.push(model.curve_point(v)?);
        }
    }
    let operating_point = match model.speed_at_load_n(scene.external_load_n)? {
        Some(v) => Some(model.curve_point(v)?),
        None => None,
    };
    let all = curve.iter().chain(operating_point.iter());
    let all_steady = all.clone().all(|p| p.free.is_none_or(|f| f.steady));
    let max_energy_residual = all
        .flat_map(|p| {
            [
                p.energy_residual.abs(),
                p.free.map_or(0.0, |f| f.energy_residual.abs()),
            ]
        })
        .fold(0.0, f64::max);
    Ok(BallResult {
        static_contact,
        drives: zero_speed_thrust > 0.0,
        zero_speed_thrust_n: zero_speed_thrust,
        stall_thrust_n: zero_speed_thrust.max(0.0),
        no_load_speed_m_per_s: no_load.unwrap_or(0.0),
        crest_speed_m_per_s: model.crest_speed_m_per_s(),
        friction_limit_n: scene.friction_coefficient * scene.preload_n,
        max_mechanical_power_w: curve
            .iter()
            .map(|p| p.mechanical_power_w)
            .fold(0.0, f64::max),
        max_efficiency: curve.iter().map(|p| p.efficiency).fold(0.0, f64::max),
        curve,
        operating_point,
        all_steady,
        max_energy_residual,
    })
}
