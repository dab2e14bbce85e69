//! The post's near field from the one-off cell FEM: the slider side's self compliance s_post
//! taken from the strip FEM's condensed compliance (static_contact's `slider-strip`: symmetry
//! planes in y, i.e. infinitely many identical rows, body bonded to a rigid top).
//!
//! The lattice model of the same strip gives, for posts i, j of the row (distance x_ij),
//!
//! C^lat_ij = δ_ij (s_post + ΔK(0)) + Σ_{m ∈ ℤ, (m, x_ij) ≠ (0, 0)} c_body(√(x_ij² + (m p)²)),
//!
//! (the body's far field [`crate::LatticeKernel::body_mutual`]; the sum converges because the
//! bonded layer's displacement decays as e^{−r/t}). Equating the diagonal for the central posts
//! of the strip gives s_post = C^FEM_ii − (C^lat_ii − s_post), which contains what the far field
//! does not: the 2 µm post column, the bonded base and the FEM's own discretisation. The
//! differential compliances C_ii − C_ij of the FEM and of the lattice, which do not depend on
//! s_post, test the far field (the split); [`NearFieldCalibration::differential`] lists them.
//!
//! **Tangential** ([`calibrate_tangential_near_field`]): the same construction on the strip
//! FEM's condensed tangential compliance of the slider body (`BodyCompliance::
//! tangential_compliance`, C_xx = WᵀK⁻¹W from the same factor) with the tangential body kernel
//! ([`crate::TangentialKernel::body_mutual`], Cerruti + ΔK_t; x forces are even under the strip's
//! y mirrors, so the image rows carry the same force): s_t,post = C^FEM_t,ii − (C^lat_t,ii −
//! s_t,post), averaged over the central posts, the differential compliances listed as the check.

use serde::{Deserialize, Serialize};
use static_contact::StripModel;

use crate::error::{Result, invalid};
use crate::lattice::{LatticeGeometry, LatticeKernel, NearField, OperatorSpec};
use crate::layer::TABLE_MIN_RANGE_OVER_T;

/// Fraction of the strip's posts, around its middle, over which s_post is averaged (away from
/// the strip's free ends). Dimensionless; default 0.2 (at least one post).
pub const CENTRAL_FRACTION: f64 = 0.2;

/// One differential compliance C_ii − C_ij (m/N) of a central post i.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DifferentialCheck {
    /// Post i.
    pub post: usize,
    /// Post j.
    pub other: usize,
    /// FEM value (m/N).
    pub fem_m_per_n: f64,
    /// Lattice value (m/N).
    pub lattice_m_per_n: f64,
}

/// The near field taken from a strip FEM.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NearFieldCalibration {
    /// s_post (m/N).
    pub slider_self_compliance_m_per_n: f64,
    /// Johnson's 1/k_pn (normal) or 1/k_pt (tangential) for comparison (m/N).
    pub johnson_m_per_n: f64,
    /// Central posts averaged.
    pub posts: Vec<usize>,
    /// C_ii − C_ij of the central posts against every other post of the row.
    pub differential: Vec<DifferentialCheck>,
}

impl NearFieldCalibration {
    /// The near field to give the lattice operator.
    pub fn near_field(&self) -> NearField {
        NearField::Value {
            slider_self_compliance_m_per_n: self.slider_self_compliance_m_per_n,
        }
    }

    /// Largest |lattice/FEM − 1| of the differential compliances.
    pub fn worst_differential_mismatch(&self) -> f64 {
        self.differential
            .iter()
            .map(|d| (d.lattice_m_per_n / d.fem_m_per_n - 1.0).abs())
            .fold(0.0, f64::max)
    }
}

/// Calibrates s_post on a one-row strip FEM (`strip_rows` = 1) of a slider body of thickness
/// `slider_thickness_m` (m).
pub fn calibrate_near_field(
    strip: &StripModel,
    slider_thickness_m: f64,
) -> Result<NearFieldCalibration> {
    let spec = row_spec(strip, slider_thickness_m)?;
    let kernel = LatticeKernel::new(&spec)?;
    let cfg = &strip.config;
    let johnson = contact_springs::k_pn(&cfg.slider_material, cfg.post_radius_m)
        .map_err(|e| invalid("post_diameter_m", 2.0 * cfg.post_radius_m, e.to_string()))?;
    Ok(calibrate(
        strip,
        &spec,
        &strip.slider.compliance_m_per_n,
        |dx, dy| {
            if dx.hypot(dy) < 0.5 * cfg.post_radius_m {
                kernel.parts().layer_at_zero_m_per_n
            } else {
                kernel.body_mutual(dx.hypot(dy))
            }
        },
        1.0 / johnson,
    ))
}

/// Calibrates the tangential s_t,post on a one-row strip FEM (module doc): one set of partial
/// forward solves on the strip's slider factor (the tangential columns), then as
/// [`calibrate_near_field`]. `johnson_m_per_n` of the result is 1/k_pt.
pub fn calibrate_tangential_near_field(
    strip: &StripModel,
    slider_thickness_m: f64,
) -> Result<NearFieldCalibration> {
    let spec = row_spec(strip, slider_thickness_m)?;
    let kernel = crate::tangential::TangentialKernel::new(
        &spec,
        NearField::Value {
            slider_self_compliance_m_per_n: 0.0,
        },
    )?;
    let fem = strip.slider.tangential_compliance()?.tangential_m_per_n;
    let cfg = &strip.config;
    let johnson = contact_springs::k_pt(&cfg.slider_material, cfg.post_radius_m)
        .map_err(|e| invalid("post_diameter_m", 2.0 * cfg.post_radius_m, e.to_string()))?;
    Ok(calibrate(
        strip,
        &spec,
        &fem,
        |dx, dy| {
            if dx.hypot(dy) < 0.5 * cfg.post_radius_m {
                kernel.body_layer(0.0, 0.0)
            } else {
                kernel.body_mutual(dx, dy)
            }
        },
        1.0 / johnson,
    ))
}

/// The lattice spec of the strip's row with enough image rows for the body's far field.
fn row_spec(strip: &StripModel, slider_thickness_m: f64) -> Result<OperatorSpec> {
    if strip.strip_rows != 1 {
        return Err(invalid(
            "strip_rows",
            strip.strip_rows as f64,
            "the near-field calibration needs a one-row strip",
        ));
    }
    let cfg = &strip.config;
    let p = cfg.pitch_m;
    let rows = image_rows(p, slider_thickness_m);
    let x_span = strip.posts.last().map_or(0.0, |q| q.x_m) - strip.posts[0].x_m;
    let posts_x = ((x_span / p).round() as usize + 1).max(1);
    Ok(OperatorSpec {
        geometry: LatticeGeometry {
            posts_x,
            posts_y: 2 * rows as usize + 1,
            pitch_m: p,
            post_radius_m: cfg.post_radius_m,
            slider_length_m: posts_x as f64 * p,
            slider_width_m: (2 * rows + 1) as f64 * p,
        },
        slider_material: cfg.slider_material.clone(),
        stator_material: cfg.stator_material.clone(),
        slider_thickness_m,
        near_field: NearField::Value {
            slider_self_compliance_m_per_n: 0.0,
        },
    })
}

/// Image rows on each side of the strip's row: the bonded body's far field has decayed there.
fn image_rows(pitch_m: f64, slider_thickness_m: f64) -> i64 {
    (TABLE_MIN_RANGE_OVER_T * slider_thickness_m / pitch_m).ceil() as i64
}

/// s_post from the FEM matrix `fem` (m/N) and the body kernel `body(dx, dy)` (its r → 0 value
/// the layer correction at the origin), with the differential checks.
fn calibrate(
    strip: &StripModel,
    spec: &OperatorSpec,
    fem: &nalgebra::DMatrix<f64>,
    body: impl Fn(f64, f64) -> f64,
    johnson_m_per_n: f64,
) -> NearFieldCalibration {
    let n = strip.post_count();
    let p = strip.config.pitch_m;
    let rows = image_rows(p, spec.slider_thickness_m);
    let lattice = |i: usize, j: usize| -> f64 {
        let dx = strip.posts[i].x_m - strip.posts[j].x_m;
        (-rows..=rows).map(|m| body(dx, m as f64 * p)).sum()
    };
    let count = ((CENTRAL_FRACTION * n as f64).round() as usize).max(1);
    let first = (n - count) / 2;
    let posts: Vec<usize> = (first..first + count).collect();
    let s_post = posts
        .iter()
        .map(|&i| fem[(i, i)] - lattice(i, i))
        .sum::<f64>()
        / count as f64;
    let differential = posts
        .iter()
        .flat_map(|&i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
        .map(|(i, j)| DifferentialCheck {
            post: i,
            other: j,
            fem_m_per_n: fem[(i, i)] - fem[(i, j)],
            lattice_m_per_n: s_post + lattice(i, i) - lattice(i, j),
        })
        .collect();
    NearFieldCalibration {
        slider_self_compliance_m_per_n: s_post,
        johnson_m_per_n,
        posts,
        differential,
    }
}
