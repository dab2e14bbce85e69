//! The `fem-peers` case: elastic-fem against peer FEM codes on the punch (scikit-fem with a
//! tuned solver, CalculiX ccx), agreement and time, as `scripts/compare-peers.sh` runs it
//! (validation/fem-peers/README.md). The peers are not dependencies of sawdrive: without them
//! the case is skipped, saying which are missing ([`missing_peers`]); with them it is run by
//! that script from a checkout (it builds the Python peers' venv in the target folder).

use super::{CaseOutcome, Level};

/// The peers `compare-peers.sh` needs that are not found: `ccx` on PATH, and a Python with
/// `skfem` (scikit-fem) importable.
pub fn missing_peers() -> Vec<&'static str> {
    let runs = |program: &str, args: &[&str]| {
        std::process::Command::new(program)
            .args(args)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    };
    let on_path = |program: &str| {
        std::env::var_os("PATH")
            .is_some_and(|path| std::env::split_paths(&path).any(|dir| dir.join(program).is_file()))
    };
    let mut missing = Vec::new();
    if !on_path("ccx") {
        missing.push("CalculiX ccx (apt-get install calculix-ccx)");
    }
    if !runs("python3", &["-c", "import skfem"]) {
        missing.push("scikit-fem (pip install scikit-fem meshio pyamg)");
    }
    missing
}

/// The case at `level`: skipped, naming the missing peers or the script that compares them.
pub fn run(level: Level) -> CaseOutcome {
    let missing = missing_peers();
    let reason = if missing.is_empty() {
        "peers found; the comparison runs from a checkout: scripts/compare-peers.sh LEVEL \
         (validation/fem-peers/README.md)"
            .to_string()
    } else {
        format!("peers not installed: {}", missing.join(", "))
    };
    CaseOutcome {
        case: "fem-peers".into(),
        level,
        checks: Vec::new(),
        skipped: Some(reason),
        wall_s: 0.0,
    }
}
