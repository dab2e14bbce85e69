//! Is the process that left a hidden folder still running?

use std::path::Path;

/// `Some(true)` if process `pid` exists, `Some(false)` if it does not, `None` where this cannot
/// be told (no `/proc`). A PID reused by an unrelated process reads as alive: the folder is then
/// left alone, never wrongly removed.
pub(crate) fn process_alive(pid: u32) -> Option<bool> {
    let proc = Path::new("/proc");
    proc.is_dir().then(|| proc.join(pid.to_string()).exists())
}

/// The PID in a hidden name `.<name>.<kind>-<pid>`, if `file_name` is one.
pub(crate) fn owner_pid(file_name: &str, name: &str, kind: &str) -> Option<u32> {
    file_name
        .strip_prefix(&format!(".{name}.{kind}-"))?
        .parse()
        .ok()
}
