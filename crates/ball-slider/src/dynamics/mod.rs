//! The steel ball driven by the Rayleigh wave: dynamics, periodic steady state, speed–thrust
//! curve and its energy books.
//!
//! **Model.** The stator's surface point under the ball moves on the retrograde ellipse of
//! docs/physics.md §4 (stick-slip's and motor's `Wave`): w = A_n sin θ, u = A_t cos θ,
//! θ = ωt − kx_b (x_b the ball's position; the Doppler shift of the phase kept, as in
//! stick-slip). The ball (mass m, rigid body translation; it is held in its slider and does not
//! roll) carries the preload P downward and the external load L opposing the drive. Contact:
//! * normal — Hertz, N = (4/3)E*√R δ₊^{3/2}, δ = w − z_b (z_b the height of the ball's lowest
//!   point); δ ≤ 0 is a flight phase (N = 0), the tangential memory is then lost;
//! * tangential — the Mindlin–Deresiewicz partial-slip memory as an MDR/Iwan spring bed
//!   ([`crate::iwan`]): exact Mindlin curve and Masing loops for constant N, and the
//!   Cattaneo–Mindlin-type response for N and Q varying together; sliding when every spring
//!   in contact slips (|Q| = μN). The relative displacement rate is ∂u/∂t − ẋ_b.
//!
//! m ẍ_b = Q + L (drive along −x, so L ≥ 0 acts along +x), m z̈_b = N − P.
//!
//! **Steady state.** The ball's speed ripple within a period is (μP/m)·(2π/ω), ≈ 1e-5 of its
//! speed for the default 2 mm ball, and its contact resonance ω_c = √(k/m) ≈ 10⁻³ω: the
//! ball neither follows the wave vertically nor changes speed within a period. Its periodic
//! steady state is therefore found in two steps: (1) at an imposed drive speed V, the
//! contact's periodic state with the ball held at the height z_eq where the period-mean normal
//! force is P (from a bed saturated in the forward-sliding direction: by the monotonicity of
//! the return mapping the orbit is reached within one period) gives the mean thrust T(V);
//! (2) the free ball (its mass, the load L = T(V), the preload, vertical motion, contact loss)
//! is integrated over `numerics.free_periods` periods from that state, and the point is steady
//! when the mean speeds of the two halves agree to `numerics.steady_tolerance`. The mean
//! speed reported is the free ball's. A light ball (ω_c not ≪ ω) is integrated the same way;
//! its free run then differs from the imposed one, which the steadiness flag and the
//! `free_speed_m_per_s` column show (tests: from rest, a light ball reaches the speed of the
//! imposed model).
//!
//! **Integrator and step.** Implicit trapezoidal rule (second order, A-stable) on the ball;
//! the normal force is the discrete gradient of Hertz's energy over the step, the tangential
//! force the step mean of the return-mapped bed. Each step is a fixed point on (Δx, Δz),
//! converging while ω_c h ≤ 0.5. The massless interface is rate-independent, so the contact
//! stiffness brings no time scale of its own: the stiff scale is the ball–contact resonance
//! ω_c, far below ω for a ball. The step is `numerics.steps_per_period` per Doppler-shifted
//! period (default 128: the wave's elliptical motion and the slip events resolved;
//! convergence tested), raised where needed so that ω_c h ≤ [`MAX_RESONANCE_STEP`].
//!
//! **Energy books.** Per step, exactly: stator work Q̄Δu + N̄Δw = friction dissipation
//! Σf̄_iΔp_i + work delivered (against L, or to the imposed motion) + Δ(stored energy), stored =
//! kinetic + Hertz + bed + preload potential Pz_b. Over a period: power from the wave =
//! friction power + mechanical power + rate of change of the stored energy; the residual is
//! reported per curve point (measured ≤ 1e-12 relative at imposed speed, ≤ 1e-9 free; tests
//! assert 1e-9 and 1e-7).
//!
//! **Validity.** As for [`crate::hertz`] and [`crate::mindlin`] (β = 0, constant μ), a contact
//! small against the wavelength (ka ≪ 1; the contact radius and ka are reported), the contact
//! normal taken along z (the wave's slope kA_n ≈ 3·10⁻⁵ neglected), the interface massless
//! (quasi-static elasticity: the contact's own elastic waves are far faster than its size
//! over the period), and no rolling.

pub mod attenuation;
mod curve;
mod kernel;
mod run;

pub use attenuation::WaveShare;
pub use curve::{BallModel, BallResult, CurvePoint, FreeCheck, SpeedPoint, StaticSummary, solve};

/// Largest ω_c h (the contact resonance times the step) the step may take. Default 0.5.
pub const MAX_RESONANCE_STEP: f64 = 0.5;
