//! Files for people: a ParaView VTU of one snapshot (displacement, stress, contact pressure) and
//! a chart of post force against x with the frozen wave beneath it (the chart only with the
//! cargo feature `charts`, on by default; without it the crate builds without plotters and font
//! libraries).

use std::path::Path;
#[cfg(feature = "charts")]
use std::path::PathBuf;

#[cfg(feature = "charts")]
use charts::{Chart, Series, Style, write_stacked};
use gmsh_mesh::{Field, FieldValues, write_vtu};

use crate::BodyCompliance;
#[cfg(feature = "charts")]
use crate::analysis::PreloadResult;
use crate::analysis::{SnapshotResult, StaticAnalysis};
use crate::error::{ContactError, Result};
#[cfg(feature = "charts")]
use crate::lumped::independent_posts;
#[cfg(feature = "charts")]
use crate::params::StaticParams;
use crate::scene::StatorCompliance;

/// Points per wavelength of the drawn wave. Default 48.
#[cfg(feature = "charts")]
pub const WAVE_CHART_POINTS_PER_WAVELENGTH: usize = 48;

fn scatter_body(body: &BodyCompliance, u_body: &[f64], offset_z_m: f64, u: &mut [[f64; 3]]) {
    for (local, &node) in body.mesh_nodes().iter().enumerate() {
        u[node] = [
            u_body[3 * local],
            u_body[3 * local + 1],
            u_body[3 * local + 2] + offset_z_m,
        ];
    }
}

/// Writes `snapshot` (of `analysis`) as a VTU with point fields `displacement_m` (slider:
/// relative to the undeformed strip whose tips start at z = 0, i.e. including the rigid approach
/// z_s; stator block: relative to its clamped bottom; nodes of an unmeshed half-space stator: 0),
/// `stress_zz_pa`, `von_mises_pa` and `contact_pressure_pa` (−σ_zz on the tip nodes of posts in
/// contact, nodal-averaged).
pub fn write_snapshot_vtu(
    analysis: &StaticAnalysis,
    snapshot: &SnapshotResult,
    path: &Path,
) -> Result<()> {
    let model = &analysis.model;
    let mesh = &model.mesh;
    let forces: Vec<f64> = snapshot.posts.iter().map(|p| p.force_n).collect();
    let n = mesh.nodes.len();
    let mut u = vec![[0.0; 3]; n];
    let mut szz = vec![0.0; n];
    let mut vm = vec![0.0; n];
    let mut pressure = vec![0.0; n];
    let mut add_body = |body: &BodyCompliance, offset: f64, contact: bool| -> Result<()> {
        let ub = body.displacement(&forces)?;
        scatter_body(body, &ub, offset, &mut u);
        let stress = body.nodal_stress(&ub)?;
        for (local, &node) in body.mesh_nodes().iter().enumerate() {
            szz[node] = stress[local][2];
            vm[node] = elastic_fem::post::von_mises(&stress[local]);
        }
        if contact {
            for (post, nodes) in body.disk_nodes().iter().enumerate() {
                if snapshot.posts[post].in_contact {
                    for &l in nodes {
                        pressure[body.mesh_nodes()[l]] = (-stress[l][2]).max(0.0);
                    }
                }
            }
        }
        Ok(())
    };
    add_body(&model.slider, snapshot.reference_height_m, true)?;
    if let StatorCompliance::Meshed(stator) = &model.stator {
        add_body(stator, 0.0, false)?;
    }
    write_vtu(
        path,
        mesh,
        &[
            Field {
                name: "displacement_m",
                values: FieldValues::Vector(&u),
            },
            Field {
                name: "stress_zz_pa",
                values: FieldValues::Scalar(&szz),
            },
            Field {
                name: "von_mises_pa",
                values: FieldValues::Scalar(&vm),
            },
            Field {
                name: "contact_pressure_pa",
                values: FieldValues::Scalar(&pressure),
            },
        ],
        &[],
    )
    .map_err(|e| ContactError::Output {
        path: path.to_path_buf(),
        detail: e.to_string(),
    })
}

/// Writes `stem.svg` (and `.png`): post forces against x (FEM, and the lumped model with the
/// fitted η) above the frozen wave w(x) and the posts' positions. Returns the files written.
#[cfg(feature = "charts")]
pub fn write_force_chart(
    analysis: &StaticAnalysis,
    preload_index: usize,
    snapshot_index: usize,
    stem: &Path,
) -> Result<Vec<PathBuf>> {
    let report = &analysis.report;
    let preload = report
        .preloads
        .get(preload_index)
        .ok_or_else(|| ContactError::Output {
            path: stem.to_path_buf(),
            detail: format!(
                "no preload #{preload_index} (the report has {})",
                report.preloads.len()
            ),
        })?;
    let snapshot = preload
        .snapshots
        .get(snapshot_index)
        .unwrap_or(&preload.flat_stator);
    let force_chart = force_chart(analysis, preload, snapshot);
    let wave_chart = wave_chart(&analysis.params, snapshot);
    write_stacked(&[force_chart, wave_chart], stem).map_err(|e| ContactError::Output {
        path: stem.to_path_buf(),
        detail: e.to_string(),
    })
}

/// The post forces of `snapshot` against x: the FEM's, and the lumped model's with the fitted η.
#[cfg(feature = "charts")]
fn force_chart(
    analysis: &StaticAnalysis,
    preload: &PreloadResult,
    snapshot: &SnapshotResult,
) -> Chart {
    let (params, report) = (&analysis.params, &analysis.report);
    let mm = 1e3;
    let fem: Vec<(f64, f64)> = snapshot
        .posts
        .iter()
        .map(|p| (p.x_m * mm, p.force_n * 1e3))
        .collect();
    let mut force_chart = Chart::new(
        format!(
            "Post forces, P = {} N ({} posts of {:.0} µm){}",
            preload.preload_n,
            report.posts_total,
            params.post_diameter_m * 1e6,
            snapshot
                .phase_rad
                .map_or(" — flat stator".to_string(), |p| format!(
                    ", θ₀ = {p:.2} rad"
                ))
        ),
        "x (mm)",
        "post force (mN)",
    );
    force_chart
        .series
        .push(Series::new("FEM strip", fem, Style::Markers));
    if let Some(eta) = preload.effective_contact_ratio {
        let heights: Vec<f64> = snapshot.posts.iter().map(|p| p.surface_height_m).collect();
        let (lumped, _) =
            independent_posts(&heights, eta * report.k_n_n_per_m, preload.preload_strip_n);
        let points = snapshot
            .posts
            .iter()
            .zip(&lumped)
            .map(|(p, f)| (p.x_m * mm, f * 1e3))
            .collect();
        force_chart.series.push(Series::new(
            format!("lumped, η = {eta:.3}"),
            points,
            Style::Line,
        ));
    }
    force_chart
}

/// The frozen wave w(x) of `snapshot` and each post's tip height w + gap (m shown in nm).
#[cfg(feature = "charts")]
fn wave_chart(params: &StaticParams, snapshot: &SnapshotResult) -> Chart {
    let mm = 1e3;
    let x0 = snapshot.posts.first().map_or(0.0, |p| p.x_m);
    let x1 = snapshot.posts.last().map_or(0.0, |p| p.x_m);
    let samples = ((x1 - x0) / params.wavelength_m * WAVE_CHART_POINTS_PER_WAVELENGTH as f64)
        .ceil()
        .max(2.0) as usize;
    let k = 2.0 * std::f64::consts::PI / params.wavelength_m;
    let phase = snapshot.phase_rad.unwrap_or(0.0);
    let amplitude = if snapshot.phase_rad.is_some() {
        params.wave_amplitude_m
    } else {
        0.0
    };
    let wave: Vec<(f64, f64)> = (0..=samples)
        .map(|i| {
            let x = x0 + (x1 - x0) * i as f64 / samples as f64;
            (x * mm, amplitude * (phase - k * x).sin() * 1e9)
        })
        .collect();
    // Height w_i + g_i: on the undeformed wave where a post is in contact, above it by its gap.
    let tips: Vec<(f64, f64)> = snapshot
        .posts
        .iter()
        .map(|p| (p.x_m * mm, (p.surface_height_m + p.gap_m) * 1e9))
        .collect();
    let mut wave_chart = Chart::new(
        "Frozen wave and the gaps under the posts",
        "x (mm)",
        "height (nm)",
    );
    wave_chart
        .series
        .push(Series::new("stator surface w(x)", wave, Style::Line));
    wave_chart.series.push(Series::new(
        "w + gap at each post (on w where in contact)",
        tips,
        Style::Markers,
    ));
    wave_chart
}
