//! The one gmsh runner of the workspace: mesh a `.geo` file with `-setnumber` parameters into an
//! MSH 4.1 file (binary or ASCII), on one thread so that a parameter set always gives the same
//! mesh, written under a temporary name beside the target and renamed into place only when gmsh
//! succeeded (an interrupted or failed run never leaves a partial mesh under the target name).
//! `scripts/mesh.sh` runs the same command for people at a shell.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::error::{MeshError, Result};

/// Environment variable naming the gmsh binary (as in `scripts/mesh.sh`).
pub const GMSH_ENV: &str = "GMSH";
/// Lines of gmsh's output quoted in an error when it printed no `Error` line. Default 10.
pub const LOG_TAIL_LINES: usize = 10;

/// How gmsh is run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GmshOptions {
    /// The gmsh program: default `$GMSH`, else `gmsh` on the PATH.
    pub program: PathBuf,
    /// MSH 4.1 binary (default) or ASCII.
    pub binary: bool,
    /// Meshing threads. Default 1: reproducible meshes.
    pub threads: u32,
}

impl Default for GmshOptions {
    fn default() -> Self {
        Self {
            program: std::env::var_os(GMSH_ENV).map_or_else(|| "gmsh".into(), PathBuf::from),
            binary: true,
            threads: 1,
        }
    }
}

/// gmsh's `Error` lines, or the last [`LOG_TAIL_LINES`] lines of its output, joined by " | ".
fn log_summary(log: &str) -> String {
    let errors: Vec<&str> = log.lines().filter(|l| l.starts_with("Error")).collect();
    if errors.is_empty() {
        let mut tail: Vec<&str> = log.lines().rev().take(LOG_TAIL_LINES).collect();
        tail.reverse();
        tail.join(" | ")
    } else {
        errors.join(" | ")
    }
}

/// Mesh `geo` in 3D into `out` with `gmsh -setnumber NAME VALUE` for each of `setnumbers`,
/// creating `out`'s folder. Errors: [`MeshError::GmshMissing`] when gmsh cannot be started,
/// [`MeshError::GmshFailed`] (with gmsh's `Error` lines or the tail of its log) when it exits
/// non-zero, prints an `Error` line or writes no mesh, [`MeshError::Io`] for the file system.
pub fn run_geo(
    geo: &Path,
    out: &Path,
    setnumbers: &[(&str, f64)],
    options: &GmshOptions,
) -> Result<()> {
    let io = |path: &Path, action: &str| {
        let path = path.to_path_buf();
        let action = action.to_string();
        move |source| MeshError::Io {
            path,
            action,
            source,
        }
    };
    std::fs::metadata(geo).map_err(io(geo, "reading the geometry"))?;
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io(dir, "creating the mesh folder"))?;
    }
    // gmsh writes the temporary sibling itself; the one atomic writer renames it into place.
    atomic_files::write_atomically_via(out, |tmp| run_gmsh(geo, tmp, out, setnumbers, options))
}

/// Run gmsh on `geo` writing `tmp`; a failure names `out`, the file the caller asked for.
fn run_gmsh(
    geo: &Path,
    tmp: &Path,
    out: &Path,
    setnumbers: &[(&str, f64)],
    options: &GmshOptions,
) -> Result<()> {
    let mut command = Command::new(&options.program);
    command.arg(geo).args(["-3", "-format", "msh41"]);
    if options.binary {
        command.arg("-bin");
    }
    command.arg("-nt").arg(options.threads.max(1).to_string());
    for (name, value) in setnumbers {
        command
            .arg("-setnumber")
            .arg(name)
            .arg(format!("{value:e}"));
    }
    command.arg("-o").arg(tmp);
    die_with_parent(&mut command);
    let output = command.output().map_err(|source| MeshError::GmshMissing {
        geometry: geo.to_path_buf(),
        program: options.program.display().to_string(),
        source,
    })?;
    let log = String::from_utf8_lossy(&output.stdout).into_owned()
        + &String::from_utf8_lossy(&output.stderr);
    let wrote = std::fs::metadata(tmp).is_ok_and(|m| m.len() > 0);
    let status = if !output.status.success() {
        Some(output.status.to_string())
    } else if log.lines().any(|l| l.starts_with("Error")) {
        Some("it reported errors".to_string())
    } else if !wrote {
        Some("it wrote no mesh".to_string())
    } else {
        None
    };
    match status {
        None => Ok(()),
        Some(status) => Err(MeshError::GmshFailed {
            geometry: geo.to_path_buf(),
            out: out.to_path_buf(),
            status,
            log_tail: log_summary(&log),
        }),
    }
}

/// Make the child get SIGKILL when the thread that started it ends (the whole sawdrive process
/// killed, or its meshing thread gone), so that a long gmsh run never outlives the run that
/// asked for it (Linux `prctl(PR_SET_PDEATHSIG)`; elsewhere nothing is changed).
#[cfg(target_os = "linux")]
fn die_with_parent(command: &mut Command) {
    use std::os::unix::process::CommandExt;
    // SAFETY: the closure runs in the forked child before exec and only calls prctl, which is
    // async-signal-safe; it allocates nothing and touches no lock.
    unsafe {
        command.pre_exec(|| {
            if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) == -1 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
}

#[cfg(not(target_os = "linux"))]
fn die_with_parent(_command: &mut Command) {}
