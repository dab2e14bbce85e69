//! The limits every part of a run checks against — memory (the layout's positions in `slider`,
//! the records and histories in `cost`) and work (the defaults of `scene::SolveOptions`): a
//! leaf module, so that the slider and the scene, which the cost estimate reads, do not import
//! the cost estimate back.

/// Largest memory a run may hold in its per-period records, histories, curve and layout
/// (bytes). Default 1 GiB: the default transient (1000 periods) needs ≈ 0.2 MB.
pub const MAX_RUN_MEMORY_BYTES: f64 = 1024.0 * 1024.0 * 1024.0;
/// Largest estimated work of a run in post-steps (one phase group advanced by one time step).
/// Default 2·10¹⁰: a few minutes at ≈ 10⁸ post-steps/s (the default return-mapping transient
/// of the 10 × 10-post scene, `sawdrive dynamic tests/scenes/small-strip.toml --set
/// effective_ratio=0.36`, is estimated at ≤ 7.7·10⁷ post-steps and takes ≈ 1 s); the
/// automatic `regularized` step on that scene is estimated at 2·10¹¹ and refused.
pub const MAX_POST_STEPS: f64 = 2e10;
