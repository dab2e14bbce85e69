#![doc = include_str!("../README.md")]

mod axes;
mod draw;
mod error;
mod model;
mod output;

pub use error::ChartError;
pub use model::{CategoryMap, Chart, Scale, Series, Style};
pub use output::{write_category_map, write_chart, write_stacked};
