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
    /// Johnson's 1/k_pn for comparison (m/N).
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
    if strip.strip_rows != 1 {
        return Err(invalid(
            "strip_rows",
            strip.strip_rows as f64,
            "the near-field calibration needs a one-row strip",
        ));
    }
    let cfg = &strip.config;
    let n = strip.post_count();
    let p = cfg.pitch_m;
    let rows = (TABLE_MIN_RANGE_OVER_T * slider_thickness_m / p).ceil() as i64;
    let x_span = strip.posts.last().map_or(0.0, |q| q.x_m) - strip.posts[0].x_m;
    let posts_x = ((x_span / p).round() as usize + 1).max(1);
    let kernel = LatticeKernel::new(&OperatorSpec {
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
    })?;
    let lattice = |i: usize, j: usize| -> f64 {
        let dx = strip.posts[i].x_m - strip.posts[j].x_m;
        (-rows..=rows)
            .map(|m| {
                let r = dx.hypot(m as f64 * p);
                if r < 0.5 * cfg.post_radius_m {
                    kernel.parts().layer_at_zero_m_per_n
                } else {
                    kernel.body_mutual(r)
                }
            })
            .sum()
    };
    let fem = &strip.slider.compliance_m_per_n;
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
    let johnson = contact_springs::k_pn(&cfg.slider_material, cfg.post_radius_m)
        .map_err(|e| invalid("post_diameter_m", 2.0 * cfg.post_radius_m, e.to_string()))?;
    Ok(NearFieldCalibration {
        slider_self_compliance_m_per_n: s_post,
        johnson_m_per_n: 1.0 / johnson,
        posts,
        differential,
    })
}
