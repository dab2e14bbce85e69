//! Choosing the `slider-strip` mesh of a run: a committed mesh of `meshes/` when its parameters
//! match (embedded in the binary and written into the mesh cache, so that no run reads the
//! checkout), otherwise gmsh ([`gmsh_mesh::gmsh::run_geo`]) on the embedded geometry script
//! ([`gmsh_mesh::geo_scripts`]) into the mesh cache ([`gmsh_mesh::cache::meshes_dir`]), named by a hash
//! of the geometry parameters so that a second run reuses it. Each cached mesh has its SHA-256
//! recorded beside it (`NAME.msh.sha256`) and is verified before reuse: a swapped, edited or
//! truncated cached mesh is regenerated, never used.
//!
//! An automatic Tet10 strip is meshed by gmsh in Tet4 and raised to Tet10 on reading
//! ([`gmsh_mesh::elevate`]: midside nodes on the post cylinders, and on the tip circles imprinted
//! on a stator block, as gmsh's curvilinear order 2 places them, to 1e-15 relative); gmsh's own
//! order elevation took about a quarter of its time. The cache then holds the Tet4 file and
//! every reader goes through [`ResolvedMesh::read`], which elevates it.
//!
//! A strip of an even number of posts along x is meshed by gmsh as its half x ≤ L/2
//! (`slider-strip.geo` `mirror_x`) and reflected into the whole strip on reading
//! ([`gmsh_mesh::mirror`]) before the elevation: the strip is mirror-symmetric about its middle,
//! and gmsh takes about half the time (default strip: 1.8 s instead of 3.9 s).

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use crate::error::{ContactError, Result};
use crate::params::{MeshChoice, StaticParams};
/// Re-exported from [`crate::params`], where the results' content hash needs them.
pub use crate::params::{elevated_in_rust, geometry_source, mirrored_in_rust, rust_mesh_steps};
use crate::scene::StatorModel;

/// Relative tolerance when comparing mesh parameters with a committed mesh's. Default 1e-9.
pub const PARAMETER_MATCH_TOLERANCE: f64 = 1e-9;

/// Committed `slider-strip` meshes (embedded bytes) and the parameters they were made with
/// (meshes/README.md).
#[allow(clippy::type_complexity)]
const COMMITTED: &[(&str, &[u8], &[(&str, f64)])] = &[(
    "slider-strip_p40um_d20um_n10_tet4_10k.msh",
    include_bytes!("../../../meshes/slider-strip_p40um_d20um_n10_tet4_10k.msh"),
    &[
        ("pitch", 40e-6),
        ("d", 20e-6),
        ("h", 2e-6),
        ("t", 0.5e-3),
        ("n_posts", 10.0),
        ("rows", 1.0),
        ("margin", 0.0),
        ("stator_depth", 1e-3),
        ("h_post", 2.5e-6),
        ("h_body", 100e-6),
        ("growth", 0.3),
        ("order", 1.0),
        ("periodic_x", 0.0),
    ],
)];

/// The checkout this crate was built in (`$SAWDRIVE_ROOT` overrides): for tests and development
/// tools that read committed files. No run-time path goes through it (runs use the embedded
/// scripts and meshes and the cache folder), so a binary used elsewhere never looks here.
pub fn workspace_root() -> PathBuf {
    std::env::var_os("SAWDRIVE_ROOT").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."),
        PathBuf::from,
    )
}

/// The mirror plane of a half strip (`slider-strip.geo` with `mirror_x = 1`): its cut faces, and
/// the end faces x = 0 whose images are the ends x = L (tags as in the whole strip's script),
/// of the slider and, with a meshed stator block, of the stator.
pub fn strip_mirror_plane(params: &StaticParams) -> gmsh_mesh::mirror::MirrorPlane {
    let mut bodies = vec![("slider", 16)];
    if params.stator == StatorModel::MeshedBlock {
        bodies.push(("stator", 26));
    }
    gmsh_mesh::mirror::MirrorPlane {
        groups: bodies
            .iter()
            .map(|(b, _)| format!("{b}_mirror_x"))
            .collect(),
        renames: bodies
            .iter()
            .map(|&(b, tag)| gmsh_mesh::mirror::MirrorRename {
                from: format!("{b}_x0"),
                to: format!("{b}_x1"),
                tag,
            })
            .collect(),
    }
}

/// The gmsh `-setnumber` parameters of the strip mesh file the run needs (`order` = 1 when the
/// Tet10 mesh is elevated in Rust, [`elevated_in_rust`]). A one-row strip is meshed as its half
/// y ≤ W/2 (`half_y`): the plane through the post axes is a mirror plane of the geometry and of a
/// load uniform in y, so the half with a symmetry plane there has the whole strip's solution (up
/// to its mesh) with fewer unknowns (static-contact README, Speed).
pub fn strip_mesh_parameters(params: &StaticParams) -> Vec<(&'static str, f64)> {
    let order = if elevated_in_rust(params) {
        1
    } else {
        params.element_order
    };
    gmsh_parameters(params, order)
}

/// The curved boundaries of the strip: the post walls (group `post_walls` of `slider-strip.geo`),
/// one vertical cylinder per post, axis at x = margin + (i + ½)·pitch, y = (r + ½)·pitch, radius
/// d/2; with a stator block also the rims of its imprinted tip disks (`stator_tip_disks`).
pub fn strip_post_walls(params: &StaticParams) -> Vec<gmsh_mesh::elevate::CylinderWalls> {
    let (pitch, margin) = (params.post_pitch_m, params.strip_margin_m());
    let cylinders = (0..params.strip_rows)
        .flat_map(|r| {
            (0..params.strip_posts_along_x()).map(move |i| gmsh_mesh::elevate::Cylinder {
                axis_point: [
                    margin + (i as f64 + 0.5) * pitch,
                    (r as f64 + 0.5) * pitch,
                    0.0,
                ],
                axis_direction: [0.0, 0.0, 1.0],
                radius: 0.5 * params.post_diameter_m,
            })
        })
        .collect();
    let mut walls = vec![gmsh_mesh::elevate::CylinderWalls {
        group: "post_walls".into(),
        cylinders,
        rims_only: false,
    }];
    if params.stator == StatorModel::MeshedBlock {
        walls.push(gmsh_mesh::elevate::CylinderWalls {
            group: "stator_tip_disks".into(),
            cylinders: walls[0].cylinders.clone(),
            rims_only: true,
        });
    }
    walls
}

fn gmsh_parameters(params: &StaticParams, order: u8) -> Vec<(&'static str, f64)> {
    let stator_depth = match params.stator {
        StatorModel::HalfSpace => 0.0,
        StatorModel::MeshedBlock => params.stator_depth_m,
    };
    vec![
        ("pitch", params.post_pitch_m),
        ("d", params.post_diameter_m),
        ("h", params.post_height_m),
        ("t", params.slider_thickness_m),
        ("n_posts", params.strip_posts_along_x() as f64),
        ("rows", params.strip_rows as f64),
        ("margin", params.strip_margin_m()),
        ("stator_depth", stator_depth),
        ("h_post", params.mesh_h_post_m()),
        ("h_body", params.mesh_sizes.h_body_m),
        ("growth", params.mesh_sizes.growth),
        ("order", order as f64),
        ("periodic_x", 0.0),
        ("half_y", if params.strip_rows == 1 { 1.0 } else { 0.0 }),
        ("mirror_x", if mirrored_in_rust(params) { 1.0 } else { 0.0 }),
    ]
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= PARAMETER_MATCH_TOLERANCE * a.abs().max(b.abs())
}

/// A committed mesh usable for these parameters. A mesh with a stator block also serves the
/// half-space stator model (its stator volume is then ignored), a whole-width mesh serves a
/// half-width request (the strip model reads half or whole tip disks from the mesh), and a whole
/// strip serves one that would be mirrored.
/// Its path is `<mesh cache>/committed/FILE`, written from the embedded bytes when missing or
/// different (None if that write fails: the mesh is then generated like any other).
pub fn committed_mesh(params: &StaticParams) -> Option<PathBuf> {
    let (file, bytes) = committed_match(params)?;
    let path = cache_dir(params).join("committed").join(file);
    gmsh_mesh::cache::write_if_different(&path, bytes).ok()?;
    Some(path)
}

/// The committed mesh (file name, embedded bytes) usable for these parameters, if any
/// ([`committed_mesh`] without writing it into the cache).
fn committed_match(params: &StaticParams) -> Option<(&'static str, &'static [u8])> {
    let wanted = gmsh_parameters(params, params.element_order);
    COMMITTED.iter().find_map(|(file, bytes, made)| {
        let fits = wanted.iter().all(|(name, value)| {
            if *name == "half_y" || *name == "mirror_x" {
                return true;
            }
            let Some((_, m)) = made.iter().find(|(n, _)| n == name) else {
                return false;
            };
            (*name == "stator_depth" && params.stator == StatorModel::HalfSpace) || same(*value, *m)
        });
        fits.then_some((*file, *bytes))
    })
}

/// The cache directory for automatic meshes: the run's `mesh_cache_dir`, else the mesh folder
/// of the one cache ([`gmsh_mesh::cache::meshes_dir`]).
pub fn cache_dir(params: &StaticParams) -> PathBuf {
    params
        .mesh_cache_dir
        .clone()
        .unwrap_or_else(gmsh_mesh::cache::meshes_dir)
}

/// The mesh of a run and where it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedMesh {
    /// The mesh file.
    pub path: PathBuf,
    /// The cache folder if the mesh is one of the automatic mesh cache (else `None`).
    pub cache_dir: Option<PathBuf>,
    /// What the cache check found and did, one line each (e.g. a damaged cached mesh that
    /// was regenerated), for the user.
    pub notes: Vec<String>,
    /// `Some`: the file holds the half x ≤ L/2 of the strip, and the run's mesh is it reflected
    /// in this plane ([`ResolvedMesh::read`]; before any elevation).
    pub mirror: Option<gmsh_mesh::mirror::MirrorPlane>,
    /// `Some`: the file holds the Tet4 mesh, and the run's mesh is it raised to Tet10 with
    /// curved midside nodes on these walls ([`ResolvedMesh::read`]).
    pub elevate: Option<Vec<gmsh_mesh::elevate::CylinderWalls>>,
}

impl ResolvedMesh {
    /// The run's mesh: the file read, reflected if [`ResolvedMesh::mirror`] says so, and raised
    /// to Tet10 if [`ResolvedMesh::elevate`] does. Every reader of the strip mesh goes through
    /// here, so all see the same mesh.
    pub fn read(&self) -> gmsh_mesh::Result<gmsh_mesh::TetMesh> {
        let mut mesh = gmsh_mesh::read_msh(&self.path)?;
        if let Some(plane) = &self.mirror {
            mesh = gmsh_mesh::mirror::mirror_in_x(&mesh, plane)?;
        }
        match &self.elevate {
            Some(walls) => gmsh_mesh::elevate::elevate_to_tet10(&mesh, walls),
            None => Ok(mesh),
        }
    }
}

/// Suffix of the file beside a cached mesh that records its SHA-256 (hex) when it was made.
pub const MESH_HASH_SUFFIX: &str = "sha256";

/// SHA-256 (hex) of a file's bytes, read through the bounded mesh reader.
pub fn file_sha256(path: &Path) -> Result<String> {
    let bytes =
        gmsh_mesh::read_file_bounded(path, gmsh_mesh::MAX_MSH_FILE_BYTES).map_err(|source| {
            ContactError::Mesh {
                file: path.display().to_string(),
                source: Box::new(source),
            }
        })?;
    Ok(hex(&Sha256::digest(&bytes)))
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// `mesh.msh.sha256` beside `mesh.msh`.
fn hash_file(mesh: &Path) -> PathBuf {
    let mut name = mesh.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".{MESH_HASH_SUFFIX}"));
    mesh.with_file_name(name)
}

/// Why the cached mesh `path` cannot be trusted (`None`: its bytes hash to the recorded value).
fn cached_mesh_problem(path: &Path) -> Option<String> {
    let Ok(recorded) = std::fs::read_to_string(hash_file(path)) else {
        return Some("no content hash recorded beside it".into());
    };
    match file_sha256(path) {
        Ok(actual) if actual == recorded.trim() => None,
        Ok(_) => Some("its content hash differs from the one recorded when it was made".into()),
        Err(e) => Some(format!("it cannot be read ({e})")),
    }
}

/// The file of the automatic mesh cache that holds (or will hold) the strip mesh of `params`:
/// the cache folder's `slider-strip_n<N>x<rows>_o<order>_<hash>.msh`, the hash taken over the
/// geometry script and the gmsh parameters. `None` when the run uses a given mesh file or a
/// committed mesh (no meshing). Callers that mesh concurrently lock per file name.
pub fn cached_mesh_path(params: &StaticParams) -> Option<PathBuf> {
    let automatic =
        !matches!(params.mesh, MeshChoice::File(_)) && committed_match(params).is_none();
    automatic.then(|| automatic_mesh_path(params))
}

/// [`cached_mesh_path`] without the checks for a given or committed mesh.
/// The name says `o1to2` for a Tet4 file raised to Tet10 on reading; the hash then also covers
/// [`gmsh_mesh::elevate::ELEVATION_VERSION`].
fn automatic_mesh_path(params: &StaticParams) -> PathBuf {
    let mut hasher = Sha256::new();
    hasher.update(geometry_source("slider-strip"));
    for (name, value) in &strip_mesh_parameters(params) {
        hasher.update(format!("{name}={value:e}\n"));
    }
    hasher.update(rust_mesh_steps(params));
    let order = if elevated_in_rust(params) {
        "1to2".to_string()
    } else {
        params.element_order.to_string()
    };
    let digest = hex(&hasher.finalize()[..8]);
    cache_dir(params).join(format!(
        "slider-strip_n{}x{}_o{order}_{digest}.msh",
        params.strip_posts_along_x(),
        params.strip_rows,
    ))
}

/// The mesh file of the run: the given file, a committed mesh, or a cached/generated one. For a
/// Tet10 strip elevated in Rust this file holds the Tet4 mesh: read the run's mesh with
/// [`resolve_mesh_verified`] and [`ResolvedMesh::read`].
pub fn resolve_mesh(params: &StaticParams) -> Result<PathBuf> {
    resolve_mesh_verified(params).map(|r| r.path)
}

/// [`resolve_mesh`], verifying a cached mesh against the SHA-256 recorded when it was made: a
/// swapped, edited or truncated cached mesh is regenerated (and said so in the notes).
pub fn resolve_mesh_verified(params: &StaticParams) -> Result<ResolvedMesh> {
    let plain = |path: PathBuf| ResolvedMesh {
        path,
        cache_dir: None,
        notes: Vec::new(),
        mirror: None,
        elevate: None,
    };
    if let MeshChoice::File(path) = &params.mesh {
        return Ok(plain(path.clone()));
    }
    if let Some(path) = committed_mesh(params) {
        return Ok(plain(path));
    }
    let out = automatic_mesh_path(params);
    let setnumbers = strip_mesh_parameters(params);
    let dir = cache_dir(params);
    let mirror = mirrored_in_rust(params).then(|| strip_mirror_plane(params));
    let elevate = elevated_in_rust(params).then(|| strip_post_walls(params));
    let mut notes = Vec::new();
    if out.is_file() {
        match cached_mesh_problem(&out) {
            None => {
                return Ok(ResolvedMesh {
                    path: out,
                    cache_dir: Some(dir),
                    notes,
                    mirror,
                    elevate,
                });
            }
            Some(why) => notes.push(format!(
                "cached mesh {} not used: {why}; regenerating it",
                out.display()
            )),
        }
    }
    generate_mesh("slider-strip", &out, &setnumbers)?;
    record_mesh_hash(&out)?;
    Ok(ResolvedMesh {
        path: out,
        cache_dir: Some(dir),
        notes,
        mirror,
        elevate,
    })
}

/// Write `mesh.msh.sha256` (temporary name, then rename) with the mesh's SHA-256.
fn record_mesh_hash(mesh: &Path) -> Result<()> {
    let target = hash_file(mesh);
    let temporary = target.with_extension(format!("tmp-{}", std::process::id()));
    let write_error = |e: std::io::Error| ContactError::CacheWrite {
        path: target.clone(),
        detail: e.to_string(),
    };
    std::fs::write(&temporary, file_sha256(mesh)?).map_err(write_error)?;
    std::fs::rename(&temporary, &target).map_err(write_error)
}

/// Meshes the embedded `meshes/GEOMETRY.geo` ([`gmsh_mesh::geo_scripts::path`], written into
/// the cache folder) into OUT with gmsh (`-setnumber NAME VALUE` for each pair), through the
/// workspace's one runner [`gmsh_mesh::gmsh::run_geo`] (binary MSH 4.1, one thread, written
/// atomically). Errors carry gmsh's message, or how to install gmsh.
pub fn generate_mesh(geometry: &str, out: &Path, setnumbers: &[(&str, f64)]) -> Result<()> {
    let meshing = |source: gmsh_mesh::MeshError| ContactError::Meshing {
        geometry: geometry.into(),
        source: Box::new(source),
    };
    let geo = gmsh_mesh::geo_scripts::path(geometry).map_err(|source| {
        meshing(gmsh_mesh::MeshError::Io {
            path: gmsh_mesh::cache::cache_dir().join("geo"),
            action: format!("writing the embedded gmsh script {geometry}.geo"),
            source,
        })
    })?;
    gmsh_mesh::gmsh::run_geo(
        &geo,
        out,
        setnumbers,
        &gmsh_mesh::gmsh::GmshOptions::default(),
    )
    .map_err(meshing)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 10-post Tet4 strip whose mesh is committed (`meshes/`).
    fn ten_post_tet4() -> StaticParams {
        StaticParams {
            strip_posts: Some(10),
            element_order: 1,
            mesh_sizes: crate::params::MeshSizes {
                h_post_over_radius: 0.25,
                ..Default::default()
            },
            ..StaticParams::default()
        }
    }

    #[test]
    fn the_ten_post_strip_resolves_to_the_committed_mesh() {
        let params = ten_post_tet4();
        let path = committed_mesh(&params).expect("committed 10-post strip mesh matches");
        assert!(
            path.ends_with("slider-strip_p40um_d20um_n10_tet4_10k.msh"),
            "picked {}",
            path.display()
        );
        let tet10 = StaticParams {
            element_order: 2,
            ..params
        };
        assert!(
            committed_mesh(&tet10).is_none(),
            "a Tet10 request must not reuse the Tet4 mesh"
        );
    }

    #[test]
    fn a_tet10_strip_is_meshed_in_tet4_with_its_curved_boundaries_named() {
        let order = |p: &StaticParams| {
            strip_mesh_parameters(p)
                .iter()
                .find(|(n, _)| *n == "order")
                .map(|(_, v)| *v)
        };
        let default = StaticParams {
            mesh_cache_dir: Some(std::env::temp_dir().join("sawdrive-elevation-test")),
            ..StaticParams::default()
        };
        assert_eq!(
            order(&default),
            Some(1.0),
            "gmsh order of the default strip"
        );
        let path = cached_mesh_path(&default).expect("default strip is meshed into the cache");
        assert!(
            path.to_string_lossy().contains("_o1to2_"),
            "cached Tet4 file of a Tet10 strip named {}",
            path.display()
        );
        assert_eq!(
            strip_post_walls(&default)[0].cylinders.len(),
            default.strip_post_count(),
            "one wall cylinder per post"
        );
        let block = StaticParams {
            stator: StatorModel::MeshedBlock,
            ..default
        };
        assert_eq!(order(&block), Some(1.0), "gmsh order with a stator block");
        assert_eq!(
            strip_post_walls(&block).len(),
            2,
            "post walls and the stator's tip circles"
        );
    }

    #[test]
    fn a_mesh_to_generate_has_its_cache_file_and_a_committed_one_none() {
        let committed = ten_post_tet4();
        assert_eq!(
            cached_mesh_path(&committed),
            None,
            "committed mesh needs no cache file"
        );
        let dir = std::env::temp_dir().join("sawdrive-cached-mesh-path-test");
        let generated = StaticParams {
            mesh_cache_dir: Some(dir.clone()),
            ..StaticParams::default()
        };
        let path = cached_mesh_path(&generated).expect("default strip is meshed into the cache");
        assert_eq!(
            path.parent(),
            Some(dir.as_path()),
            "mesh file {}",
            path.display()
        );
        let coarser = StaticParams {
            mesh_sizes: crate::params::MeshSizes {
                growth: 0.5,
                ..Default::default()
            },
            ..generated
        };
        assert_ne!(
            cached_mesh_path(&coarser),
            Some(path),
            "another mesh size growth must name another mesh file"
        );
    }
}
