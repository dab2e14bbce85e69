//! Output of the springs validation: the text table ([`std::fmt::Display`]), the charts and the
//! JSON files.

use std::fmt;
use std::path::{Path, PathBuf};

use charts::{Chart, Scale, Series, Style, write_chart};

use crate::error::ValidationError;
use crate::spring::Spring;
use crate::study::SpringsValidation;

pub use crate::serde_nan::{f64_or_nan, pair_or_nan};

/// Reads a `results.json` written by [`write_json`] (e.g. to redraw the charts).
pub fn read_results(path: &Path) -> Result<SpringsValidation, ValidationError> {
    let text = std::fs::read_to_string(path).map_err(|source| ValidationError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|source| ValidationError::Json {
        what: "springs validation results",
        source,
    })
}

fn percent(x: f64) -> String {
    if x.is_finite() {
        format!("{:+.3} %", 100.0 * x)
    } else {
        "n/a".into()
    }
}

impl fmt::Display for SpringsValidation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.fmt_cases(f)?;
        self.fmt_partners(f)?;
        self.fmt_truncation(f)?;
        self.fmt_work_precision(f)?;
        if let Some(st) = &self.stability {
            fmt_stability(st, f)?;
        }
        writeln!(f)?;
        write!(
            f,
            "study wall time {:.0} s on {} logical CPUs (load average {:.1} at start, {:.1} at end)",
            self.wall_s, self.cpus, self.load_average[0], self.load_average[1]
        )
    }
}

impl SpringsValidation {
    /// The title, one row per case and the acceptance line.
    fn fmt_cases(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "Rigid punch on a half-space: FEM (Tet{}, {} levels, R = {} a, point-force far field) vs Johnson springs",
            if self.family.order == 2 { 10 } else { 4 },
            self.levels
                .iter()
                .map(|l| l.level)
                .max()
                .map_or(0, |m| m + 1),
            self.family.truncation_ratio
        )?;
        writeln!(
            f,
            "{:<5} {:<7} {:>6} {:>14} {:>9} {:>14} {:>10} {:>6} {:>9}  status",
            "", "", "a", "FEM", "est. err", "formula", "FEM/form.", "order", "unknowns"
        )?;
        writeln!(
            f,
            "{:<5} {:<7} {:>6} {:>14} {:>9} {:>14} {:>10} {:>6} {:>9}",
            "", "", "(um)", "(N/m)", "", "(N/m)", "-1", "", "(finest)"
        )?;
        for c in &self.cases {
            let status = match (c.converged, c.agrees) {
                (true, true) => "ok".to_string(),
                (false, true) => "NOT CONVERGED".to_string(),
                (true, false) => "DISAGREES".to_string(),
                (false, false) => "NOT CONVERGED, DISAGREES".to_string(),
            };
            writeln!(
                f,
                "{:<5} {:<7} {:>6.1} {:>14.6e} {:>8.3}% {:>14.6e} {:>10} {:>6.2} {:>9}  {}",
                c.spring.label(),
                c.material,
                c.radius_m * 1e6,
                c.fem_n_per_m,
                100.0 * c.fem_error_estimate,
                c.analytic_n_per_m,
                percent(c.relative_difference),
                c.observed_order,
                c.finest_level_unknowns,
                status
            )?;
        }
        writeln!(
            f,
            "acceptance: estimated error <= {:.1} %, |FEM/formula - 1| <= {:.1} %: {}",
            100.0 * self.error_tolerance,
            100.0 * self.agreement_tolerance,
            if self.all_pass() {
                "all pass"
            } else {
                "NOT all pass (see validation/springs/README.md)"
            }
        )?;
        Ok(())
    }

    /// Each case's FEM value against the partner formula (the wrong boundary condition).
    fn fmt_partners(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f)?;
        writeln!(
            f,
            "Wrong boundary condition: FEM value against the partner formula (bonded <-> frictional)"
        )?;
        for c in &self.cases {
            writeln!(
                f,
                "  {} {:<7} a = {:>4.1} um: FEM vs {} formula {:>9} -> {}",
                c.spring,
                c.material,
                c.radius_m * 1e6,
                c.partner_spring,
                percent(c.partner_relative_difference),
                if c.tells_partner_apart {
                    "told apart"
                } else {
                    "NOT told apart"
                }
            )?;
        }
        Ok(())
    }

    /// FEM/formula − 1 against the truncation radius, clamped and with the far field.
    fn fmt_truncation(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.truncation.is_empty() {
            writeln!(f)?;
            writeln!(
                f,
                "Truncation (level 0): FEM/formula - 1 for R/a, clamped | point-force far field"
            )?;
            let mut keys: Vec<(Spring, String)> = self
                .truncation
                .iter()
                .map(|t| (t.spring, t.material.clone()))
                .collect();
            keys.dedup();
            keys.sort();
            keys.dedup();
            for (spring, material) in keys {
                write!(f, "  {spring} {material:<7}")?;
                for t in self
                    .truncation
                    .iter()
                    .filter(|t| t.spring == spring && t.material == material)
                {
                    write!(
                        f,
                        "  R/a {:>4}: {} | {}",
                        t.truncation_ratio,
                        percent(t.clamped_over_analytic - 1.0),
                        percent(t.point_force_over_analytic - 1.0)
                    )?;
                }
                writeln!(f)?;
            }
        }
        Ok(())
    }

    /// Error against cost of the work-precision case.
    fn fmt_work_precision(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.work_precision.is_empty() {
            writeln!(f)?;
            writeln!(
                f,
                "Work-precision ({}):",
                self.work_precision_case
                    .as_ref()
                    .map_or(String::new(), |w| format!(
                        "{} {} a = {} um",
                        w.spring,
                        w.material,
                        w.radius_m * 1e6
                    ))
            )?;
            for p in &self.work_precision {
                writeln!(
                    f,
                    "  Tet{:<2} level {} h_e/a {:<7} {:>8} unknowns {:>8.2} s  |error| {:.4} %",
                    if p.order == 2 { 10 } else { 4 },
                    p.level,
                    p.h_edge_over_a,
                    p.unknowns,
                    p.wall_s,
                    100.0 * p.relative_error
                )?;
            }
        }
        Ok(())
    }
}

/// Near-incompressibility, the floating punch and distorted meshes.
fn fmt_stability(st: &crate::study::StabilityResults, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    writeln!(f)?;
    writeln!(
        f,
        "Near-incompressible (k_sn / formula; Tet4 {} vs Tet10 {} unknowns):",
        st.locking_unknowns[0], st.locking_unknowns[1]
    )?;
    for p in &st.locking {
        writeln!(
            f,
            "  nu = {:<6} Tet4 {:.4}  Tet10 {:.4}",
            p.poisson_ratio, p.tet4_over_analytic, p.tet10_over_analytic
        )?;
    }
    writeln!(f, "Floating punch (no far field, only u_z on the punch):")?;
    writeln!(
        f,
        "  with rigid-mode check:    {}",
        st.singular_system.with_rigid_mode_check
    )?;
    writeln!(
        f,
        "  without rigid-mode check: {}",
        st.singular_system.without_rigid_mode_check
    )?;
    writeln!(
        f,
        "    direct path:            {}",
        st.singular_system.direct_without_check
    )?;
    writeln!(
        f,
        "    iterative path:         {}",
        st.singular_system.iterative_without_check
    )?;
    writeln!(
        f,
        "Distorted interior nodes ({}), k_sn / formula:",
        st.distortion_mesh
    )?;
    for p in &st.distortion {
        if p.refusal.is_empty() {
            writeln!(
                f,
                "  amplitude {:<5} min quality {:.3}, {} poor elements: {:.4}",
                p.amplitude, p.min_quality, p.poor_elements, p.stiffness_over_analytic
            )?;
        } else {
            writeln!(f, "  amplitude {:<5} refused: {}", p.amplitude, p.refusal)?;
        }
    }
    Ok(())
}

/// Reference slope line through (x0, y0) with y ∝ x^slope over [x0, x1].
fn slope_line(name: &str, x0: f64, x1: f64, y0: f64, slope: f64) -> Series {
    let points = (0..=8)
        .map(|i| x0 * (x1 / x0).powf(i as f64 / 8.0))
        .map(|x| (x, y0 * (x / x0).powf(slope)))
        .collect();
    Series::new(name, points, Style::Dashed)
}

fn chart_err(path: &Path) -> impl Fn(charts::ChartError) -> ValidationError + '_ {
    move |source| ValidationError::Chart {
        path: path.to_path_buf(),
        source,
    }
}

/// Writes the charts into `dir` and returns the files written (SVG, and PNG where fonts allow).
pub fn write_charts(
    validation: &SpringsValidation,
    dir: &Path,
) -> Result<Vec<PathBuf>, ValidationError> {
    std::fs::create_dir_all(dir).map_err(|source| ValidationError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut files = Vec::new();

    files.extend(work_precision_charts(validation, dir)?);
    files.extend(convergence_chart(validation, dir)?);
    files.extend(truncation_chart(validation, dir)?);
    Ok(files)
}

/// Work-precision: error against unknowns and against wall time, with the theory slopes.
fn work_precision_charts(
    validation: &SpringsValidation,
    dir: &Path,
) -> Result<Vec<PathBuf>, ValidationError> {
    let mut files = Vec::new();
    if !validation.work_precision.is_empty() {
        for (stem, x_label, x_of) in [
            (
                "work_precision_unknowns",
                "unknowns",
                (|p: &crate::study::WorkPrecisionPoint| p.unknowns as f64) as fn(&_) -> f64,
            ),
            (
                "work_precision_time",
                "wall time of one solve (s)",
                |p: &crate::study::WorkPrecisionPoint| p.wall_s,
            ),
        ] {
            let case = validation
                .work_precision_case
                .as_ref()
                .map_or(String::new(), |w| {
                    format!("{} {} a = {} um", w.spring, w.material, w.radius_m * 1e6)
                });
            let mut chart = Chart::new(
                format!("work-precision, {case}"),
                x_label,
                "|FEM/exact - 1|",
            )
            .log_log();
            for order in [1u8, 2] {
                let pts: Vec<(f64, f64)> = validation
                    .work_precision
                    .iter()
                    .filter(|p| p.order == order)
                    .map(|p| (x_of(p), p.relative_error))
                    .collect();
                if pts.is_empty() {
                    continue;
                }
                let name = if order == 2 { "Tet10" } else { "Tet4" };
                let (first, last) = (pts[0], pts[pts.len() - 1]);
                chart
                    .series
                    .push(Series::new(name, pts.clone(), Style::LineMarkers));
                // Theory: error ∝ h_e; unknowns ∝ h_e^-(1 + 1/p) → error ∝ N^(-p/(p+1)); sparse
                // Cholesky of a 3D mesh (nested dissection) costs ∝ N² → error ∝ t^(-p/(2(p+1))).
                let p = f64::from(order);
                let (slope, label) = if stem == "work_precision_unknowns" {
                    (
                        -p / (p + 1.0),
                        format!("{name} theory: N^{:.2}", -p / (p + 1.0)),
                    )
                } else {
                    let slope = -p / (2.0 * (p + 1.0));
                    (slope, format!("{name}, if cost ∝ N²: t^{slope:.2}"))
                };
                chart
                    .series
                    .push(slope_line(&label, first.0, last.0, first.1 * 1.3, slope));
            }
            if stem == "work_precision_unknowns" {
                chart
                    .series
                    .push(accuracy_target(&validation.work_precision));
            }
            let path = dir.join(stem);
            files.extend(write_chart(&chart, &path).map_err(chart_err(&path))?);
        }
    }
    Ok(files)
}

/// The 0.3 % accuracy target across the work-precision points' range of unknowns.
fn accuracy_target(points: &[crate::study::WorkPrecisionPoint]) -> Series {
    let unknowns = points.iter().map(|p| p.unknowns as f64);
    let low = unknowns.clone().fold(f64::INFINITY, f64::min);
    let high = unknowns.fold(0.0, f64::max);
    Series::new(
        "0.3 % target",
        vec![(low, 0.003), (high, 0.003)],
        Style::Dashed,
    )
}

/// Convergence of each spring (first radius, each material): FEM/formula − 1 against h_e/a,
/// with the extrapolated value at h_e = 0.
fn convergence_chart(
    validation: &SpringsValidation,
    dir: &Path,
) -> Result<Vec<PathBuf>, ValidationError> {
    let mut files = Vec::new();
    if let Some(radius) = validation.cases.first().map(|c| c.radius_m) {
        let mut chart = Chart::new(
            format!("convergence, a = {} um (Tet10)", radius * 1e6),
            "h_edge / a",
            "FEM / formula - 1 (%)",
        );
        chart.x_scale = Scale::Linear;
        for c in validation
            .cases
            .iter()
            .filter(|c| (c.radius_m / radius - 1.0).abs() < 1e-9)
        {
            let mut pts: Vec<(f64, f64)> = validation
                .levels
                .iter()
                .filter(|l| {
                    l.result.spring == c.spring
                        && l.result.material == c.material
                        && (l.result.radius_m / radius - 1.0).abs() < 1e-6
                })
                .map(|l| {
                    (
                        l.h_edge_over_a,
                        100.0 * (l.result.stiffness_n_per_m / c.analytic_n_per_m - 1.0),
                    )
                })
                .collect();
            pts.push((0.0, 100.0 * c.relative_difference));
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart.series.push(Series::new(
                format!("{} {}", c.spring, c.material),
                pts,
                Style::LineMarkers,
            ));
        }
        let path = dir.join("convergence");
        files.extend(write_chart(&chart, &path).map_err(chart_err(&path))?);
    }
    Ok(files)
}

/// Truncation: FEM/formula − 1 against a/R, clamped and with the point-force far field.
fn truncation_chart(
    validation: &SpringsValidation,
    dir: &Path,
) -> Result<Vec<PathBuf>, ValidationError> {
    let mut files = Vec::new();
    if !validation.truncation.is_empty() {
        let mut chart = Chart::new("truncation at level 0", "a / R", "FEM / formula - 1 (%)");
        let mut keys: Vec<(Spring, String)> = validation
            .truncation
            .iter()
            .map(|t| (t.spring, t.material.clone()))
            .collect();
        keys.sort();
        keys.dedup();
        for (spring, material) in keys
            .into_iter()
            .filter(|(_, m)| Some(m) == validation.cases.first().map(|c| &c.material))
        {
            for (label, style, clamped) in [
                ("clamped", Style::Dashed, true),
                ("point force", Style::LineMarkers, false),
            ] {
                let pts: Vec<(f64, f64)> = validation
                    .truncation
                    .iter()
                    .filter(|t| t.spring == spring && t.material == material)
                    .map(|t| {
                        (
                            1.0 / t.truncation_ratio,
                            100.0
                                * (if clamped {
                                    t.clamped_over_analytic
                                } else {
                                    t.point_force_over_analytic
                                } - 1.0),
                        )
                    })
                    .collect();
                chart.series.push(Series::new(
                    format!("{spring} {material} {label}"),
                    pts,
                    style,
                ));
            }
        }
        let path = dir.join("truncation");
        files.extend(write_chart(&chart, &path).map_err(chart_err(&path))?);
    }
    Ok(files)
}

/// Writes `results.json` (everything) and `cases.json` (the `--json` array) into `dir`.
pub fn write_json(
    validation: &SpringsValidation,
    dir: &Path,
) -> Result<Vec<PathBuf>, ValidationError> {
    std::fs::create_dir_all(dir).map_err(|source| ValidationError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let full =
        serde_json::to_string_pretty(validation).map_err(|source| ValidationError::Json {
            what: "springs validation",
            source,
        })?;
    let mut written = Vec::new();
    for (name, text) in [
        ("results.json", full),
        ("cases.json", validation.cases_json()?),
    ] {
        let path = dir.join(name);
        atomic_files::write_atomically(&path, text + "\n").map_err(|error| {
            let (path, source) = error.into_parts();
            ValidationError::Io { path, source }
        })?;
        written.push(path);
    }
    Ok(written)
}
