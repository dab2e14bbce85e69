//! Writing charts to `stem.svg` and `stem.png`, atomically.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::axes::{padded_range, to_axis};
use crate::draw::{axis_points, draw_category_map, draw_chart};
use crate::{CategoryMap, Chart, ChartError};

/// Pixel size of one chart panel.
const PANEL_SIZE: (u32, u32) = (900, 560);
/// Pixel height of one panel in a vertical stack.
const STACKED_PANEL_HEIGHT: u32 = 380;

/// Write `chart` to `stem.svg` and `stem.png`; returns the files written. The PNG is skipped
/// (only the SVG returned) where no font can be loaded to render its text.
pub fn write_chart(chart: &Chart, stem: &Path) -> Result<Vec<PathBuf>, ChartError> {
    check_has_data(chart)?;
    write_both(stem, &chart.title, PANEL_SIZE, &Figure::Single(chart))
}

/// Write panels stacked vertically with a shared x-range (e.g. normal and tangential force of
/// one post over time).
pub fn write_stacked(charts: &[Chart], stem: &Path) -> Result<Vec<PathBuf>, ChartError> {
    let title = charts.first().map(|c| c.title.clone()).unwrap_or_default();
    if charts.is_empty() {
        return Err(ChartError::NoData { title });
    }
    for chart in charts {
        check_has_data(chart)?;
    }
    let shared_x = padded_range(charts.iter().flat_map(axis_points).flatten().map(|p| p.0));
    let height = STACKED_PANEL_HEIGHT * charts.len() as u32;
    write_both(
        stem,
        &title,
        (PANEL_SIZE.0, height),
        &Figure::Stacked(charts, shared_x),
    )
}

/// Write a category map (e.g. a stability map) to `stem.svg` and `stem.png`.
pub fn write_category_map(map: &CategoryMap, stem: &Path) -> Result<Vec<PathBuf>, ChartError> {
    let bad = |what: String| ChartError::BadGrid {
        title: map.title.clone(),
        what,
    };
    let to_axes = |values: &[f64], scale, name: &str| -> Result<Vec<f64>, ChartError> {
        let mapped: Option<Vec<f64>> = values.iter().map(|&v| to_axis(scale, v)).collect();
        let mapped =
            mapped.ok_or_else(|| bad(format!("{name} holds a value its scale cannot show")))?;
        if mapped.is_empty() || mapped.windows(2).any(|w| w[1] <= w[0]) {
            return Err(bad(format!(
                "{name} must be non-empty and strictly increasing"
            )));
        }
        Ok(mapped)
    };
    let xs = to_axes(&map.xs, map.x_scale, "xs")?;
    let ys = to_axes(&map.ys, map.y_scale, "ys")?;
    if map.cells.len() != ys.len() || map.cells.iter().any(|row| row.len() != xs.len()) {
        return Err(bad(format!(
            "cells must be {} rows of {} entries",
            ys.len(),
            xs.len()
        )));
    }
    if let Some(c) = map
        .cells
        .iter()
        .flatten()
        .find(|c| **c >= map.categories.len())
    {
        return Err(bad(format!(
            "cell category {c} has no name ({} categories)",
            map.categories.len()
        )));
    }
    write_both(stem, &map.title, PANEL_SIZE, &Figure::Map(map, &xs, &ys))
}

fn check_has_data(chart: &Chart) -> Result<(), ChartError> {
    if axis_points(chart).iter().all(Vec::is_empty) {
        return Err(ChartError::NoData {
            title: chart.title.clone(),
        });
    }
    Ok(())
}

/// What one output file shows, drawable on any backend.
enum Figure<'a> {
    Single(&'a Chart),
    /// Panels and their shared x-range in axis space.
    Stacked(&'a [Chart], Option<(f64, f64)>),
    /// A map with its cell centres in axis space.
    Map(&'a CategoryMap, &'a [f64], &'a [f64]),
}

impl Figure<'_> {
    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<(), String> {
        match *self {
            Figure::Single(chart) => draw_chart(area, chart, None),
            Figure::Stacked(charts, shared_x) => {
                let panels = area.split_evenly((charts.len(), 1));
                charts
                    .iter()
                    .zip(&panels)
                    .try_for_each(|(chart, panel)| draw_chart(panel, chart, shared_x))
            }
            Figure::Map(map, xs, ys) => draw_category_map(area, map, xs, ys),
        }
    }
}

/// Render `figure` into an SVG and a PNG next to each other.
fn write_both(
    stem: &Path,
    title: &str,
    size: (u32, u32),
    figure: &Figure<'_>,
) -> Result<Vec<PathBuf>, ChartError> {
    if let Some(dir) = stem.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| ChartError::Io {
            path: dir.to_owned(),
            source,
        })?;
    }
    let draw_error = |message: String| ChartError::Draw {
        title: title.to_owned(),
        message,
    };

    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        area.fill(&WHITE).map_err(|e| draw_error(e.to_string()))?;
        figure.draw(&area).map_err(draw_error)?;
        area.present().map_err(|e| draw_error(e.to_string()))?;
    }
    let svg_path = stem.with_extension("svg");
    atomic_files::write_atomically(&svg_path, svg.as_bytes())?;
    let mut written = vec![svg_path];

    let png_path = stem.with_extension("png");
    let png = atomic_files::write_atomically_via(&png_path, |tmp| {
        let area = BitMapBackend::new(tmp, size).into_drawing_area();
        area.fill(&WHITE).map_err(|e| draw_error(e.to_string()))?;
        figure.draw(&area).map_err(draw_error)?;
        area.present().map_err(|e| draw_error(e.to_string()))
    });
    match png {
        Ok(()) => written.push(png_path),
        // Text rendering needs a system font; without one, the SVG alone is the chart.
        Err(ChartError::Draw { .. }) => {}
        Err(other) => return Err(other),
    }
    Ok(written)
}
