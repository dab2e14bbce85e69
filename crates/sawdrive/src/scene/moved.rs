//! Keys that moved: an old spelling is refused with an error that names its new one (every file
//! in the repository is migrated; a user's old file fails once, with the fix in the message).
//!
//! `[model]` keeps the choice (`dynamics`, `lumped_tolerance`) and the curve (`curve_points`);
//! each model's own settings moved into its sub-table (`[model.lumped]`, `[model.transient]`,
//! `[model.coupled]`, `[model.ball]`), where `deny_unknown_fields` refuses a misplaced key.

use toml::Table;

use super::SceneError;

/// Old scene keys and their new spellings.
pub const MOVED_SCENE_KEYS: [(&str, &str); 7] = [
    ("model.integrator", "model.lumped.integrator"),
    ("model.time_step", "model.lumped.time_step"),
    (
        "model.regularization_velocity",
        "model.lumped.regularization_velocity",
    ),
    ("model.vertical", "model.lumped.vertical"),
    (
        "model.vertical_damping_ratio",
        "model.lumped.vertical_damping_ratio",
    ),
    ("model.periods", "model.transient.periods"),
    (
        "model.steps_per_period",
        "model.coupled.steps_per_period (model.ball.steps_per_period for a ball)",
    ),
];

/// Refuse an old scene key in the merged scene `table` (from `origin`), naming its new spelling.
pub(super) fn check_scene_keys(table: &Table, origin: &str) -> Result<(), SceneError> {
    match motor::input::first_moved(table, &MOVED_SCENE_KEYS) {
        None => Ok(()),
        Some(e) => Err(SceneError::Field {
            origin: origin.to_owned(),
            field: e.field,
            message: e.message,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_old_model_key_is_refused_naming_its_new_spelling() {
        let table: Table = "[model]\nsteps_per_period = 96\n".parse().unwrap();
        let e = check_scene_keys(&table, "s.toml").unwrap_err().to_string();
        assert!(e.contains("model.steps_per_period"), "{e}");
        assert!(e.contains("model.coupled.steps_per_period"), "{e}");
        let table: Table = "[model.coupled]\nsteps_per_period = 96\n".parse().unwrap();
        assert!(check_scene_keys(&table, "s.toml").is_ok());
    }
}
