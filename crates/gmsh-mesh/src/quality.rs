//! Element quality: radius ratio, inverted and degenerate tetrahedra, reported by element tag.
//!
//! Builds on [`crate::mesh`] (it reads a [`TetMesh`]), and holds the mesh's quality methods
//! ([`TetMesh::quality`] and the bad-element check) so that the mesh module does not depend
//! on it.

use serde::Serialize;

use crate::error::{MeshError, Result};
use crate::geometry::{self, Point};
use crate::mesh::{TetMesh, Tets};

/// Radius ratio ρ = 3 r_in / R_circ below which a tet counts as poor (stiffness conditioning and
/// stress accuracy suffer). Dimensionless, regular tet = 1. Default 0.1.
pub const POOR_RADIUS_RATIO: f64 = 0.1;

/// Normalised volume |V| / l_rms³ below which a tet is degenerate (l_rms the RMS edge length;
/// the regular tet has 1/(6√2) ≈ 0.118). Such a tet makes the stiffness matrix singular in
/// floating point. Dimensionless. Default 1e-8.
pub const DEGENERATE_NORMALIZED_VOLUME: f64 = 1e-8;

/// How many element tags a report lists per kind of defect. Default 20.
pub const MAX_LISTED_TAGS: usize = 20;

/// Quality figures of a mesh. Radius ratios use the straight (corner) tets; for Tet10 the
/// Jacobian of the curved map is sampled at corners, edge midpoints and quadrature points.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QualityReport {
    /// Number of tets assessed.
    pub tet_count: usize,
    /// Smallest radius ratio (0 degenerate … 1 regular).
    pub radius_ratio_min: f64,
    /// Largest radius ratio.
    pub radius_ratio_max: f64,
    /// Mean radius ratio.
    pub radius_ratio_mean: f64,
    /// Tag of the tet with the smallest radius ratio.
    pub worst_tet_tag: Option<u64>,
    /// Threshold below which a tet is counted as poor ([`POOR_RADIUS_RATIO`]).
    pub poor_threshold: f64,
    /// Number of tets with radius ratio below `poor_threshold`.
    pub poor_count: usize,
    /// Number of tets with a negative Jacobian (inverted).
    pub inverted_count: usize,
    /// Tags of the first [`MAX_LISTED_TAGS`] inverted tets.
    pub inverted_tags: Vec<u64>,
    /// Number of tets with a vanishing volume ([`DEGENERATE_NORMALIZED_VOLUME`]).
    pub degenerate_count: usize,
    /// Tags of the first [`MAX_LISTED_TAGS`] degenerate tets.
    pub degenerate_tags: Vec<u64>,
    /// Tet10 only: smallest ratio min det J / max det J within one tet (1 for straight tets;
    /// ≤ 0 means inverted somewhere inside).
    pub jacobian_ratio_min: Option<f64>,
}

impl QualityReport {
    /// Whether any tet is inverted or degenerate.
    pub fn has_bad_elements(&self) -> bool {
        self.inverted_count > 0 || self.degenerate_count > 0
    }
}

impl std::fmt::Display for QualityReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "radius ratio min {:.4} (tet {}), mean {:.4}, max {:.4}; {} of {} tets below {}",
            self.radius_ratio_min,
            self.worst_tet_tag
                .map_or("-".to_string(), |t| t.to_string()),
            self.radius_ratio_mean,
            self.radius_ratio_max,
            self.poor_count,
            self.tet_count,
            self.poor_threshold
        )?;
        if let Some(ratio) = self.jacobian_ratio_min {
            write!(f, "; Tet10 min det J / max det J {ratio:.4}")?;
        }
        write!(f, "; inverted {}", self.inverted_count)?;
        if !self.inverted_tags.is_empty() {
            write!(f, " (tags {:?})", self.inverted_tags)?;
        }
        write!(f, ", degenerate {}", self.degenerate_count)?;
        if !self.degenerate_tags.is_empty() {
            write!(f, " (tags {:?})", self.degenerate_tags)?;
        }
        Ok(())
    }
}

impl TetMesh {
    /// Element quality: radius ratio statistics, poor, inverted and degenerate tets.
    pub fn quality(&self) -> QualityReport {
        assess(self)
    }

    /// [`MeshError::BadElements`] if a tet is inverted or degenerate (a mesh made from another,
    /// e.g. by [`crate::elevate`] or [`crate::mirror`], is checked as a file is on reading).
    pub(crate) fn check_elements(&self) -> Result<()> {
        let quality = self.quality();
        if quality.has_bad_elements() {
            return Err(MeshError::BadElements {
                file: self.source.clone(),
                inverted_count: quality.inverted_count,
                degenerate_count: quality.degenerate_count,
                shown: MAX_LISTED_TAGS,
                inverted_tags: quality.inverted_tags,
                degenerate_tags: quality.degenerate_tags,
            });
        }
        Ok(())
    }
}

/// Assess every tet of `mesh`.
pub(crate) fn assess(mesh: &TetMesh) -> QualityReport {
    let count = mesh.tets.len();
    let mut report = QualityReport {
        tet_count: count,
        radius_ratio_min: if count == 0 { 0.0 } else { f64::INFINITY },
        radius_ratio_max: 0.0,
        radius_ratio_mean: 0.0,
        worst_tet_tag: None,
        poor_threshold: POOR_RADIUS_RATIO,
        poor_count: 0,
        inverted_count: 0,
        inverted_tags: Vec::new(),
        degenerate_count: 0,
        degenerate_tags: Vec::new(),
        jacobian_ratio_min: None,
    };
    let mut sum = 0.0;
    for i in 0..count {
        let corners = mesh.tets.corners(i).map(|n| mesh.nodes[n]);
        let tag = mesh.tet_tags[i];
        let rho = geometry::radius_ratio(corners);
        sum += rho;
        if rho < report.radius_ratio_min {
            report.radius_ratio_min = rho;
            report.worst_tet_tag = Some(tag);
        }
        report.radius_ratio_max = report.radius_ratio_max.max(rho);
        if rho < POOR_RADIUS_RATIO {
            report.poor_count += 1;
        }
        let inverted = match &mesh.tets {
            Tets::Linear(_) => geometry::tet4_signed_volume(corners) < 0.0,
            Tets::Quadratic(tets) => {
                let p: [Point; 10] = tets[i].map(|n| mesh.nodes[n]);
                let (lo, hi) = geometry::tet10_jacobian_range(&p);
                let ratio = if hi > 0.0 { lo / hi } else { lo.signum() };
                report.jacobian_ratio_min =
                    Some(report.jacobian_ratio_min.map_or(ratio, |r| r.min(ratio)));
                lo < 0.0
            }
        };
        let scale = geometry::rms_edge_length(corners);
        let normalized_volume =
            geometry::tet4_signed_volume(corners).abs() / (scale * scale * scale);
        // NaN (a zero-length tet) counts as degenerate.
        let degenerate =
            normalized_volume.is_nan() || normalized_volume < DEGENERATE_NORMALIZED_VOLUME;
        if inverted {
            report.inverted_count += 1;
            if report.inverted_tags.len() < MAX_LISTED_TAGS {
                report.inverted_tags.push(tag);
            }
        } else if degenerate {
            report.degenerate_count += 1;
            if report.degenerate_tags.len() < MAX_LISTED_TAGS {
                report.degenerate_tags.push(tag);
            }
        }
    }
    if count > 0 {
        report.radius_ratio_mean = sum / count as f64;
    }
    report
}
