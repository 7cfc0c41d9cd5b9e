//! PNG plots with plotters and a bundled font (DejaVu Sans through the `dejavu` crate and
//! plotters' `ab_glyph` backend), so they render on a machine with no system fonts. Draws what it
//! is given; computes nothing. Shared by every study's figures.

mod contour;
mod file;
mod lines;
mod map;
mod space_time;
mod style;

pub use contour::{CentroidGrid, GridCell, Segment};
pub use file::figure;
pub use lines::{LineChart, LogAxes, Shading, draw, line_chart, line_chart_shaded};
pub use map::{ContourSet, Map, diverging, map_with_contours};
pub use space_time::{Field, space_time};
pub use style::{Curve, Dash, Labels, Mark, PALETTE, Scale};
