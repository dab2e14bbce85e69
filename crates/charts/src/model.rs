//! What a chart shows, independent of how it is drawn.

/// Axis scale.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// Linear axis.
    #[default]
    Linear,
    /// Base-10 logarithmic axis; values ≤ 0 are dropped.
    Log,
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Style {
    /// Solid line through the points.
    #[default]
    Line,
    /// Dashed line (reference slopes, analytic curves).
    Dashed,
    /// Markers only.
    Markers,
    /// Solid line with markers.
    LineMarkers,
}

/// One named set of (x, y) points.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// Legend entry.
    pub name: String,
    /// Points in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Line or marker style.
    pub style: Style,
}

impl Series {
    /// A series from its name, points and style.
    pub fn new(name: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Self {
            name: name.into(),
            points,
            style,
        }
    }
}

/// An x–y chart with any number of series and shaded x-intervals.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Chart {
    /// Title above the plot.
    pub title: String,
    /// x-axis label, with its unit.
    pub x_label: String,
    /// y-axis label, with its unit.
    pub y_label: String,
    /// x-axis scale.
    pub x_scale: Scale,
    /// y-axis scale.
    pub y_scale: Scale,
    /// The data.
    pub series: Vec<Series>,
    /// x-intervals shaded in the background (e.g. stick phases).
    pub shaded_x: Vec<(f64, f64)>,
}

impl Chart {
    /// An empty linear chart with a title and axis labels.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Self::default()
        }
    }

    /// The same chart with log–log axes.
    pub fn log_log(mut self) -> Self {
        self.x_scale = Scale::Log;
        self.y_scale = Scale::Log;
        self
    }
}

/// A map of categories over a 2-D parameter grid (e.g. stable / oscillating / diverged over
/// step size × regularisation).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CategoryMap {
    /// Title above the map.
    pub title: String,
    /// x-axis label, with its unit.
    pub x_label: String,
    /// y-axis label, with its unit.
    pub y_label: String,
    /// x-axis scale.
    pub x_scale: Scale,
    /// y-axis scale.
    pub y_scale: Scale,
    /// Grid values along x (cell centres), increasing.
    pub xs: Vec<f64>,
    /// Grid values along y (cell centres), increasing.
    pub ys: Vec<f64>,
    /// `cells[iy][ix]`: index into `categories`.
    pub cells: Vec<Vec<usize>>,
    /// Category names, shown in the legend.
    pub categories: Vec<String>,
}
