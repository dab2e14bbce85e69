//! Lumped dynamic stick/slip model of the SAW motor (docs/physics.md §4–5).
//!
//! A Rayleigh wave travels along +x on the stator (w = A_n sin θ, u = A_t cos θ, θ = ωt − kx,
//! retrograde orbit); the slider's posts touch it through springs k_n, k_t and Coulomb friction
//! (Jenkins elements), and the slider is driven along −x.
//!
//! * [`DynamicScene`] holds the input (SI): [`Wave`], [`PostContact`], [`Slider`],
//!   [`ModelChoice`], [`Integrator`], [`SolveOptions`]; `validate()` returns typed errors.
//! * [`solve`] runs the model the scene needs and returns a [`DynamicResult`] (serde
//!   `Serialize`): stall thrust, no-load speed, speed–thrust curve, stick fraction, efficiency.
//! * [`PeriodicAverageModel`]: one post period-averaged at imposed speed (closed-form
//!   event-driven segments by default).
//! * [`TransientModel`]: all phase groups and the slider integrated in time.
//! * `plots` (cargo feature `charts`, on by default): SVG/PNG charts of a
//!   result. The validation study (work-precision, stability maps) is in the `validation` crate.
//!
//! Inside the solvers lengths are scaled by A_n, time by 1/ω and forces by k_n A_n per post
//! (N_eff k_n A_n for the slider), so every tolerance is relative.
//!
//! ```
//! use stick_slip::{DynamicScene, solve};
//! // Post springs of a 20 µm post (from Johnson's formulas, computed by another crate).
//! let scene = DynamicScene::paper_default(1.8e6, 1.5e6);
//! let result = solve(&scene).unwrap();
//! assert!(result.stall_thrust_n > 0.0 && result.stall_thrust_n <= 0.3 * 40.0);
//! assert!(result.no_load_speed_m_per_s <= result.crest_speed_m_per_s);
//! ```

mod contact;
mod cost;
mod error;
mod history;
mod integrator;
mod math;
mod mean_normal;
mod periodic;
#[cfg(feature = "charts")]
pub mod plots;
mod post;
mod result;
mod scene;
mod slider;
mod solve;
mod transient;
mod wave;

pub use contact::{PAPER_FRICTION_COEFFICIENT, PostContact};
pub use cost::{MAX_POST_STEPS, MAX_RUN_MEMORY_BYTES, MemoryEstimate, WorkEstimate};
pub use error::{Result, StickSlipError, Warning};
pub use history::{ContactState, PostHistory, SliderHistory};
pub use integrator::{
    EVENT_DRIVEN_STEPS_PER_PERIOD, Integrator, IntegratorKind, RETURN_MAPPING_MIN_STEPS_PER_PERIOD,
    StabilityLimit, StabilityPolicy, StabilitySetting, TRANSIENT_DEFAULT_STEPS_PER_PERIOD,
};
pub use periodic::{PeriodicAverageModel, SpeedSample};
pub use post::stepping::StabilityProbe;
pub use result::{
    CurvePoint, DynamicResult, OperatingPoint, TransientSummary, curve_csv, write_curve_csv,
};
pub use scene::{
    BOUNCE_LIMIT, DynamicScene, HistoryOptions, ModelChoice, ModelKind, PHASE_HARMONICS,
    SPEED_RIPPLE_LIMIT, SolveOptions, TransientOptions, TransientStart,
};
pub use slider::{
    PAPER_EFFECTIVE_RATIO, PAPER_PITCH_M, PAPER_POSTS_PER_SIDE, PAPER_SLIDER_SIDE_M,
    PAPER_SLIDER_THICKNESS_M, PostLayout, Slider, VerticalModel,
};
pub use solve::{
    RunHistories, ShouldStop, solve, solve_with_histories, solve_with_histories_cancellable,
};
pub use transient::{TransientModel, TransientRun};
pub use wave::{Wave, WaveLimits};
