//! The springs validation study: [`validate_springs`].
//!
//! For every spring × material × radius: FEM stiffness on a sequence of punch meshes (Tet10,
//! [`MeshFamily::tet10`]), Richardson extrapolation with an error estimate
//! ([`crate::richardson`]), a truncation error estimate from a study in R/a, and the comparison
//! with the formula. Then: whether each FEM value can tell its boundary condition from the
//! partner one (bonded vs frictional), the work-precision of Tet4 vs Tet10, and the stability
//! cases. Charts and JSON are written by [`crate::report`].

use std::collections::BTreeMap;
use std::time::Instant;

use contact_springs::Material;
use serde::{Deserialize, Serialize};

use crate::error::ValidationError;
use crate::family::MeshFamily;
use crate::mesh_cache::MeshCache;
use crate::punch::{AssembledPunch, PunchSolveOptions, PunchStiffness};
use crate::punch_mesh::{MeshSymmetry, PunchMesh};
use crate::richardson::extrapolate;
use crate::spring::Spring;
use crate::stability::{
    DistortionPoint, LockingPoint, SingularSystemReport, distortion_study, locking_study,
    singular_system,
};

/// Solves per work-precision point; the fastest is kept, to reduce the effect of other
/// processes on a shared machine. Default 2.
pub const WORK_PRECISION_REPETITIONS: usize = 2;

/// Acceptance: largest estimated relative FEM error. Dimensionless; 0.003.
pub const ERROR_TOLERANCE: f64 = 0.003;
/// Acceptance: largest |FEM / formula − 1|. Dimensionless; 0.005.
pub const AGREEMENT_TOLERANCE: f64 = 0.005;

/// What the work-precision comparison runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WorkPrecisionOptions {
    /// Spring (an exact formula: k_sn or k_st).
    pub spring: Spring,
    /// Material name (one of the study's materials).
    pub material: String,
    /// Punch radius (m).
    pub radius_m: f64,
    /// Tet10 levels (the study's levels are reused, extra levels added).
    pub tet10_levels: usize,
    /// Tet4 family.
    pub tet4_family: MeshFamily,
    /// Tet4 levels.
    pub tet4_levels: usize,
}

/// What the stability section runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StabilityOptions {
    /// Poisson ratios of the locking study.
    pub poisson_ratios: Vec<f64>,
    /// Tet4 level (of the work-precision Tet4 family) and Tet10 level (of the study family) of
    /// the locking study; chosen to have similar numbers of unknowns.
    pub tet4_level: usize,
    /// See `tet4_level`.
    pub tet10_level: usize,
    /// Distortion amplitudes (fraction of the shortest edge at each interior node).
    pub distortion_amplitudes: Vec<f64>,
}

/// Options of [`validate_springs`].
#[derive(Debug, Clone)]
pub struct SpringsOptions {
    /// Materials (each gets all springs).
    pub materials: Vec<Material>,
    /// Punch radii (m).
    pub radii_m: Vec<f64>,
    /// Springs.
    pub springs: Vec<Spring>,
    /// Mesh family of the convergence study.
    pub family: MeshFamily,
    /// Number of levels (≥ 3).
    pub levels: usize,
    /// Model of the tangential springs: `Half` (y ≥ 0, symmetric) or `Quarter` (antisymmetric
    /// in x = 0 as well; exact too, 4× cheaper). Normal springs always use the quarter model.
    pub tangential_symmetry: MeshSymmetry,
    /// R/a values of the truncation study (on level 0, first radius); must contain the family's
    /// R/a and a larger one to give a truncation error estimate. Empty: no study, no estimate.
    pub truncation_ratios: Vec<f64>,
    /// Work-precision comparison (None: skipped).
    pub work_precision: Option<WorkPrecisionOptions>,
    /// Stability section (None: skipped).
    pub stability: Option<StabilityOptions>,
    /// Mesh generation.
    pub cache: MeshCache,
    /// Solver options.
    pub solve: PunchSolveOptions,
    /// Print progress lines on stderr.
    pub progress: bool,
}

impl Default for SpringsOptions {
    /// The full study: Si and LiNbO3, a = 10 and 25 µm, all four springs, three
    /// Tet10 levels, truncation R/a = 25…200, work-precision and stability.
    fn default() -> Self {
        Self {
            materials: vec![Material::silicon(), Material::lithium_niobate()],
            radii_m: vec![10e-6, 25e-6],
            springs: Spring::ALL.to_vec(),
            family: MeshFamily::tet10(),
            levels: 3,
            tangential_symmetry: MeshSymmetry::Half,
            truncation_ratios: vec![25.0, 50.0, 100.0, 200.0],
            work_precision: Some(WorkPrecisionOptions {
                spring: Spring::FrictionlessNormal,
                material: "linbo3".into(),
                radius_m: 10e-6,
                tet10_levels: 4,
                tet4_family: MeshFamily::tet4(),
                tet4_levels: 4,
            }),
            stability: Some(StabilityOptions {
                poisson_ratios: vec![0.25, 0.4, 0.45, 0.49, 0.499],
                tet4_level: 1,
                tet10_level: 0,
                distortion_amplitudes: vec![0.1, 0.2, 0.3, 0.45],
            }),
            cache: MeshCache::default(),
            solve: PunchSolveOptions::default(),
            progress: false,
        }
    }
}

impl SpringsOptions {
    /// A small, fast version of the whole pipeline (coarse meshes, R = 20a, a = 10 µm only, no
    /// work-precision, no stability): for tests and smoke runs, not for conclusions.
    pub fn smoke() -> Self {
        let family = MeshFamily {
            order: 2,
            h_edge_over_a: 0.2,
            growth: 0.6,
            refinement_ratio: 2.0,
            truncation_ratio: 20.0,
            h_max_over_a: 0.0,
        };
        Self {
            radii_m: vec![10e-6],
            family,
            tangential_symmetry: MeshSymmetry::Quarter,
            truncation_ratios: vec![20.0, 40.0],
            work_precision: None,
            stability: None,
            ..Self::default()
        }
    }

    fn validate(&self) -> Result<(), ValidationError> {
        let bad = |option: &'static str, value: String, reason: &'static str| {
            Err(ValidationError::InvalidOption {
                option,
                value,
                reason,
            })
        };
        if self.levels < 3 {
            return bad(
                "levels",
                self.levels.to_string(),
                "Richardson extrapolation with an error estimate needs at least 3 levels",
            );
        }
        if self.materials.is_empty() || self.radii_m.is_empty() || self.springs.is_empty() {
            return bad(
                "materials/radii/springs",
                String::new(),
                "need at least one of each",
            );
        }
        if let Some(r) = self.radii_m.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
            return bad("radii_m", r.to_string(), "radii must be positive");
        }
        if self.tangential_symmetry == MeshSymmetry::Full {
            return bad(
                "tangential_symmetry",
                "full".into(),
                "use half or quarter (both exact; full is only a waste)",
            );
        }
        if let Some(wp) = &self.work_precision {
            if !self.materials.iter().any(|m| m.name == wp.material) {
                return bad(
                    "work_precision.material",
                    wp.material.clone(),
                    "must be one of the study's materials",
                );
            }
            if wp.tet10_levels < 3 || wp.tet4_levels < 3 {
                return bad(
                    "work_precision levels",
                    format!("{} / {}", wp.tet10_levels, wp.tet4_levels),
                    "need at least 3 levels each",
                );
            }
        }
        Ok(())
    }
}

/// The FEM result of one spring on one mesh level.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LevelResult {
    /// Level index.
    pub level: usize,
    /// h_e / a of the level.
    pub h_edge_over_a: f64,
    /// Growth g of the level.
    pub growth: f64,
    /// Mesh file.
    pub mesh: String,
    /// The solve.
    pub result: PunchStiffness,
}

/// Validation of one spring for one material and radius.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpringCase {
    /// `k_pn`, `k_pt`, `k_sn` or `k_st`.
    pub spring: Spring,
    /// Material name.
    pub material: String,
    /// Punch radius a (m).
    pub radius_m: f64,
    /// Extrapolated FEM stiffness (N/m).
    pub fem_n_per_m: f64,
    /// Estimated relative error of `fem_n_per_m` (discretisation + truncation).
    #[serde(deserialize_with = "crate::serde_nan::f64_or_nan")]
    pub fem_error_estimate: f64,
    /// Formula value (N/m).
    pub analytic_n_per_m: f64,
    /// fem / analytic − 1.
    #[serde(deserialize_with = "crate::serde_nan::f64_or_nan")]
    pub relative_difference: f64,
    /// Relative discretisation error estimate (Richardson).
    #[serde(deserialize_with = "crate::serde_nan::f64_or_nan")]
    pub discretisation_error_estimate: f64,
    /// Relative truncation error estimate (R/a study), NaN if not run.
    #[serde(deserialize_with = "crate::serde_nan::f64_or_nan")]
    pub truncation_error_estimate: f64,
    /// Observed convergence order in h_e (theory: 1).
    #[serde(deserialize_with = "crate::serde_nan::f64_or_nan")]
    pub observed_order: f64,
    /// Whether the observed order is in the asymptotic range.
    pub asymptotic: bool,
    /// FEM stiffness on the finest level (N/m).
    pub finest_level_n_per_m: f64,
    /// Unknowns on the finest level.
    pub finest_level_unknowns: usize,
    /// fem_error_estimate ≤ [`ERROR_TOLERANCE`] and the sequence is asymptotic.
    pub converged: bool,
    /// |relative_difference| ≤ [`AGREEMENT_TOLERANCE`].
    pub agrees: bool,
    /// The formula of the partner boundary condition (bonded ↔ frictional), for the
    /// wrong-boundary-condition check.
    pub partner_spring: Spring,
    /// fem / partner formula − 1.
    #[serde(deserialize_with = "crate::serde_nan::f64_or_nan")]
    pub partner_relative_difference: f64,
    /// |partner_relative_difference| > fem_error_estimate + AGREEMENT_TOLERANCE: the FEM value
    /// rejects the wrong condition.
    pub tells_partner_apart: bool,
}

/// One point of the truncation study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TruncationPoint {
    /// Spring.
    pub spring: Spring,
    /// Material name.
    pub material: String,
    /// R / a.
    pub truncation_ratio: f64,
    /// Point-force far field: FEM / formula.
    pub point_force_over_analytic: f64,
    /// Clamped far field: FEM / formula.
    pub clamped_over_analytic: f64,
    /// Unknowns.
    pub unknowns: usize,
}

/// One point of the work-precision comparison.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WorkPrecisionPoint {
    /// 1 Tet4, 2 Tet10.
    pub order: u8,
    /// Level.
    pub level: usize,
    /// h_e / a.
    pub h_edge_over_a: f64,
    /// Unknowns.
    pub unknowns: usize,
    /// Wall time of one solve from the mesh in memory (pattern to reactions), the smallest of
    /// [`WORK_PRECISION_REPETITIONS`] runs (s).
    pub wall_s: f64,
    /// Stage times of that run.
    pub timings: crate::punch::StageTimings,
    /// |FEM / exact − 1|.
    #[serde(deserialize_with = "crate::serde_nan::f64_or_nan")]
    pub relative_error: f64,
}

/// Results of the stability section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StabilityResults {
    /// Locking study: unknowns of the Tet4 and Tet10 meshes.
    pub locking_unknowns: [usize; 2],
    /// k_sn / analytic for Tet4 and Tet10 as ν → 1/2.
    pub locking: Vec<LockingPoint>,
    /// Floating punch: the two error messages.
    pub singular_system: SingularSystemReport,
    /// Distorted Tet10 meshes: quality and k_sn.
    pub distortion: Vec<DistortionPoint>,
    /// Mesh of the distortion study.
    pub distortion_mesh: String,
}

/// Everything the springs validation found.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SpringsValidation {
    /// One row per spring × material × radius.
    pub cases: Vec<SpringCase>,
    /// Raw per-level results of the convergence study.
    pub levels: Vec<LevelResult>,
    /// Truncation study.
    pub truncation: Vec<TruncationPoint>,
    /// Work-precision points.
    pub work_precision: Vec<WorkPrecisionPoint>,
    /// Spring, material and radius of the work-precision comparison.
    pub work_precision_case: Option<WorkPrecisionOptions>,
    /// Stability section.
    pub stability: Option<StabilityResults>,
    /// Mesh family of the convergence study.
    pub family: MeshFamily,
    /// Model of the tangential springs.
    pub tangential_symmetry: MeshSymmetry,
    /// [`ERROR_TOLERANCE`].
    pub error_tolerance: f64,
    /// [`AGREEMENT_TOLERANCE`].
    pub agreement_tolerance: f64,
    /// Whole study wall time (s).
    pub wall_s: f64,
    /// 1-minute load average of the machine at the start and end of the study (Linux
    /// /proc/loadavg; NaN elsewhere): context for the wall times on a shared machine.
    #[serde(deserialize_with = "crate::serde_nan::pair_or_nan")]
    pub load_average: [f64; 2],
    /// Logical CPUs available.
    pub cpus: usize,
}

/// The 1-minute load average, or NaN.
fn load_average() -> f64 {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse().ok())
        .unwrap_or(f64::NAN)
}

impl SpringsValidation {
    /// Whether every case converged and agrees with its formula.
    pub fn all_pass(&self) -> bool {
        self.cases.iter().all(|c| c.converged && c.agrees)
    }

    /// The `--json` output: the array of cases.
    pub fn cases_json(&self) -> Result<String, ValidationError> {
        serde_json::to_string_pretty(&self.cases).map_err(|source| ValidationError::Json {
            what: "springs validation cases",
            source,
        })
    }
}

struct Runner<'o> {
    options: &'o SpringsOptions,
    start: Instant,
}

impl Runner<'_> {
    fn log(&self, message: impl AsRef<str>) {
        if self.options.progress {
            eprintln!(
                "[{:7.1} s] {}",
                self.start.elapsed().as_secs_f64(),
                message.as_ref()
            );
        }
    }

    fn symmetry_of(&self, spring: Spring) -> MeshSymmetry {
        if spring.is_normal() {
            MeshSymmetry::Quarter
        } else {
            self.options.tangential_symmetry
        }
    }

    /// Springs grouped by the mesh symmetry they use (quarter first).
    fn spring_groups(&self) -> BTreeMap<&'static str, (MeshSymmetry, Vec<Spring>)> {
        let mut groups: BTreeMap<&'static str, (MeshSymmetry, Vec<Spring>)> = BTreeMap::new();
        for &s in &self.options.springs {
            let sym = self.symmetry_of(s);
            groups
                .entry(if sym == MeshSymmetry::Quarter {
                    "0"
                } else {
                    "1"
                })
                .or_insert((sym, Vec::new()))
                .1
                .push(s);
        }
        groups
    }

    fn read_mesh(
        &self,
        family: &MeshFamily,
        level: usize,
        radius_m: f64,
        symmetry: MeshSymmetry,
        ratio: f64,
    ) -> Result<(PunchMesh, String), ValidationError> {
        let parameters = family.with_truncation(level, radius_m, symmetry, ratio);
        let t = Instant::now();
        let path = self.options.cache.punch_mesh(&parameters)?;
        let generated_s = t.elapsed().as_secs_f64();
        let mesh = PunchMesh::read(&path)?;
        self.log(format!(
            "mesh {} ({} nodes, {} elements; {generated_s:.1} s to find or generate)",
            path.display(),
            mesh.node_count(),
            mesh.element_count()
        ));
        let name = path
            .file_name()
            .map(|f| f.to_string_lossy().to_string())
            .unwrap_or_default();
        Ok((mesh, name))
    }

    /// Solves `springs` for all materials on one mesh.
    fn solve_on(
        &self,
        mesh: &PunchMesh,
        materials: &[Material],
        springs: &[Spring],
    ) -> Result<Vec<PunchStiffness>, ValidationError> {
        let mut out = Vec::new();
        for material in materials {
            let assembled = AssembledPunch::new(mesh, material)?;
            for &spring in springs {
                let r = assembled.solve(spring, &self.options.solve)?;
                self.log(format!(
                    "  {} {:7} {} unknowns: k = {:.6e} N/m (k/formula = {:.5}; clamped {:.5}), factor {:.1} s",
                    spring,
                    material.name,
                    r.unknowns,
                    r.stiffness_n_per_m,
                    r.stiffness_n_per_m / spring.analytic_n_per_m(material, mesh.radius_m)?,
                    r.clamped_stiffness_n_per_m / spring.analytic_n_per_m(material, mesh.radius_m)?,
                    r.timings.numeric_s
                ));
                out.push(r);
            }
        }
        Ok(out)
    }
}

/// Runs the springs validation.
pub fn validate_springs(options: &SpringsOptions) -> Result<SpringsValidation, ValidationError> {
    options.validate()?;
    let runner = Runner {
        options,
        start: Instant::now(),
    };
    let load_at_start = load_average();
    let family = options.family;
    let levels = runner.ladders()?;
    let truncation = runner.truncation_study()?;
    let cases = cases(options, &levels, &truncation)?;
    let work_precision = runner.work_precision()?;
    let stability = runner.stability()?;
    Ok(SpringsValidation {
        cases,
        levels,
        truncation,
        work_precision,
        work_precision_case: options.work_precision.clone(),
        stability,
        family,
        tangential_symmetry: options.tangential_symmetry,
        error_tolerance: ERROR_TOLERANCE,
        agreement_tolerance: AGREEMENT_TOLERANCE,
        wall_s: runner.start.elapsed().as_secs_f64(),
        load_average: [load_at_start, load_average()],
        cpus: std::thread::available_parallelism().map_or(1, |n| n.get()),
    })
}

impl Runner<'_> {
    /// The study's material of that name, if it has one.
    fn material_named(&self, name: &str) -> Option<Material> {
        self.options
            .materials
            .iter()
            .find(|m| m.name == name)
            .cloned()
    }

    /// 1. Convergence ladders: every radius, level and spring group on its mesh.
    fn ladders(&self) -> Result<Vec<LevelResult>, ValidationError> {
        let mut levels: Vec<LevelResult> = Vec::new();
        for &radius_m in &self.options.radii_m {
            for level in 0..self.options.levels {
                for (symmetry, springs) in self.spring_groups().into_values() {
                    let (mesh, name) = self.read_mesh(
                        &self.options.family,
                        level,
                        radius_m,
                        symmetry,
                        self.options.family.truncation_ratio,
                    )?;
                    for result in self.solve_on(&mesh, &self.options.materials, &springs)? {
                        levels.push(LevelResult {
                            level,
                            h_edge_over_a: self.options.family.h_edge(level),
                            growth: self.options.family.growth(level),
                            mesh: name.clone(),
                            result,
                        });
                    }
                }
            }
        }
        Ok(levels)
    }

    /// 2. Truncation study (level 0, first radius): point-force and clamped far fields.
    fn truncation_study(&self) -> Result<Vec<TruncationPoint>, ValidationError> {
        let mut truncation = Vec::new();
        for &ratio in &self.options.truncation_ratios {
            for (symmetry, springs) in self.spring_groups().into_values() {
                let (mesh, _) = self.read_mesh(
                    &self.options.family,
                    0,
                    self.options.radii_m[0],
                    symmetry,
                    ratio,
                )?;
                for r in self.solve_on(&mesh, &self.options.materials, &springs)? {
                    let material = self
                        .material_named(&r.material)
                        .unwrap_or_else(Material::silicon);
                    let analytic = r.spring.analytic_n_per_m(&material, r.radius_m)?;
                    truncation.push(TruncationPoint {
                        spring: r.spring,
                        material: r.material.clone(),
                        truncation_ratio: ratio,
                        point_force_over_analytic: r.stiffness_n_per_m / analytic,
                        clamped_over_analytic: r.clamped_stiffness_n_per_m / analytic,
                        unknowns: r.unknowns,
                    });
                }
            }
        }
        Ok(truncation)
    }

    /// 4. Work-precision: error against cost on the Tet10 and Tet4 ladders (best of the
    /// repetitions).
    fn work_precision(&self) -> Result<Vec<WorkPrecisionPoint>, ValidationError> {
        let mut work_precision = Vec::new();
        if let Some(wp) = &self.options.work_precision {
            let material = self
                .material_named(&wp.material)
                .unwrap_or_else(Material::lithium_niobate);
            let exact = wp.spring.analytic_n_per_m(&material, wp.radius_m)?;
            let symmetry = self.symmetry_of(wp.spring);
            for (fam, count) in [
                (self.options.family, wp.tet10_levels),
                (wp.tet4_family, wp.tet4_levels),
            ] {
                for level in 0..count {
                    let (mesh, _) =
                        self.read_mesh(&fam, level, wp.radius_m, symmetry, fam.truncation_ratio)?;
                    let mut best: Option<PunchStiffness> = None;
                    for _ in 0..WORK_PRECISION_REPETITIONS {
                        let r = self
                            .solve_on(&mesh, std::slice::from_ref(&material), &[wp.spring])?
                            .remove(0);
                        if best
                            .as_ref()
                            .is_none_or(|b| r.timings.total_s() < b.timings.total_s())
                        {
                            best = Some(r);
                        }
                    }
                    let Some(result) = best else { continue };
                    work_precision.push(WorkPrecisionPoint {
                        order: fam.order,
                        level,
                        h_edge_over_a: fam.h_edge(level),
                        unknowns: result.unknowns,
                        wall_s: result.timings.total_s(),
                        timings: result.timings,
                        relative_error: (result.stiffness_n_per_m / exact - 1.0).abs(),
                    });
                }
            }
        }
        Ok(work_precision)
    }

    /// 5. Stability: locking, the singular (floating) system and distorted meshes.
    fn stability(&self) -> Result<Option<StabilityResults>, ValidationError> {
        let stability = match &self.options.stability {
            None => None,
            Some(st) => {
                let material = self
                    .material_named("linbo3")
                    .unwrap_or_else(|| self.options.materials[0].clone());
                let radius_m = self.options.radii_m[0];
                let tet4_family = self
                    .options
                    .work_precision
                    .as_ref()
                    .map_or_else(MeshFamily::tet4, |w| w.tet4_family);
                let (tet4, _) = self.read_mesh(
                    &tet4_family,
                    st.tet4_level,
                    radius_m,
                    MeshSymmetry::Quarter,
                    tet4_family.truncation_ratio,
                )?;
                let (tet10, tet10_name) = self.read_mesh(
                    &self.options.family,
                    st.tet10_level,
                    radius_m,
                    MeshSymmetry::Quarter,
                    self.options.family.truncation_ratio,
                )?;
                self.log("locking study");
                let locking = locking_study(
                    &tet4,
                    &tet10,
                    &material,
                    &st.poisson_ratios,
                    &self.options.solve,
                )?;
                let unknowns = |m: &PunchMesh| -> Result<usize, ValidationError> {
                    Ok(AssembledPunch::new(m, &material)?
                        .solve(Spring::FrictionlessNormal, &self.options.solve)?
                        .unknowns)
                };
                let locking_unknowns = [unknowns(&tet4)?, unknowns(&tet10)?];
                self.log("singular system");
                let full = tet4
                    .mirrored(crate::punch_mesh::MirrorPlane::X0)?
                    .mirrored(crate::punch_mesh::MirrorPlane::Y0)?;
                let singular = singular_system(&full, &material)?;
                self.log("distorted meshes");
                let distortion = distortion_study(
                    &tet10,
                    &material,
                    Spring::FrictionlessNormal,
                    &st.distortion_amplitudes,
                    &self.options.solve,
                )?;
                Some(StabilityResults {
                    locking_unknowns,
                    locking,
                    singular_system: singular,
                    distortion,
                    distortion_mesh: tet10_name,
                })
            }
        };
        Ok(stability)
    }
}

/// 3. Cases: every radius, material and spring against its formula.
fn cases(
    options: &SpringsOptions,
    levels: &[LevelResult],
    truncation: &[TruncationPoint],
) -> Result<Vec<SpringCase>, ValidationError> {
    let mut cases = Vec::new();
    for &radius_m in &options.radii_m {
        for material in &options.materials {
            for &spring in &options.springs {
                cases.push(make_case(
                    options, levels, truncation, spring, material, radius_m,
                )?);
            }
        }
    }
    Ok(cases)
}

/// Two truncation ratios closer than this (relative) are the same. Dimensionless; default 1e-9.
const RATIO_MATCH_TOLERANCE: f64 = 1e-9;

/// Relative truncation error at the family's R/a from the point-force results at R/a and at the
/// largest R/a of the study, assuming the O((a/R)²) behaviour of the point-force far field:
/// e(R) = (k(R) − k(R_max)) / (1 − (R/R_max)²). NaN if the study lacks either.
fn truncation_estimate(
    truncation: &[TruncationPoint],
    spring: Spring,
    material: &str,
    ratio: f64,
) -> f64 {
    let of = |r: f64| {
        truncation
            .iter()
            .find(|t| {
                t.spring == spring
                    && t.material == material
                    && (t.truncation_ratio / r - 1.0).abs() < RATIO_MATCH_TOLERANCE
            })
            .map(|t| t.point_force_over_analytic)
    };
    let largest = truncation
        .iter()
        .filter(|t| t.spring == spring && t.material == material)
        .map(|t| t.truncation_ratio)
        .fold(f64::NAN, f64::max);
    match (of(ratio), of(largest)) {
        (Some(k), Some(k_far)) if largest > ratio => {
            ((k - k_far) / (1.0 - (ratio / largest).powi(2))).abs() / k_far
        }
        _ => f64::NAN,
    }
}

fn make_case(
    options: &SpringsOptions,
    levels: &[LevelResult],
    truncation: &[TruncationPoint],
    spring: Spring,
    material: &Material,
    radius_m: f64,
) -> Result<SpringCase, ValidationError> {
    let mut ladder: Vec<&LevelResult> = levels
        .iter()
        .filter(|l| {
            l.result.spring == spring
                && l.result.material == material.name
                && (l.result.radius_m / radius_m - 1.0).abs() < MESH_RADIUS_TOLERANCE
        })
        .collect();
    ladder.sort_by_key(|l| l.level);
    let h: Vec<f64> = ladder.iter().map(|l| l.h_edge_over_a).collect();
    let k: Vec<f64> = ladder.iter().map(|l| l.result.stiffness_n_per_m).collect();
    let quantity = format!("{spring} ({}, a = {} um)", material.name, radius_m * 1e6);
    let extrapolation = extrapolate(&quantity, &h, &k)?;
    let analytic = spring.analytic_n_per_m(material, radius_m)?;
    let partner = spring.partner();
    let partner_analytic = partner.analytic_n_per_m(material, radius_m)?;
    let fem = extrapolation.value;
    let discretisation = extrapolation.error_estimate / fem;
    let truncation_rel = truncation_estimate(
        truncation,
        spring,
        &material.name,
        options.family.truncation_ratio,
    );
    let error = discretisation
        + if truncation_rel.is_finite() {
            truncation_rel
        } else {
            0.0
        };
    let relative_difference = fem / analytic - 1.0;
    let partner_relative_difference = fem / partner_analytic - 1.0;
    let finest = ladder.last().map(|l| &l.result);
    Ok(SpringCase {
        spring,
        material: material.name.clone(),
        radius_m,
        fem_n_per_m: fem,
        fem_error_estimate: error,
        analytic_n_per_m: analytic,
        relative_difference,
        discretisation_error_estimate: discretisation,
        truncation_error_estimate: truncation_rel,
        observed_order: extrapolation.observed_order,
        asymptotic: extrapolation.asymptotic,
        finest_level_n_per_m: extrapolation.finest,
        finest_level_unknowns: finest.map_or(0, |r| r.unknowns),
        converged: error <= ERROR_TOLERANCE
            && extrapolation.asymptotic
            && truncation_rel.is_finite(),
        agrees: relative_difference.abs() <= AGREEMENT_TOLERANCE,
        partner_spring: partner,
        partner_relative_difference,
        tells_partner_apart: partner_relative_difference.abs() > error + AGREEMENT_TOLERANCE,
    })
}

/// The punch radius read from a mesh matches the requested one to this relative tolerance
/// (the radius is the largest punch-node distance from the axis, exact for gmsh's circle nodes).
/// Dimensionless; default 1e-6.
const MESH_RADIUS_TOLERANCE: f64 = 1e-6;
