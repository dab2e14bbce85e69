//! Charts (SVG and PNG through the workspace `charts` crate): the speed–thrust curve and the
//! paper's Fig. 6-style time history of one post (normal and tangential force, stick shaded).

use std::path::{Path, PathBuf};

use charts::{Chart, Series, Style, write_chart, write_stacked};

use crate::error::{Result, StickSlipError};
use crate::history::{PostHistory, SliderHistory};
use crate::result::DynamicResult;

/// Seconds → nanoseconds for time axes.
const NS_PER_S: f64 = 1e9;

fn chart_error(stem: &Path) -> impl FnOnce(charts::ChartError) -> StickSlipError + '_ {
    move |source| StickSlipError::Chart {
        path: stem.to_path_buf(),
        source,
    }
}

/// The speed–thrust chart of several labelled results (one series each), with the friction
/// limit μP of the first as a dashed reference at zero speed.
pub fn speed_thrust_chart(title: &str, results: &[(&str, &DynamicResult)]) -> Chart {
    let mut chart = Chart::new(title, "speed (m/s)", "thrust (N)");
    for (label, result) in results {
        let points = result
            .curve
            .iter()
            .map(|p| (p.speed_m_per_s, p.thrust_n))
            .collect();
        chart
            .series
            .push(Series::new(*label, points, Style::LineMarkers));
    }
    if let Some((_, first)) = results.first() {
        let crest = first.crest_speed_m_per_s;
        chart.series.push(Series::new(
            format!(
                "μP = {:.3} N, A_t ω = {:.3} m/s",
                first.friction_limit_n, crest
            ),
            vec![(0.0, first.friction_limit_n), (crest, 0.0)],
            Style::Dashed,
        ));
    }
    chart
}

/// Write the speed–thrust curve of one result to `stem.svg` / `stem.png`.
pub fn write_speed_thrust_chart(result: &DynamicResult, stem: &Path) -> Result<Vec<PathBuf>> {
    let title = format!(
        "speed–thrust ({}, {})",
        model_name(result),
        result.integrator
    );
    write_chart(&speed_thrust_chart(&title, &[("curve", result)]), stem).map_err(chart_error(stem))
}

/// Write several labelled speed–thrust curves on one chart.
pub fn write_speed_thrust_comparison(
    title: &str,
    results: &[(&str, &DynamicResult)],
    stem: &Path,
) -> Result<Vec<PathBuf>> {
    write_chart(&speed_thrust_chart(title, results), stem).map_err(chart_error(stem))
}

fn model_name(result: &DynamicResult) -> &'static str {
    match result.model {
        crate::scene::ModelKind::PeriodicAverage => "period average",
        crate::scene::ModelKind::Transient => "transient",
    }
}

/// The two panels of a Fig. 6-style history: normal force (top) and tangential force with
/// the friction bounds ±μ_k N (bottom), time in ns, stick intervals shaded in both.
pub fn post_history_charts(title: &str, history: &PostHistory) -> [Chart; 2] {
    let time: Vec<f64> = history.time_s.iter().map(|t| t * NS_PER_S).collect();
    let shaded: Vec<(f64, f64)> = history
        .stick_intervals_s
        .iter()
        .map(|&(a, b)| (a * NS_PER_S, b * NS_PER_S))
        .collect();
    let zip = |values: &[f64]| {
        time.iter()
            .copied()
            .zip(values.iter().copied())
            .collect::<Vec<_>>()
    };
    let mut normal = Chart::new(
        format!(
            "{title}: one post at {:.3} m/s (stick shaded)",
            history.speed_m_per_s
        ),
        "time (ns)",
        "normal force (N)",
    );
    normal
        .series
        .push(Series::new("N", zip(&history.normal_force_n), Style::Line));
    normal.shaded_x = shaded.clone();
    let mut tangential = Chart::new("", "time (ns)", "tangential force (N)");
    tangential.series.push(Series::new(
        "F (drive direction)",
        zip(&history.tangential_force_n),
        Style::Line,
    ));
    let lower: Vec<f64> = history.friction_bound_n.iter().map(|b| -b).collect();
    tangential.series.push(Series::new(
        "+μ_k N",
        zip(&history.friction_bound_n),
        Style::Dashed,
    ));
    tangential
        .series
        .push(Series::new("−μ_k N", zip(&lower), Style::Dashed));
    tangential.shaded_x = shaded;
    [normal, tangential]
}

/// Write a Fig. 6-style history of one post to `stem.svg` / `stem.png` (two stacked panels).
pub fn write_post_history_chart(
    title: &str,
    history: &PostHistory,
    stem: &Path,
) -> Result<Vec<PathBuf>> {
    write_stacked(&post_history_charts(title, history), stem).map_err(chart_error(stem))
}

/// Write a slider history (speed and total thrust over time, µs) as two stacked panels.
pub fn write_slider_history_chart(
    title: &str,
    history: &SliderHistory,
    stem: &Path,
) -> Result<Vec<PathBuf>> {
    let time: Vec<f64> = history.time_s.iter().map(|t| t * 1e6).collect();
    let zip = |values: &[f64]| {
        time.iter()
            .copied()
            .zip(values.iter().copied())
            .collect::<Vec<_>>()
    };
    let mut speed = Chart::new(title, "time (µs)", "slider speed (m/s)");
    speed.series.push(Series::new(
        "speed (drive direction)",
        zip(&history.speed_m_per_s),
        Style::Line,
    ));
    let mut thrust = Chart::new("", "time (µs)", "contact thrust (N)");
    thrust.series.push(Series::new(
        "ΣF (drive direction)",
        zip(&history.thrust_n),
        Style::Line,
    ));
    let mut height = Chart::new("", "time (µs)", "tip height z_s (nm)");
    height.series.push(Series::new(
        "z_s",
        zip(&history
            .tip_height_m
            .iter()
            .map(|z| z * 1e9)
            .collect::<Vec<_>>()),
        Style::Line,
    ));
    write_stacked(&[speed, thrust, height], stem).map_err(chart_error(stem))
}
