//! Resolved motor parameters (SI) of a static contact run, their validation and content hash.
//! The content hash keys an automatic mesh by the geometry script and the steps Rust applies to
//! the mesh on reading ([`rust_mesh_steps`]), so those facts of the parameters live here and
//! [`crate::mesh_source`] re-exports them (it builds on this module, never the reverse).

use std::path::PathBuf;

use contact_springs::{Material, PostSprings, post_springs};
use motor::Motor;
use serde::Serialize;
use sha2::{Digest, Sha256};

use crate::body_solver::FemSolver;
use crate::error::{ContactError, Result};
use crate::lcp::{ActiveSetOptions, DEFAULT_COMPLEMENTARITY_TOLERANCE, DEFAULT_MAX_ITERATIONS};
use crate::scene::StatorModel;

/// Bumped whenever a change of this crate changes its numbers or its report's fields (part of the
/// content hash). 2: `eta_full_contact`, `strip_rows`. 3: the contact solver's tolerance and
/// iteration limit are parameters (they change the numbers within the tolerance).
pub const MODEL_VERSION: u32 = 3;

/// Where the mesh comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum MeshChoice {
    /// A committed mesh of `meshes/` if one matches the parameters, else gmsh into the cache.
    #[default]
    Auto,
    /// This `slider-strip` mesh file.
    File(PathBuf),
}

/// Mesh-size parameters of the automatic `slider-strip` mesh (see meshes/README.md).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeshSizes {
    /// Element size on the post tips, relative to the post radius a (gmsh `h_post` = this × a).
    pub h_post_over_radius: f64,
    /// Largest element size (m).
    pub h_body_m: f64,
    /// Size growth per unit distance from the tips.
    pub growth: f64,
}

impl Default for MeshSizes {
    /// a/2 at the tips (5 µm for 20 µm posts), 100 µm far away, growth 0.3. With Tet10 this puts
    /// η within ≈ 1.5 % of its mesh-converged value (validation/static-contact/README.md).
    fn default() -> Self {
        Self {
            h_post_over_radius: 0.5,
            h_body_m: 100e-6,
            growth: 0.3,
        }
    }
}

/// Everything a static contact run depends on, in SI units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StaticParams {
    /// Slider material.
    pub slider_material: Material,
    /// Stator material.
    pub stator_material: Material,
    /// Post diameter d (m).
    pub post_diameter_m: f64,
    /// Post height h (m).
    pub post_height_m: f64,
    /// Posts along x (the wave's direction) of the real slider.
    pub posts_x: usize,
    /// Rows of posts along y of the real slider.
    pub posts_y: usize,
    /// Post pitch (m), the same in x and y.
    pub post_pitch_m: f64,
    /// Slider length along x (m) (≥ posts_x · pitch; the rest is margin around the array).
    pub slider_length_m: f64,
    /// Slider width along y (m).
    pub slider_width_m: f64,
    /// Slider body thickness above the posts (m).
    pub slider_thickness_m: f64,
    /// Normal wave amplitude A_n (m); 0 for a flat stator.
    pub wave_amplitude_m: f64,
    /// Wavelength λ (m).
    pub wavelength_m: f64,
    /// Preload P on the whole slider (N): the top-level results refer to it.
    pub preload_n: f64,
    /// Further preloads (N) for the η-against-preload sweep (may be empty).
    pub preload_sweep_n: Vec<f64>,
    /// Snapshot phases θ₀ = 2πk/phases pooled in the η fit (≥ 1).
    pub phases: usize,
    /// Element order: 1 (Tet4) or 2 (Tet10). Default 2: Tet4 is ≈ 10 % too stiff locally at the
    /// tip disks at the default size and biases η up by ≈ 4 %.
    pub element_order: u8,
    /// Posts along x inside the strip: `None` = the whole row (posts_x) with the slider's
    /// margins; `Some(n)` = a shorter strip of n posts without margins (free ends).
    pub strip_posts: Option<usize>,
    /// Rows of posts across the strip, between its two symmetry planes (default 1). A wider
    /// strip has, up to its mesh, the solution of the one-pitch strip (each row mirrors the next);
    /// 2 or more checks that.
    pub strip_rows: usize,
    /// Stator model.
    pub stator: StatorModel,
    /// Stator depth (m) of a meshed stator block.
    pub stator_depth_m: f64,
    /// Mesh source.
    pub mesh: MeshChoice,
    /// Sizes of an automatic mesh.
    pub mesh_sizes: MeshSizes,
    /// Largest accepted scaled complementarity residual of each contact solve (dimensionless;
    /// see [`crate::ContactSolution::complementarity_residual`]). Default
    /// [`DEFAULT_COMPLEMENTARITY_TOLERANCE`].
    pub contact_tolerance: f64,
    /// Active-set iteration limit of each contact solve (both phases). Default
    /// [`DEFAULT_MAX_ITERATIONS`].
    pub max_iterations: usize,
    /// Linear solver of the FEM bodies (`static.fem_solver`, [`crate::body_solver`]): the cost
    /// model's choice (default, left out of the content hash: it depends only on the mesh) or
    /// `direct` / `iterative` (hashed: the compliances differ by ≤ the PCG tolerance).
    #[serde(default, skip_serializing_if = "FemSolver::is_auto")]
    pub fem_solver: FemSolver,
    /// Directory for automatic meshes (`None`: the mesh folder of the one cache,
    /// `gmsh_mesh::cache::meshes_dir`).
    /// Not part of the content hash.
    #[serde(skip)]
    pub mesh_cache_dir: Option<PathBuf>,
}

impl Default for StaticParams {
    /// The paper's motor ([`Motor::paper`], docs/physics.md §1) with the default stage settings:
    /// 5 × 5 × 0.5 mm Si, 100 × 100 posts of 20 µm, 2 µm high, pitch 40 µm; LiNbO3 stator;
    /// λ = 3979/9.61e6 m, A_n = 20 nm; P = 40 N; 4 phases, Tet10, half-space stator.
    fn default() -> Self {
        Self::for_motor(&Motor::paper())
    }
}

impl StaticParams {
    /// The Johnson springs of one post (slider side bonded, stator side frictional).
    pub fn post_springs(&self) -> Result<PostSprings> {
        post_springs(
            &self.slider_material,
            &self.stator_material,
            0.5 * self.post_diameter_m,
        )
        .map_err(|e| ContactError::InvalidParameter {
            parameter: "post_diameter_m",
            value: self.post_diameter_m,
            reason: e.to_string(),
        })
    }

    /// The static stage of `motor` with the default stage settings (4 phases, Tet10, automatic
    /// mesh, half-space stator, default solver tolerances). The strip model takes the x pitch
    /// (the lattice must be square: the caller checks `motor.posts.is_square_lattice`).
    pub fn for_motor(motor: &Motor) -> Self {
        let posts = &motor.posts;
        Self {
            slider_material: motor.slider.material.clone(),
            stator_material: motor.stator.clone(),
            post_diameter_m: posts.diameter_m,
            post_height_m: posts.height_m,
            posts_x: posts.count_x as usize,
            posts_y: posts.count_y as usize,
            post_pitch_m: posts.pitch_x_m(),
            slider_length_m: motor.slider.length_m,
            slider_width_m: motor.slider.width_m,
            slider_thickness_m: motor.slider.thickness_m,
            wave_amplitude_m: motor.wave.normal_amplitude_m,
            wavelength_m: motor.wave.wavelength_m(),
            preload_n: motor.load.preload_n,
            preload_sweep_n: Vec::new(),
            phases: 4,
            element_order: 2,
            strip_posts: None,
            strip_rows: 1,
            stator: StatorModel::HalfSpace,
            stator_depth_m: 1e-3,
            mesh: MeshChoice::Auto,
            mesh_sizes: MeshSizes::default(),
            contact_tolerance: DEFAULT_COMPLEMENTARITY_TOLERANCE,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            fem_solver: FemSolver::Auto,
            mesh_cache_dir: None,
        }
    }
}

fn invalid(parameter: &'static str, value: f64, reason: impl Into<String>) -> ContactError {
    ContactError::InvalidParameter {
        parameter,
        value,
        reason: reason.into(),
    }
}

fn positive(parameter: &'static str, value: f64) -> Result<()> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(invalid(parameter, value, "must be positive and finite"))
    }
}

impl StaticParams {
    /// A square array of `posts_per_side`² posts of diameter `diameter_m` in the default
    /// 4 × 4 mm area (pitch = 4 mm / posts_per_side), otherwise the defaults.
    pub fn square_array(diameter_m: f64, posts_per_side: usize) -> Self {
        let array_side_m = 4e-3;
        Self {
            post_diameter_m: diameter_m,
            posts_x: posts_per_side,
            posts_y: posts_per_side,
            post_pitch_m: array_side_m / posts_per_side as f64,
            ..Self::default()
        }
    }

    /// Checks ranges and consistency; errors name the parameter.
    pub fn validate(&self) -> Result<()> {
        self.validate_materials_and_sizes()?;
        self.validate_array()?;
        self.validate_settings()
    }

    /// The materials, and every length and load positive.
    fn validate_materials_and_sizes(&self) -> Result<()> {
        self.slider_material.validate().map_err(|e| {
            invalid(
                "slider_material",
                self.slider_material.shear_modulus_pa,
                e.to_string(),
            )
        })?;
        self.stator_material.validate().map_err(|e| {
            invalid(
                "stator_material",
                self.stator_material.shear_modulus_pa,
                e.to_string(),
            )
        })?;
        positive("post_diameter_m", self.post_diameter_m)?;
        positive("post_height_m", self.post_height_m)?;
        positive("post_pitch_m", self.post_pitch_m)?;
        positive("slider_thickness_m", self.slider_thickness_m)?;
        positive("wavelength_m", self.wavelength_m)?;
        positive("preload_n", self.preload_n)?;
        for &p in &self.preload_sweep_n {
            positive("preload_sweep_n", p)?;
        }
        Ok(())
    }

    /// The post array: posts narrower than the pitch, at least one post, the slider as long and
    /// as wide as the array.
    fn validate_array(&self) -> Result<()> {
        if self.post_diameter_m >= self.post_pitch_m {
            return Err(invalid(
                "post_diameter_m",
                self.post_diameter_m,
                format!("must be smaller than the pitch {} m", self.post_pitch_m),
            ));
        }
        if self.posts_x == 0 || self.posts_y == 0 {
            return Err(invalid(
                "posts_x",
                self.posts_x.min(self.posts_y) as f64,
                "post counts must be ≥ 1",
            ));
        }
        let array_x = self.posts_x as f64 * self.post_pitch_m;
        if self.slider_length_m < array_x * (1.0 - 1e-9) {
            return Err(invalid(
                "slider_length_m",
                self.slider_length_m,
                format!("shorter than the post array {array_x} m"),
            ));
        }
        let array_y = self.posts_y as f64 * self.post_pitch_m;
        if self.slider_width_m < array_y * (1.0 - 1e-9) {
            return Err(invalid(
                "slider_width_m",
                self.slider_width_m,
                format!("narrower than the post array {array_y} m"),
            ));
        }
        Ok(())
    }

    /// The wave, the snapshot phases, the strip, the stator, the mesh sizes and the contact
    /// solver's settings.
    fn validate_settings(&self) -> Result<()> {
        if !(self.wave_amplitude_m >= 0.0 && self.wave_amplitude_m.is_finite()) {
            return Err(invalid(
                "wave_amplitude_m",
                self.wave_amplitude_m,
                "must be ≥ 0 and finite",
            ));
        }
        if self.phases == 0 {
            return Err(invalid("phases", 0.0, "need at least one snapshot phase"));
        }
        if self.element_order != 1 && self.element_order != 2 {
            return Err(invalid(
                "element_order",
                self.element_order as f64,
                "must be 1 (Tet4) or 2 (Tet10)",
            ));
        }
        if let Some(n) = self.strip_posts
            && (n == 0 || n > self.posts_x)
        {
            return Err(invalid(
                "strip_posts",
                n as f64,
                format!("must lie in 1..={}", self.posts_x),
            ));
        }
        if self.strip_rows == 0 || self.strip_rows > self.posts_y {
            return Err(invalid(
                "strip_rows",
                self.strip_rows as f64,
                format!("must lie in 1..={} (the slider's rows)", self.posts_y),
            ));
        }
        if self.stator == StatorModel::MeshedBlock {
            positive("stator_depth_m", self.stator_depth_m)?;
        }
        positive(
            "mesh_sizes.h_post_over_radius",
            self.mesh_sizes.h_post_over_radius,
        )?;
        positive("mesh_sizes.growth", self.mesh_sizes.growth)?;
        positive("contact_tolerance", self.contact_tolerance)?;
        if self.max_iterations == 0 {
            return Err(invalid(
                "max_iterations",
                0.0,
                "the contact solver needs at least one iteration",
            ));
        }
        if self.mesh_sizes.h_body_m < self.mesh_h_post_m() {
            return Err(invalid(
                "mesh_sizes.h_body_m",
                self.mesh_sizes.h_body_m,
                "must be ≥ the tip element size",
            ));
        }
        Ok(())
    }

    /// The contact solver's options: [`Self::contact_tolerance`] and [`Self::max_iterations`],
    /// the rest at their defaults.
    pub fn solver_options(&self) -> ActiveSetOptions {
        ActiveSetOptions {
            tolerance: self.contact_tolerance,
            max_iterations: self.max_iterations,
            ..ActiveSetOptions::default()
        }
    }

    /// Element size on the post tips (m).
    pub fn mesh_h_post_m(&self) -> f64 {
        self.mesh_sizes.h_post_over_radius * 0.5 * self.post_diameter_m
    }

    /// Posts along x in each row of the strip.
    pub fn strip_posts_along_x(&self) -> usize {
        self.strip_posts.unwrap_or(self.posts_x)
    }

    /// Posts in the strip (all its rows).
    pub fn strip_post_count(&self) -> usize {
        self.strip_posts_along_x() * self.strip_rows
    }

    /// Margin of the strip beyond its first and last post cell (m).
    pub fn strip_margin_m(&self) -> f64 {
        match self.strip_posts {
            None => 0.5 * (self.slider_length_m - self.posts_x as f64 * self.post_pitch_m).max(0.0),
            Some(_) => 0.0,
        }
    }

    /// The strip's share of the preload, P · (posts in strip) / (posts of the slider) (N).
    pub fn strip_share(&self) -> f64 {
        self.strip_post_count() as f64 / (self.posts_x * self.posts_y) as f64
    }

    /// All preloads of the run: the main one first, then the sweep.
    pub fn all_preloads_n(&self) -> Vec<f64> {
        let mut p = vec![self.preload_n];
        p.extend(
            self.preload_sweep_n
                .iter()
                .copied()
                .filter(|&x| x != self.preload_n),
        );
        p
    }

    /// SHA-256 (hex) of everything the results depend on: the parameters (without the cache
    /// directory), the mesh file's bytes if a file is given (else the `slider-strip.geo` script's),
    /// and [`MODEL_VERSION`].
    pub fn content_hash(&self) -> Result<String> {
        let mut hasher = Sha256::new();
        hasher.update(format!("static-contact model {MODEL_VERSION}\n"));
        // A given mesh enters by its bytes (below), not by where it lies: the same mesh in
        // another checkout or folder keys the same cache entry.
        let mut keyed = self.clone();
        if let MeshChoice::File(path) = &self.mesh {
            keyed.mesh = MeshChoice::File(path.file_name().map(PathBuf::from).unwrap_or_default());
        }
        let json = serde_json::to_string(&keyed)
            .map_err(|e| invalid("params", 0.0, format!("cannot serialise: {e}")))?;
        hasher.update(json.as_bytes());
        if let MeshChoice::File(path) = &self.mesh {
            let bytes = gmsh_mesh::read_file_bounded(path, gmsh_mesh::MAX_MSH_FILE_BYTES).map_err(
                |source| ContactError::Mesh {
                    file: path.display().to_string(),
                    source: Box::new(source),
                },
            )?;
            hasher.update(&bytes);
        } else {
            hasher.update(geometry_source("slider-strip"));
            hasher.update(rust_mesh_steps(self));
        }
        Ok(hasher
            .finalize()
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect())
    }
}

/// Whether the run's automatic strip mesh is gmsh's Tet4 mesh raised to Tet10 in Rust
/// ([`gmsh_mesh::elevate`]): every Tet10 strip.
pub fn elevated_in_rust(params: &StaticParams) -> bool {
    params.element_order == 2
}

/// Whether the run's automatic strip mesh is gmsh's half x ≤ L/2 reflected in Rust
/// ([`gmsh_mesh::mirror`]): every strip with an even number of posts along x.
pub fn mirrored_in_rust(params: &StaticParams) -> bool {
    params.strip_posts_along_x().is_multiple_of(2)
}

/// What Rust does to the automatic strip mesh file on reading (reflection, elevation) and the
/// versions of those steps, one line each: hashed into the mesh cache's file names and into the
/// results' content hash, so that a changed step never reuses a mesh or result made before.
pub fn rust_mesh_steps(params: &StaticParams) -> String {
    let mut steps = String::new();
    if mirrored_in_rust(params) {
        steps += &format!("mirror x {}\n", gmsh_mesh::mirror::MIRROR_VERSION);
    }
    if elevated_in_rust(params) {
        steps += &format!(
            "tet10 elevation {}\n",
            gmsh_mesh::elevate::ELEVATION_VERSION
        );
    }
    steps
}

/// The bytes of `meshes/GEOMETRY.geo` as embedded in the binary
/// ([`gmsh_mesh::geo_scripts::source`]; empty for an unknown name, meshing then fails with its
/// own error). Cached meshes and results are keyed by them, so editing the geometry script
/// invalidates both.
pub fn geometry_source(geometry: &str) -> Vec<u8> {
    gmsh_mesh::geo_scripts::source(geometry)
        .unwrap_or_default()
        .as_bytes()
        .to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_content_hash_changes_with_a_parameter_and_not_with_the_cache_dir() {
        let a = StaticParams::default();
        let mut b = a.clone();
        b.mesh_cache_dir = Some("/somewhere".into());
        assert_eq!(
            a.content_hash().unwrap(),
            b.content_hash().unwrap(),
            "cache dir must not change the hash"
        );
        b.preload_n = 41.0;
        assert_ne!(
            a.content_hash().unwrap(),
            b.content_hash().unwrap(),
            "preload must change the hash"
        );
    }

    #[test]
    fn the_same_mesh_in_another_folder_keys_the_same_hash_and_other_bytes_do_not() {
        let mesh = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../meshes/slider-strip-periodic_p40um_d20um_n1_tet4_1k.msh"
        );
        let bytes = std::fs::read(mesh).unwrap();
        let (one, two) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
        let here = one.path().join("strip.msh");
        let there = two.path().join("strip.msh");
        std::fs::write(&here, &bytes).unwrap();
        std::fs::write(&there, &bytes).unwrap();
        let with = |path: &std::path::Path| StaticParams {
            mesh: MeshChoice::File(path.to_path_buf()),
            ..StaticParams::default()
        };
        assert_eq!(
            with(&here).content_hash().unwrap(),
            with(&there).content_hash().unwrap()
        );
        let mut edited = bytes.clone();
        edited.extend_from_slice(b"\n");
        std::fs::write(&there, &edited).unwrap();
        assert_ne!(
            with(&here).content_hash().unwrap(),
            with(&there).content_hash().unwrap()
        );
    }

    #[test]
    fn the_solver_settings_change_the_content_hash() {
        let a = StaticParams::default();
        let tighter = StaticParams {
            contact_tolerance: 1e-12,
            ..a.clone()
        };
        let shorter = StaticParams {
            max_iterations: 1,
            ..a.clone()
        };
        let hash = a.content_hash().unwrap();
        assert_ne!(
            hash,
            tighter.content_hash().unwrap(),
            "contact tolerance must change the hash"
        );
        assert_ne!(
            hash,
            shorter.content_hash().unwrap(),
            "iteration limit must change the hash"
        );
        assert_eq!(
            shorter.solver_options().max_iterations,
            1,
            "iteration limit reaches the solver"
        );
        assert_eq!(
            tighter.solver_options().tolerance,
            1e-12,
            "tolerance reaches the solver"
        );
        let none = StaticParams {
            max_iterations: 0,
            ..a
        };
        assert!(
            none.validate()
                .unwrap_err()
                .to_string()
                .contains("max_iterations"),
            "zero iterations are refused by name"
        );
    }

    #[test]
    fn bad_parameters_are_named() {
        let p = StaticParams {
            post_diameter_m: 50e-6,
            ..StaticParams::default()
        };
        let err = p.validate().unwrap_err().to_string();
        assert!(
            err.contains("post_diameter_m"),
            "error names the post diameter: {err}"
        );
        let p = StaticParams {
            phases: 0,
            ..StaticParams::default()
        };
        assert!(
            p.validate().unwrap_err().to_string().contains("phases"),
            "error names the phase count"
        );
    }

    #[test]
    fn the_paper_arrays_fill_four_millimetres() {
        for (d, n) in [(20e-6, 100), (30e-6, 67), (40e-6, 50), (50e-6, 40)] {
            let p = StaticParams::square_array(d, n);
            p.validate().unwrap();
            assert!(
                (p.posts_x as f64 * p.post_pitch_m - 4e-3).abs() < 1e-12,
                "array side for d = {d}"
            );
        }
    }
}
