//! The source paper's motor, docs/physics.md §1: the only copy of its numbers in the libraries
//! ([`crate::Motor::paper`] assembles them).

/// Operating frequency f (Hz).
pub const FREQUENCY_HZ: f64 = 9.61e6;
/// Normal vibration amplitude A_n (m) at 125 V(0-p).
pub const NORMAL_AMPLITUDE_M: f64 = 20e-9;
/// Tangential vibration velocity amplitude V_t = A_t ω (m/s).
pub const TANGENTIAL_VELOCITY_M_PER_S: f64 = 1.1;
/// Rayleigh wave speed on the free surface of 128° YX LiNbO3 (m/s).
pub const PHASE_VELOCITY_M_PER_S: f64 = 3979.0;
/// Aperture of the paper's IDT: the width of the wave's beam across y (m).
pub const APERTURE_M: f64 = 9e-3;
/// Finger pairs of the paper's IDT (section 3, Fig. 4).
pub const IDT_FINGER_PAIRS: u32 = 20;
/// Finger width of the paper's IDT (m).
pub const IDT_FINGER_WIDTH_M: f64 = 100e-6;
/// Gap between neighbouring fingers of the paper's IDT (m); period 2(w + g) = 400 µm.
pub const IDT_GAP_M: f64 = 100e-6;
/// The paper's drive: peak voltage on the IDT, V₀₋ₚ (V), for its 20 nm and 70 W.
pub const DRIVE_VOLTAGE_PEAK_V: f64 = 125.0;
/// The stator's crystal cut: 128° rotated Y-cut LiNbO3, X propagation (crate `saw-wave`'s name).
pub const STATOR_CUT: &str = "128yx-linbo3";
/// The crystal constant set of [`STATOR_CUT`] (crate `saw-wave`'s name).
pub const STATOR_CRYSTAL: &str = "LiNbO3 (Kovacs et al. 1990)";
/// ZXZ Euler angles (φ, θ, ψ) of the wave frame of [`STATOR_CUT`] (degrees): a θ_Y-rotated
/// Y-cut with X propagation is (0°, θ_Y − 90°, 0°).
pub const STATOR_CUT_EULER_DEG: [f64; 3] = [0.0, 38.0, 0.0];
/// Slider side, square (m).
pub const SLIDER_SIDE_M: f64 = 5e-3;
/// Slider body thickness (m).
pub const SLIDER_THICKNESS_M: f64 = 0.5e-3;
/// Side of the square post array (m).
pub const ARRAY_SIDE_M: f64 = 4e-3;
/// Posts per side of the array.
pub const POSTS_PER_SIDE: u32 = 100;
/// Post pitch, array side / posts per side (m).
pub const PITCH_M: f64 = ARRAY_SIDE_M / POSTS_PER_SIDE as f64;
/// Post diameter d (m).
pub const POST_DIAMETER_M: f64 = 20e-6;
/// Post height h (m).
pub const POST_HEIGHT_M: f64 = 2e-6;
/// Friction coefficient μ (static = kinetic).
pub const FRICTION_COEFFICIENT: f64 = 0.3;
/// Preload P (N).
pub const PRELOAD_N: f64 = 40.0;
/// The paper's effective contact ratio η = 0.36 (its FEM's 36 % of posts in contact).
pub const EFFECTIVE_RATIO: f64 = 0.36;
