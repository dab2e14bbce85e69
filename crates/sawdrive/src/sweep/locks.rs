//! Sharing the FEM cache `OUT/.cache` between processes (shards of one sweep on a cluster, or two
//! sweeps writing to the same OUT): one FEM condensation per slider geometry in total, never two
//! writers of one mesh.
//!
//! Rule: a process fills the static reports of a geometry only while it holds the exclusive lock
//! `OUT/.cache/locks/geometry-<geometry key>.lock`, and fills them for *every* pending point of
//! the sweep with that geometry (its own and other shards'). A shard first visits its geometries
//! with a non-blocking `try_lock`, skipping those another shard is condensing (visiting them in an
//! order rotated by its shard index, so concurrent shards start on different geometries), then
//! waits on the skipped ones: by then their reports are in the cache and the fill is a set of
//! cache hits. An automatic mesh is generated under the lock of its file,
//! `locks/mesh-<mesh file name>.lock`, because two geometries that differ only in material or
//! wave amplitude share one mesh file.
//!
//! Meshing runs ahead of the condensations: while the calling thread condenses one geometry, up to
//! [`MAX_MESHERS_AHEAD`] threads run gmsh (one thread each: the mesh bytes do not depend on
//! which thread or process made them) for the geometries after it, in the same visiting order.
//! gmsh runs on one core, so on two cores the second is otherwise idle while a mesh is made.
//! Each mesh is made once: a thread that finds a mesh locked waits and then verifies the
//! finished file instead of meshing again.
//!
//! The locks are advisory `flock` locks held by an open file (`std::fs::File::lock`): the
//! kernel releases them when the process exits, so a killed shard leaves no stale lock. On NFS,
//! Linux emulates `flock` with byte-range locks, which NFSv4 (and NFSv3 with lockd) honour across
//! nodes; Lustre needs the `flock` mount option, else locking fails with a named error. Cache files
//! are written atomically (temporary file + rename), so a reader never sees half a file either way.

use std::fs::{File, TryLockError};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use super::error::SweepRunError;
use crate::pipeline::RunControl;
use crate::pipeline::{fill_static_cache, geometry_key, static_params};
use crate::scene::Scene;

/// Folder of the lock files inside the FEM cache.
const LOCK_FOLDER: &str = "locks";

/// Most threads that run gmsh ahead of the condensations (each runs one one-threaded gmsh), at
/// most the machine's cores. Default 2: on the 2-core reference machine meshing the five
/// geometries of the Figs 7–8 sweep then overlaps with their condensations. Unit: threads.
pub const MAX_MESHERS_AHEAD: usize = 2;

/// Open (creating it if needed) the lock file `name` of `cache`.
fn lock_file(cache: &Path, name: &str) -> Result<(File, PathBuf), SweepRunError> {
    let folder = cache.join(LOCK_FOLDER);
    let path = folder.join(name);
    let locked = |source| SweepRunError::Lock {
        path: path.clone(),
        source,
    };
    std::fs::create_dir_all(&folder).map_err(locked)?;
    let file = File::options()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&path)
        .map_err(locked)?;
    Ok((file, path))
}

/// Wait for and take the exclusive lock `name` of `cache`; it is held until the file is dropped.
pub(super) fn lock_exclusive(cache: &Path, name: &str) -> Result<File, SweepRunError> {
    let (file, path) = lock_file(cache, name)?;
    file.lock()
        .map_err(|source| SweepRunError::Lock { path, source })?;
    Ok(file)
}

/// The scenes of one slider geometry.
struct Group {
    /// [`geometry_key`] of the geometry.
    key: String,
    /// Pending scenes with this geometry (any shard's).
    scenes: Vec<Scene>,
    /// Whether a scene of the calling process is among them.
    mine: bool,
}

/// Group the FEM scenes of `pending` (scene, whether the caller runs it) by slider geometry, in
/// order of first appearance. Scenes with a given η or without valid static parameters are left
/// out (their points run, or fail with their own error, without the static cache).
fn groups(pending: &[(Scene, bool)], cache: &Path) -> Vec<Group> {
    let meshes = cache.join("meshes");
    let mut groups: Vec<Group> = Vec::new();
    for (scene, mine) in pending
        .iter()
        .filter(|(s, _)| s.contact.effective_ratio.is_none())
    {
        let Ok(key) = static_params(scene, Some(&meshes)).and_then(|p| geometry_key(&p)) else {
            continue;
        };
        match groups.iter_mut().find(|g| g.key == key) {
            Some(group) => {
                group.scenes.push(scene.clone());
                group.mine |= mine;
            }
            None => groups.push(Group {
                key,
                scenes: vec![scene.clone()],
                mine: *mine,
            }),
        }
    }
    groups.retain(|g| g.mine);
    groups
}

/// Fill the static cache for the geometries of the caller's pending scenes under the geometry
/// locks (see the module text); `rotation` (the shard index) staggers the visiting order.
/// Returns the number of FEM condensations this process ran. A stop request of `control` starts no further
/// geometry (the caller then reports the cancel).
pub(super) fn fill_static_cache_shared(
    pending: &[(Scene, bool)],
    cache: &Path,
    rotation: usize,
    control: &RunControl,
) -> Result<usize, SweepRunError> {
    let mut groups = groups(pending, cache);
    if groups.is_empty() {
        return Ok(0);
    }
    let shift = rotation % groups.len();
    groups.rotate_left(shift);
    let meshers = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(MAX_MESHERS_AHEAD)
        .min(groups.len());
    let next = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        for _ in 0..meshers {
            scope.spawn(|| mesh_ahead(&groups, &next, cache, control));
        }
        let condensed = condense_groups(groups.iter().collect(), cache, control);
        // After an error or a cancel no mesher claims another geometry.
        next.store(groups.len(), Ordering::Relaxed);
        condensed
    })
}

/// Make the meshes of `groups` in order, each taken by the first thread to claim it via `next`,
/// until all are claimed or `control` asks to stop. Errors are left to the condensation, which resolves
/// the mesh again and reports the failure with its scene.
fn mesh_ahead(groups: &[Group], next: &AtomicUsize, cache: &Path, control: &RunControl) {
    loop {
        let i = next.fetch_add(1, Ordering::Relaxed);
        let Some(group) = groups.get(i) else { return };
        if control.should_stop() {
            return;
        }
        let _ = make_mesh(group, cache);
    }
}

/// The condensations of `groups` under their geometry locks: first those no other process holds,
/// then (waiting) the rest. Returns how many condensations this process ran.
fn condense_groups(
    groups: Vec<&Group>,
    cache: &Path,
    control: &RunControl,
) -> Result<usize, SweepRunError> {
    let mut condensations = 0;
    let mut busy = Vec::new();
    for group in groups {
        if control.should_stop() {
            return Ok(condensations);
        }
        let (file, path) = lock_file(cache, &format!("geometry-{}.lock", group.key))?;
        match file.try_lock() {
            Ok(()) => condensations += fill_group(group, cache)?,
            Err(TryLockError::WouldBlock) => busy.push(group),
            Err(TryLockError::Error(source)) => return Err(SweepRunError::Lock { path, source }),
        }
    }
    for group in busy {
        if control.should_stop() {
            return Ok(condensations);
        }
        let _held = lock_exclusive(cache, &format!("geometry-{}.lock", group.key))?;
        condensations += fill_group(group, cache)?;
    }
    Ok(condensations)
}

/// Make (or verify) the automatic mesh of the group's geometry under the lock of its file;
/// nothing for a given or committed mesh or scene parameters that do not validate.
fn make_mesh(group: &Group, cache: &Path) -> Result<(), SweepRunError> {
    let Ok(params) = static_params(&group.scenes[0], Some(&cache.join("meshes"))) else {
        return Ok(());
    };
    let Some(mesh) = static_contact::mesh_source::cached_mesh_path(&params) else {
        return Ok(());
    };
    let name = mesh.file_name().unwrap_or_default().to_string_lossy();
    let _held = lock_exclusive(cache, &format!("mesh-{name}.lock"))?;
    // A meshing error is reported by the condensation, with its scene.
    let _ = static_contact::mesh_source::resolve_mesh_verified(&params);
    Ok(())
}

/// With the group's geometry lock held: make its mesh (unless a mesher thread has), then condense
/// the geometry once and cache a report per scene (nothing if all are cached already).
fn fill_group(group: &Group, cache: &Path) -> Result<usize, SweepRunError> {
    make_mesh(group, cache)?;
    let (built, _failures) = fill_static_cache(&group.scenes, cache);
    Ok(built)
}
