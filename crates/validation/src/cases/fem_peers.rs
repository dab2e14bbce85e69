//! The `fem-peers` case: elastic-fem against peer FEM codes on the punch (scikit-fem with a
//! tuned solver, CalculiX ccx), agreement and time, as `scripts/compare-peers.sh` runs it
//! (validation/fem-peers/README.md). The peers are not dependencies of sawdrive: without them
//! the case is skipped, saying which are missing and where they were looked for
//! ([`missing_peers`]); with them it is run by that script from a checkout (it builds the Python
//! peers' venv, `skfem-venv`, in the target folder).

use std::path::{Path, PathBuf};

use super::{CaseOutcome, Level};

/// The Python modules the scikit-fem peer imports.
const SKFEM_MODULES: &str = "import skfem, meshio, pyamg";

/// The Pythons that may hold scikit-fem, in the order tried: the venv `scripts/compare-peers.sh`
/// makes in the target folder (`target_dir`, i.e. `$CARGO_TARGET_DIR`, else the checkout's
/// `target/`), then `python3` on PATH.
pub fn skfem_pythons(target_dir: Option<&Path>, checkout: Option<&Path>) -> Vec<PathBuf> {
    let venv_python = |target: &Path| target.join("skfem-venv").join("bin").join("python");
    let mut found: Vec<PathBuf> = target_dir.map(venv_python).into_iter().collect();
    if let Some(checkout) = checkout {
        let own = venv_python(&checkout.join("target"));
        if !found.contains(&own) {
            found.push(own);
        }
    }
    found.push(PathBuf::from("python3"));
    found
}

/// The checkout holding `from` (or `from` itself): the first folder upwards with
/// `scripts/compare-peers.sh`.
pub fn checkout_of(from: &Path) -> Option<PathBuf> {
    from.ancestors()
        .find(|dir| dir.join("scripts").join("compare-peers.sh").is_file())
        .map(Path::to_path_buf)
}

/// Whether `program args…` runs and exits with success.
fn runs(program: &Path, args: &[&str]) -> bool {
    std::process::Command::new(program)
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// The first of `pythons` that imports scikit-fem, meshio and pyamg.
pub fn python_with_skfem(pythons: &[PathBuf]) -> Option<&PathBuf> {
    pythons.iter().find(|p| runs(p, &["-c", SKFEM_MODULES]))
}

/// The peers `compare-peers.sh` needs that are not found (`ccx` on PATH; scikit-fem with meshio
/// and pyamg in the target folder's `skfem-venv` or `python3`), each naming where it was looked
/// for; and the Python that has scikit-fem, when one does.
pub fn missing_peers() -> (Vec<String>, Option<PathBuf>) {
    let on_path = |program: &str| {
        std::env::var_os("PATH")
            .is_some_and(|path| std::env::split_paths(&path).any(|dir| dir.join(program).is_file()))
    };
    let mut missing = Vec::new();
    if !on_path("ccx") {
        missing.push("CalculiX ccx, not on PATH (apt-get install calculix-ccx)".to_string());
    }
    let target = std::env::var_os("CARGO_TARGET_DIR").map(PathBuf::from);
    let checkout = std::env::current_dir().ok().and_then(|d| checkout_of(&d));
    let pythons = skfem_pythons(target.as_deref(), checkout.as_deref());
    let skfem = python_with_skfem(&pythons).cloned();
    if skfem.is_none() {
        let tried: Vec<String> = pythons.iter().map(|p| p.display().to_string()).collect();
        missing.push(format!(
            "scikit-fem with meshio and pyamg, in none of {} (scripts/compare-peers.sh makes \
             target/skfem-venv with pip)",
            tried.join(", ")
        ));
    }
    (missing, skfem)
}

/// The case at `level`: skipped, naming the missing peers or the script that compares them.
pub fn run(level: Level) -> CaseOutcome {
    let (missing, skfem) = missing_peers();
    let reason = match skfem {
        Some(python) if missing.is_empty() => format!(
            "peers found (ccx, scikit-fem in {}); the comparison runs from a checkout: \
             scripts/compare-peers.sh LEVEL (validation/fem-peers/README.md)",
            python.display()
        ),
        _ => format!("peers not installed: {}", missing.join("; ")),
    };
    CaseOutcome {
        case: "fem-peers".into(),
        level,
        checks: Vec::new(),
        skipped: Some(reason),
        wall_s: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn target_dir_venv_is_tried_before_the_checkouts_and_python3_last() {
        let pythons = skfem_pythons(Some(Path::new("/t")), Some(Path::new("/repo")));
        assert_eq!(
            pythons,
            [
                PathBuf::from("/t/skfem-venv/bin/python"),
                PathBuf::from("/repo/target/skfem-venv/bin/python"),
                PathBuf::from("python3"),
            ]
        );
    }

    #[test]
    fn checkout_target_is_tried_once_when_it_is_the_target_dir() {
        let pythons = skfem_pythons(Some(Path::new("/repo/target")), Some(Path::new("/repo")));
        assert_eq!(
            pythons,
            [
                PathBuf::from("/repo/target/skfem-venv/bin/python"),
                PathBuf::from("python3"),
            ]
        );
        assert_eq!(skfem_pythons(None, None), [PathBuf::from("python3")]);
    }

    #[test]
    fn checkout_is_found_from_a_folder_inside_it() {
        let root = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(root.path().join("scripts")).unwrap();
        std::fs::write(root.path().join("scripts/compare-peers.sh"), "").unwrap();
        let inside = root.path().join("crates/validation");
        std::fs::create_dir_all(&inside).unwrap();
        assert_eq!(checkout_of(&inside).as_deref(), Some(root.path()));
        let elsewhere = tempfile::tempdir().unwrap();
        assert_eq!(checkout_of(elsewhere.path()), None);
    }

    #[test]
    fn a_python_that_does_not_exist_has_no_skfem() {
        let pythons = [PathBuf::from("/nonexistent/skfem-venv/bin/python")];
        assert_eq!(python_with_skfem(&pythons), None);
    }
}
