//! Drawing a [`Chart`] or [`CategoryMap`] onto any plotters drawing area.

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::axes::{label, padded_range, to_axis};
use crate::{CategoryMap, Chart, Style};

/// Series colours, cycled (colour-blind friendly Okabe–Ito palette).
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(240, 228, 66),
];
/// Category colours for maps (stable, oscillating, diverged, …).
const CATEGORY_PALETTE: [RGBColor; 6] = [
    RGBColor(0, 158, 115),
    RGBColor(230, 159, 0),
    RGBColor(213, 94, 0),
    RGBColor(86, 180, 233),
    RGBColor(120, 120, 120),
    RGBColor(204, 121, 167),
];
/// Colour of shaded x-intervals.
const SHADE: RGBColor = RGBColor(190, 210, 235);
/// Font family for all text.
const FONT: &str = "sans-serif";

type DrawResult = Result<(), String>;

fn err(e: impl std::fmt::Display) -> String {
    e.to_string()
}

/// Points of a chart in axis space, per series.
pub(crate) fn axis_points(chart: &Chart) -> Vec<Vec<(f64, f64)>> {
    chart
        .series
        .iter()
        .map(|s| {
            s.points
                .iter()
                .filter_map(|&(x, y)| {
                    Some((to_axis(chart.x_scale, x)?, to_axis(chart.y_scale, y)?))
                })
                .collect()
        })
        .collect()
}

/// Draw an x–y chart into `area`. `x_range` overrides the x-range (shared x of stacked panels).
pub(crate) fn draw_chart<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &Chart,
    x_range: Option<(f64, f64)>,
) -> DrawResult {
    let points = axis_points(chart);
    let x_range = x_range
        .or_else(|| padded_range(points.iter().flatten().map(|p| p.0)))
        .ok_or("no finite x values")?;
    let y_range = padded_range(points.iter().flatten().map(|p| p.1)).ok_or("no finite y values")?;
    let (x_scale, y_scale) = (chart.x_scale, chart.y_scale);

    let mut ctx = ChartBuilder::on(area)
        .caption(&chart.title, (FONT, 20))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(75)
        .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)
        .map_err(err)?;
    ctx.configure_mesh()
        .x_desc(chart.x_label.as_str())
        .y_desc(chart.y_label.as_str())
        .x_label_formatter(&|v| label(x_scale, *v))
        .y_label_formatter(&|v| label(y_scale, *v))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(err)?;

    let shades = chart.shaded_x.iter().filter_map(|&(a, b)| {
        let (a, b) = (to_axis(x_scale, a)?, to_axis(x_scale, b)?);
        Some(Rectangle::new(
            [(a, y_range.0), (b, y_range.1)],
            SHADE.mix(0.6).filled(),
        ))
    });
    ctx.draw_series(shades).map_err(err)?;

    for (index, (series, pts)) in chart.series.iter().zip(&points).enumerate() {
        let color = PALETTE[index % PALETTE.len()];
        let stroke = color.stroke_width(2);
        let legend = move |(x, y): (i32, i32)| PathElement::new(vec![(x, y), (x + 20, y)], stroke);
        match series.style {
            Style::Line | Style::LineMarkers => {
                ctx.draw_series(LineSeries::new(pts.iter().copied(), stroke))
                    .map_err(err)?
                    .label(series.name.as_str())
                    .legend(legend);
            }
            Style::Dashed => {
                ctx.draw_series(DashedLineSeries::new(pts.iter().copied(), 8, 5, stroke))
                    .map_err(err)?
                    .label(series.name.as_str())
                    .legend(legend);
            }
            Style::Markers => {}
        }
        if matches!(series.style, Style::Markers | Style::LineMarkers) {
            let markers = ctx
                .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                .map_err(err)?;
            if series.style == Style::Markers {
                markers
                    .label(series.name.as_str())
                    .legend(move |(x, y)| Circle::new((x + 10, y), 3, color.filled()));
            }
        }
    }
    if chart.series.iter().any(|s| !s.name.is_empty()) {
        ctx.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FONT, 13))
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

/// Cell edges in axis space: midpoints between centres, extrapolated at both ends.
fn cell_edges(centres: &[f64]) -> Vec<f64> {
    let n = centres.len();
    if n == 1 {
        return vec![centres[0] - 0.5, centres[0] + 0.5];
    }
    let mut edges = Vec::with_capacity(n + 1);
    edges.push(centres[0] - 0.5 * (centres[1] - centres[0]));
    edges.extend(centres.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    edges.push(centres[n - 1] + 0.5 * (centres[n - 1] - centres[n - 2]));
    edges
}

/// Draw a category map into `area`. Axis values must already be validated.
pub(crate) fn draw_category_map<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    map: &CategoryMap,
    xs: &[f64],
    ys: &[f64],
) -> DrawResult {
    let (x_edges, y_edges) = (cell_edges(xs), cell_edges(ys));
    let (x_scale, y_scale) = (map.x_scale, map.y_scale);
    let mut ctx = ChartBuilder::on(area)
        .caption(&map.title, (FONT, 20))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(75)
        .build_cartesian_2d(x_edges[0]..x_edges[xs.len()], y_edges[0]..y_edges[ys.len()])
        .map_err(err)?;
    ctx.configure_mesh()
        .disable_mesh()
        .x_desc(map.x_label.as_str())
        .y_desc(map.y_label.as_str())
        .x_label_formatter(&|v| label(x_scale, *v))
        .y_label_formatter(&|v| label(y_scale, *v))
        .draw()
        .map_err(err)?;
    for (category, name) in map.categories.iter().enumerate() {
        let color = CATEGORY_PALETTE[category % CATEGORY_PALETTE.len()];
        let cells = map.cells.iter().enumerate().flat_map(|(iy, row)| {
            row.iter()
                .enumerate()
                .filter(move |(_, c)| **c == category)
                .map(move |(ix, _)| (ix, iy))
        });
        let rects = cells.map(|(ix, iy)| {
            Rectangle::new(
                [
                    (x_edges[ix], y_edges[iy]),
                    (x_edges[ix + 1], y_edges[iy + 1]),
                ],
                color.filled(),
            )
        });
        ctx.draw_series(rects)
            .map_err(err)?
            .label(name.as_str())
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], color.filled()));
    }
    ctx.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 13))
        .draw()
        .map_err(err)?;
    Ok(())
}
