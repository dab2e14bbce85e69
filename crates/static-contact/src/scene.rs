//! The condensed strip scene: slider strip (FEM) + stator (half-space or meshed block) reduced to
//! one dense post compliance, and the contact solve of one snapshot.
//!
//! Scales resolved: the slider FEM resolves each post (its tip disk is meshed at `h_post`) and
//! the slider body between posts and up to the rigid backing at the top (0.5 mm ≫ λ/2π ≈ 66 µm,
//! so a wave-scale load pattern has decayed to e^{−kt} ≈ 5·10⁻⁴ there); the stator enters by its
//! exact half-space disk compliance (self term = 1/k_sn) and the mutual terms of all posts of the
//! real slider (rows in y summed by mirror unfolding), or by a meshed block. Not resolved: slider
//! bending on the 5 mm scale (rigid backing), stator plate bending (half-space), friction.

use contact_springs::Material;
use gmsh_mesh::TetMesh;
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::body::{BodyCompliance, BodySpec, Disk, TipLateral};
use crate::error::{ContactError, Result};
use crate::halfspace::{
    RowLayout, StripPost, normal_tangential_cross_compliance, strip_compliance,
    strip_tangential_compliance,
};
use crate::lcp::{ActiveSetOptions, ActiveSetSolver, ContactProblem, ContactSolution};

/// Relative tolerance between the mesh's post radius/pitch and the requested ones. Default 2 %.
pub const GEOMETRY_MATCH_TOLERANCE: f64 = 0.02;

/// How the stator's compliance enters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum StatorModel {
    /// Elastic half-space, rigid-disk compliances (Johnson §3.8), rows of the real slider summed.
    #[default]
    HalfSpace,
    /// The `stator` volume of the slider-strip mesh: bottom clamped, symmetry planes in y,
    /// rollers (u_x = 0) on its x ends; the disks under the posts rigid in z, frictionless.
    MeshedBlock,
}

impl StatorModel {
    /// Each model by its scene name (`static.stator`).
    pub const NAMES: [(&'static str, Self); 2] = [
        ("half-space", Self::HalfSpace),
        ("meshed-block", Self::MeshedBlock),
    ];
}

/// What the strip scene needs besides the mesh.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StripConfig {
    /// Slider material (isotropic).
    pub slider_material: Material,
    /// Stator material (isotropic).
    pub stator_material: Material,
    /// Post radius a (m).
    pub post_radius_m: f64,
    /// Post height h (m), checked against the mesh's posts.
    pub post_height_m: f64,
    /// Post pitch in y (m): the strip's width per row.
    pub pitch_m: f64,
    /// Rows of posts of the real slider (for the half-space row sum).
    pub slider_rows: usize,
    /// Expected posts in the strip (checked against the mesh), if known.
    pub expected_strip_posts: Option<usize>,
    /// Stator model.
    pub stator: StatorModel,
    /// Linear solver of the FEM bodies (`static.fem_solver`; default auto).
    pub fem_solver: crate::FemSolver,
}

/// A post of the strip.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PostSite {
    /// Centre x (m).
    pub x_m: f64,
    /// Centre y (m).
    pub y_m: f64,
    /// Row in the strip.
    pub row: usize,
}

/// The stator side of the condensed scene.
#[derive(Debug)]
pub enum StatorCompliance {
    /// Half-space (analytic).
    HalfSpace(DMatrix<f64>),
    /// Meshed block.
    Meshed(Box<BodyCompliance>),
}

impl StatorCompliance {
    /// The stator's dense compliance (m/N).
    pub fn matrix(&self) -> &DMatrix<f64> {
        match self {
            StatorCompliance::HalfSpace(c) => c,
            StatorCompliance::Meshed(b) => &b.compliance_m_per_n,
        }
    }
}

/// Normal and tangential tip compliance of the strip (see [`StripModel::tip_compliance`]).
#[derive(Debug, Clone, PartialEq)]
pub struct TipCompliance {
    /// C_nn (m/N), the static stage's compliance.
    pub normal_m_per_n: DMatrix<f64>,
    /// C_tt (m/N): x displacement of tip i relative to the stator per unit x force on tip j.
    pub tangential_m_per_n: DMatrix<f64>,
    /// Slider-side cross term: normal tip displacement per unit x force (m/N).
    pub slider_cross_m_per_n: DMatrix<f64>,
    /// Stator-side cross term: normal surface displacement under tip i per unit x force on
    /// tip j (m/N).
    pub stator_cross_m_per_n: DMatrix<f64>,
}

impl TipCompliance {
    /// Relative size of a cross-term matrix: max |C_zx,ij| / √(max C_nn,ii · max C_tt,jj).
    pub fn cross_ratio(&self, cross: &DMatrix<f64>) -> f64 {
        let dn = self.normal_m_per_n.diagonal().max();
        let dt = self.tangential_m_per_n.diagonal().max();
        cross.amax() / (dn * dt).sqrt()
    }
}

/// The strip condensed onto its posts.
#[derive(Debug)]
pub struct StripModel {
    /// The mesh.
    pub mesh: TetMesh,
    /// Posts in x order (row-major for several rows).
    pub posts: Vec<PostSite>,
    /// Strip rows.
    pub strip_rows: usize,
    /// The slider body.
    pub slider: BodyCompliance,
    /// The stator.
    pub stator: StatorCompliance,
    /// Total compliance C = C_slider + C_stator (m/N).
    pub compliance_m_per_n: DMatrix<f64>,
    /// The configuration.
    pub config: StripConfig,
}

pub(crate) fn fem_material(m: &Material) -> Result<elastic_fem::Material> {
    elastic_fem::Material::isotropic(m.youngs_modulus_pa(), m.poisson_ratio).map_err(|source| {
        ContactError::Fem {
            body: "material",
            file: m.name.clone(),
            source: Box::new(source),
        }
    })
}

/// Post height of a `slider-strip` mesh (m): from the tip plane (the disks' mean z) to the
/// lowest node of the `slider` volume outside every post's cylinder (the body's underside,
/// z = h in slider-strip.geo). A node counts as outside when it lies farther than
/// (1 + [`GEOMETRY_MATCH_TOLERANCE`]) a from every post axis.
pub fn measured_post_height(mesh: &TetMesh, disks: &[Disk]) -> Result<f64> {
    let file = mesh.source.clone();
    let nodes = mesh
        .group_nodes("slider")
        .map_err(|source| ContactError::Mesh {
            file: file.clone(),
            source: Box::new(source),
        })?;
    let tip_z = disks.iter().map(|d| d.centre_m[2]).sum::<f64>() / disks.len().max(1) as f64;
    let outside = |p: &[f64; 3]| {
        disks.iter().all(|d| {
            let r = d.radius_m * (1.0 + GEOMETRY_MATCH_TOLERANCE);
            (p[0] - d.centre_m[0]).powi(2) + (p[1] - d.centre_m[1]).powi(2) > r * r
        })
    };
    nodes
        .iter()
        .map(|&n| mesh.nodes[n])
        .filter(|p| outside(p))
        .map(|p| p[2] - tip_z)
        .min_by(f64::total_cmp)
        .ok_or_else(|| ContactError::MeshMismatch {
            file,
            detail: "the `slider` volume has no node between the posts: cannot measure the \
                     post height"
                .into(),
        })
}

impl StripModel {
    /// Builds the condensed scene from a `slider-strip` mesh (groups of meshes/README.md).
    pub fn build(mesh: TetMesh, config: StripConfig) -> Result<Self> {
        Self::build_with_order_cache(mesh, config, None)
    }

    /// [`Self::build`] with the bodies' fill-reducing orderings read from or stored in the folder
    /// `order_cache` (see [`BodyCompliance::build_with_order_cache`]).
    pub fn build_with_order_cache(
        mesh: TetMesh,
        config: StripConfig,
        order_cache: Option<&std::path::Path>,
    ) -> Result<Self> {
        // Half disks: the one-row strip cut at its mirror plane y = W/2 (slider-strip.geo
        // `half_y`); each body then carries half of each post's force.
        let (disks, disk_fraction) =
            crate::posts::find_tip_disks_with_fraction(&mesh, "post_tips")?;
        check_tip_disks(&mesh, &config, &disks)?;
        let y0 = mesh.bounding_box().map_or(0.0, |b| b[0][1]);
        let posts: Vec<PostSite> = disks
            .iter()
            .map(|d| PostSite {
                x_m: d.centre_m[0],
                y_m: d.centre_m[1],
                row: ((d.centre_m[1] - y0) / config.pitch_m - 0.5)
                    .round()
                    .max(0.0) as usize,
            })
            .collect();
        let strip_rows = posts.iter().map(|p| p.row + 1).max().unwrap_or(1);
        let disks: Vec<Disk> = disks
            .iter()
            .map(|d| Disk {
                radius_m: config.post_radius_m,
                ..*d
            })
            .collect();
        let slider = BodyCompliance::build_with_solver(
            &BodySpec {
                name: "slider",
                mesh: &mesh,
                volume_group: "slider".into(),
                material: fem_material(&config.slider_material)?,
                contact_group: "post_tips".into(),
                disks: disks.clone(),
                lateral: TipLateral::Free,
                clamped_groups: vec!["slider_top".into()],
                roller_groups: vec![("slider_sym_y0".into(), 1), ("slider_sym_y1".into(), 1)],
                disk_fraction,
                force_sign: 1.0,
            },
            order_cache,
            config.fem_solver,
        )?;
        let stator = match config.stator {
            StatorModel::HalfSpace => half_space_stator(&config, &posts, strip_rows)?,
            StatorModel::MeshedBlock => {
                meshed_stator(&mesh, &config, disks, disk_fraction, order_cache)?
            }
        };
        let compliance_m_per_n = &slider.compliance_m_per_n + stator.matrix();
        Ok(Self {
            mesh,
            posts,
            strip_rows,
            slider,
            stator,
            compliance_m_per_n,
            config,
        })
    }

    /// Normal and tangential (x) tip compliance of the strip for the coupled dynamics, from the
    /// slider's existing factorisation ([`BodyCompliance::tangential_compliance`]) plus the
    /// stator's tangential compliance (half-space: rigid-disk self term and Cerruti mutual terms
    /// with the row images, [`strip_tangential_compliance`]; meshed block: its own factor).
    ///
    /// The normal–tangential cross terms are returned separately (slider side from the FEM,
    /// stator side from the half-space point-force coupling, −(1−2ν)dx/(4πGr²), images summed)
    /// so that a caller can quantify what it drops.
    pub fn tip_compliance(&self) -> Result<TipCompliance> {
        let slider = self.slider.tangential_compliance()?;
        let (stator_tangential, stator_cross) = match &self.stator {
            StatorCompliance::HalfSpace(_) => {
                let m = &self.config.stator_material;
                let sites: Vec<StripPost> = self
                    .posts
                    .iter()
                    .map(|p| StripPost {
                        x_m: p.x_m,
                        row: p.row,
                    })
                    .collect();
                let layout = RowLayout {
                    pitch_m: self.config.pitch_m,
                    strip_rows: self.strip_rows,
                    slider_rows: self.config.slider_rows,
                };
                let tangential = strip_tangential_compliance(
                    m.shear_modulus_pa,
                    m.poisson_ratio,
                    self.config.post_radius_m,
                    &sites,
                    &layout,
                );
                let n = self.posts.len();
                let first = layout.first_strip_row();
                let cross = DMatrix::from_fn(n, n, |i, j| {
                    let yi = self.posts[i].row as f64 * layout.pitch_m;
                    (0..layout.slider_rows)
                        .filter(|&k| layout.strip_row_of(k) == self.posts[j].row)
                        .map(|k| {
                            let yk = (k as f64 - first as f64) * layout.pitch_m;
                            normal_tangential_cross_compliance(
                                m.shear_modulus_pa,
                                m.poisson_ratio,
                                self.posts[i].x_m - self.posts[j].x_m,
                                yi - yk,
                            )
                        })
                        .sum::<f64>()
                });
                (tangential, cross)
            }
            StatorCompliance::Meshed(body) => {
                let t = body.tangential_compliance()?;
                (t.tangential_m_per_n, t.normal_from_tangential_m_per_n)
            }
        };
        Ok(TipCompliance {
            normal_m_per_n: self.compliance_m_per_n.clone(),
            tangential_m_per_n: &slider.tangential_m_per_n + &stator_tangential,
            slider_cross_m_per_n: slider.normal_from_tangential_m_per_n,
            stator_cross_m_per_n: stator_cross,
        })
    }

    /// Number of posts in the strip.
    pub fn post_count(&self) -> usize {
        self.posts.len()
    }

    /// Solves the contact of the strip under `preload_strip_n` (N, the strip's share of the
    /// preload) on obstacle heights `height_m` (m, one per post). `length_scale_m` scales gaps
    /// in the residual (the wave amplitude; `None` on a flat stator).
    pub fn solve(
        &self,
        preload_strip_n: f64,
        height_m: Vec<f64>,
        length_scale_m: Option<f64>,
        options: ActiveSetOptions,
    ) -> Result<ContactSolution> {
        let problem = ContactProblem {
            compliance_m_per_n: self.compliance_m_per_n.clone(),
            obstacle_height_m: height_m,
            preload_n: preload_strip_n,
            length_scale_m,
        };
        ActiveSetSolver::new(options).solve(&problem)
    }
}

/// The tip disks found in the mesh against the scene: their count (if the scene says it), radius
/// and the posts' height, each within [`GEOMETRY_MATCH_TOLERANCE`].
fn check_tip_disks(mesh: &TetMesh, config: &StripConfig, disks: &[Disk]) -> Result<()> {
    let mismatch = |detail: String| ContactError::MeshMismatch {
        file: mesh.source.clone(),
        detail,
    };
    if let Some(n) = config.expected_strip_posts
        && disks.len() != n
    {
        // A half strip meshed for reflection (slider-strip.geo `mirror_x = 1`) given as a
        // file: it is used as it is, so say what it is.
        let hint = if mesh.group("slider_mirror_x").is_some() {
            "; this mesh is the half x ≤ L/2 of a strip (slider-strip.geo mirror_x = 1): \
             give the whole strip (mirror_x = 0)"
        } else {
            ""
        };
        return Err(mismatch(format!(
            "group `post_tips` has {} tip disks, the scene has {n} posts in the strip{hint}",
            disks.len()
        )));
    }
    for (i, d) in disks.iter().enumerate() {
        if (d.radius_m / config.post_radius_m - 1.0).abs() > GEOMETRY_MATCH_TOLERANCE {
            return Err(mismatch(format!(
                "post {i} has radius {:.4e} m, the scene asks for post_radius_m = {:.4e} m \
                 (tolerance {} %)",
                d.radius_m,
                config.post_radius_m,
                GEOMETRY_MATCH_TOLERANCE * 100.0
            )));
        }
    }
    let height_m = measured_post_height(mesh, disks)?;
    if (height_m / config.post_height_m - 1.0).abs() > GEOMETRY_MATCH_TOLERANCE {
        return Err(mismatch(format!(
            "the posts are {height_m:.4e} m high, the scene asks for post_height_m = {:.4e} m \
             (tolerance {} %)",
            config.post_height_m,
            GEOMETRY_MATCH_TOLERANCE * 100.0
        )));
    }
    Ok(())
}

/// The half-space stator's compliance at the strip's posts, summed over the slider's rows.
fn half_space_stator(
    config: &StripConfig,
    posts: &[PostSite],
    strip_rows: usize,
) -> Result<StatorCompliance> {
    if config.slider_rows < strip_rows {
        return Err(ContactError::InvalidParameter {
            parameter: "posts_y",
            value: config.slider_rows as f64,
            reason: format!("the slider has fewer rows than the strip ({strip_rows})"),
        });
    }
    let sites: Vec<StripPost> = posts
        .iter()
        .map(|p| StripPost {
            x_m: p.x_m,
            row: p.row,
        })
        .collect();
    let layout = RowLayout {
        pitch_m: config.pitch_m,
        strip_rows,
        slider_rows: config.slider_rows,
    };
    Ok(StatorCompliance::HalfSpace(strip_compliance(
        config.stator_material.shear_modulus_pa,
        config.stator_material.poisson_ratio,
        config.post_radius_m,
        &sites,
        &layout,
    )))
}

/// The meshed stator block's compliance at the tip disks (bottom clamped, rollers on its
/// symmetry planes and x ends).
fn meshed_stator(
    mesh: &TetMesh,
    config: &StripConfig,
    disks: Vec<Disk>,
    disk_fraction: f64,
    order_cache: Option<&std::path::Path>,
) -> Result<StatorCompliance> {
    Ok(StatorCompliance::Meshed(Box::new(
        BodyCompliance::build_with_solver(
            &BodySpec {
                name: "stator",
                mesh,
                volume_group: "stator".into(),
                material: fem_material(&config.stator_material)?,
                contact_group: "stator_top".into(),
                disks,
                lateral: TipLateral::Free,
                clamped_groups: vec!["stator_bottom".into()],
                roller_groups: vec![
                    ("stator_sym_y0".into(), 1),
                    ("stator_sym_y1".into(), 1),
                    ("stator_x0".into(), 0),
                    ("stator_x1".into(), 0),
                ],
                disk_fraction,
                force_sign: -1.0,
            },
            order_cache,
            config.fem_solver,
        )?,
    )))
}
