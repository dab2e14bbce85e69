//! Charts for sawdrive: one small vocabulary (series, axes, shaded intervals, category maps)
//! drawn by `plotters` into an SVG and, where fonts allow, a PNG next to it.
//!
//! Every writer takes a path *stem* (`out/curve` → `out/curve.svg`, `out/curve.png`) and writes
//! atomically (temporary file, then rename), so an interrupted run never leaves half a chart over
//! a good one.
//!
//! ```no_run
//! use charts::{Chart, Series, Style, write_chart};
//! let mut chart = Chart::new("speed–thrust", "speed (m/s)", "thrust (N)");
//! chart.series.push(Series::new("10000 posts", vec![(0.0, 3.0), (1.0, 0.0)], Style::LineMarkers));
//! let files = write_chart(&chart, std::path::Path::new("out/curve")).unwrap();
//! ```

mod axes;
mod draw;
mod error;
mod model;
mod output;

pub use error::ChartError;
pub use model::{CategoryMap, Chart, Scale, Series, Style};
pub use output::{write_category_map, write_chart, write_stacked};
