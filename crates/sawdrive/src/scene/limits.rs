//! The bounds of every scene count and imperfection: one place, each with its reason.
//!
//! A count bounds memory and time before anything is allocated (a message gives the estimate);
//! an imperfection or coefficient is bounded by the range where the models hold:
//! * post-height scatter σ ≤ h/3 (three σ below nominal still leaves a post of positive height;
//!   beyond, the Gaussian model would give posts of negative height);
//! * |tilt|, |bow| and every height-map value ≤ h, the post height (larger, the slider body
//!   rather than the posts would meet the stator, which no model here describes);
//! * friction coefficients in [0, [`MAX_FRICTION`]] (dry friction between solids: ≈ 0.05–1.5);
//! * a fixed time step of at most T/[`MIN_STEPS_PER_PERIOD`] and at least
//!   T/[`MAX_STEPS_PER_PERIOD`] of the wave period T (the contact arc of a post is a fraction of
//!   a period; a coarser step misses it and silently lowers the thrust);
//! * a decay length of at least one wavelength (a SAW decays over millimetres to centimetres).
//!
//! Bounded where they are used, with a memory estimate: transient `model.transient.periods` and the
//! integrators' total post-steps (`stick_slip`), sweep points (`sweep::file`), Monte Carlo
//! samples (`design::uq`).

use motor::Imperfections;

use super::SceneError;
use crate::units::{Dimension, format_quantity};

/// Posts along either axis of the array (20× the paper's 100): the whole slider's lattice
/// operator holds 4·n_x·n_y complex numbers per FFT array.
pub const MAX_POSTS_PER_AXIS: u32 = 2000;
/// Largest friction coefficient accepted.
pub const MAX_FRICTION: f64 = 2.0;
/// Fewest time steps per wave period (a fixed `model.lumped.time_step` of at most T/16): the coupled
/// model's own minimum, which resolves a post's contact arc.
pub const MIN_STEPS_PER_PERIOD: usize = coupled_dynamics::scene::MIN_STEPS_PER_PERIOD;
/// Most time steps per wave period (coupled `steps_per_period`, or T/`time_step`): 64× the
/// default; the integrators' error is far below the contact solver's tolerance long before.
pub const MAX_STEPS_PER_PERIOD: usize = 16_384;
/// Most points on a speed–thrust curve.
pub const MAX_CURVE_POINTS: u32 = 1000;
/// Most wave snapshot phases of the static stage (4 by default; each is a contact solve).
pub const MAX_PHASES: u32 = 1024;
/// Most contact solver iterations (100 by default).
pub const MAX_ITERATIONS: u32 = 100_000;

fn invalid(field: &str, message: String) -> SceneError {
    SceneError::Invalid {
        field: field.to_owned(),
        message,
    }
}

fn length(value_m: f64) -> String {
    format_quantity(value_m, Dimension::Length)
}

/// A count at most `max`; the message says what the count costs (`what`, e.g. "contact solves").
pub(super) fn at_most(field: &str, value: u64, max: u64, what: &str) -> Result<(), SceneError> {
    if value <= max {
        return Ok(());
    }
    Err(invalid(
        field,
        format!("{value} is more than the {max} accepted ({value} {what})"),
    ))
}

/// The post counts, before any lattice or mesh is built.
pub(super) fn post_counts(count_x: u32, count_y: u32) -> Result<(), SceneError> {
    if count_x.max(count_y) <= MAX_POSTS_PER_AXIS {
        return Ok(());
    }
    let posts = u64::from(count_x) * u64::from(count_y);
    // Two FFT arrays of (2 n_x)(2 n_y) complex f64 per operator (forward and transformed).
    let lattice_gb = posts as f64 * 4.0 * 16.0 * 2.0 / 1e9;
    Err(invalid(
        "posts.count",
        format!(
            "{count_x}x{count_y} = {posts} posts: at most {MAX_POSTS_PER_AXIS} along each axis (the whole slider's lattice operator alone would take ≈ {lattice_gb:.3e} GB)"
        ),
    ))
}

/// A friction coefficient in [0, [`MAX_FRICTION`]].
pub(super) fn friction(field: &str, mu: f64) -> Result<(), SceneError> {
    if mu.is_finite() && (0.0..=MAX_FRICTION).contains(&mu) {
        return Ok(());
    }
    Err(invalid(
        field,
        format!("friction coefficient must lie in [0, {MAX_FRICTION}], got {mu}"),
    ))
}

/// A fixed time step that resolves the wave period T = 1/f.
pub(super) fn time_step(time_step_s: f64, frequency_hz: f64) -> Result<(), SceneError> {
    let period_s = 1.0 / frequency_hz;
    let steps = period_s / time_step_s;
    let (lo, hi) = (MIN_STEPS_PER_PERIOD as f64, MAX_STEPS_PER_PERIOD as f64);
    if (lo..=hi).contains(&steps) {
        return Ok(());
    }
    let time = |t: f64| format_quantity(t, Dimension::Time);
    Err(invalid(
        "model.lumped.time_step",
        format!(
            "{} is T/{steps:.3} of the wave period T = {}: give a step between T/{MAX_STEPS_PER_PERIOD} = {} and T/{MIN_STEPS_PER_PERIOD} = {} (a coarser step misses the posts' contact arcs), or \"auto\"",
            time(time_step_s),
            time(period_s),
            time(period_s / hi),
            time(period_s / lo)
        ),
    ))
}

/// Time steps per period (key `field`: the coupled model's or the ball's) within
/// [[`MIN_STEPS_PER_PERIOD`], [`MAX_STEPS_PER_PERIOD`]].
pub(super) fn steps_per_period(field: &str, n: u32) -> Result<(), SceneError> {
    if (MIN_STEPS_PER_PERIOD..=MAX_STEPS_PER_PERIOD).contains(&(n as usize)) {
        return Ok(());
    }
    Err(invalid(
        field,
        format!(
            "{n} is outside {MIN_STEPS_PER_PERIOD} to {MAX_STEPS_PER_PERIOD} (fewer cannot resolve a post's contact arc; more changes nothing but the time)"
        ),
    ))
}

/// A decay length of at least one wavelength.
pub(super) fn decay_length(decay_length_m: f64, wavelength_m: f64) -> Result<(), SceneError> {
    if decay_length_m >= wavelength_m {
        return Ok(());
    }
    Err(invalid(
        "wave.decay_length",
        format!(
            "{} is shorter than the wavelength {}: a surface wave decays over millimetres, give at least one wavelength",
            length(decay_length_m),
            length(wavelength_m)
        ),
    ))
}

/// Scatter σ ≤ h/3; |tilt|, |bow| and |height-map values| ≤ h.
pub(super) fn imperfections(imp: &Imperfections, post_height_m: f64) -> Result<(), SceneError> {
    let sigma_max = post_height_m / 3.0;
    if imp.height_scatter_m > sigma_max {
        return Err(invalid(
            "posts.height_scatter",
            format!(
                "σ = {} is more than a third of the post height {} (three σ below nominal would leave posts of negative height): give at most {}",
                length(imp.height_scatter_m),
                length(post_height_m),
                length(sigma_max)
            ),
        ));
    }
    for (field, value) in [
        ("slider.tilt_x", imp.tilt_x_m),
        ("slider.tilt_y", imp.tilt_y_m),
        ("slider.bow", imp.bow_m),
    ] {
        if value.is_nan() || value.abs() > post_height_m {
            return Err(invalid(
                field,
                format!(
                    "{} exceeds the post height {} in magnitude (the slider body, not its posts, would meet the stator): give at most ±{}",
                    length(value),
                    length(post_height_m),
                    length(post_height_m)
                ),
            ));
        }
    }
    let mut map = imp
        .height_map
        .iter()
        .flat_map(|m| m.height_m.iter().enumerate());
    if let Some((i, h)) = map.find(|(_, h)| h.is_nan() || h.abs() > post_height_m) {
        let file = imp.height_map.as_ref().map_or("", |m| m.file.as_str());
        return Err(invalid(
            "posts.height_map",
            format!(
                "{file}: post {i} (lattice order) has height {}, beyond ± the post height {}",
                length(*h),
                length(post_height_m)
            ),
        ));
    }
    Ok(())
}
