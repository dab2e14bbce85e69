#![doc = include_str!("../README.md")]

pub mod attenuation;
mod contact;
mod cost;
mod error;
mod history;
mod integrator;
mod limits;
mod math;
mod mean_normal;
mod model_kind;
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

pub use attenuation::{
    AttenuatedPeriodicModel, AttenuatedResult, AttenuatedRun, AttenuatedSample,
    AttenuatedTransientResult, AttenuationOptions, AttenuationSetting, ProfileIteration,
};
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
pub use run_control::RunControl;
pub use scene::{
    BOUNCE_LIMIT, DynamicScene, HistoryOptions, ModelChoice, ModelKind, PHASE_HARMONICS,
    SPEED_RIPPLE_LIMIT, SolveOptions, TransientOptions, TransientStart,
};
pub use slider::{
    PAPER_EFFECTIVE_RATIO, PAPER_PITCH_M, PAPER_POSTS_PER_SIDE, PAPER_SLIDER_SIDE_M,
    PAPER_SLIDER_THICKNESS_M, PostLayout, Slider, VerticalModel,
};
pub use solve::{RunHistories, solve, solve_with_histories};
pub use transient::{TransientModel, TransientRun};
pub use wave::{Wave, WaveLimits};
