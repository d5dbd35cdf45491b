//! Publication-quality line plots of simulation output, written as SVG or PNG.
//!
//! [`draw`] renders a [`Figure`] (title, axis labels, linear or logarithmic
//! axes, one or more [`Series`]) to a file whose extension picks the format.
//! Everything is pure Rust: SVG text is laid out by the viewer, and PNG text
//! is rasterised with the Noto Sans Regular font (Apache License 2.0) that is
//! compiled into the binary, so no system font or image library is needed.
//!
//! How data becomes a picture:
//!
//! - Points whose coordinates cannot be shown are skipped: NaN and ±∞ on
//!   every axis, and also zero and negative values on a logarithmic axis. The
//!   line of a series bridges the points it skips. If nothing is left to show,
//!   the axes are still drawn, with a note in the middle of the frame.
//! - Axis ranges span the data with a 5 % margin on each side. A constant
//!   series gets a range of ±10 % around its value (±1 around zero, half a
//!   decade on a log axis) instead of a degenerate one.
//! - Logarithmic axes are drawn by plotting `log₁₀` of the data on linear
//!   axes, with tick labels in scientific notation such as `1e-12`.
//! - A series with more than [`MAX_POINTS`] points is decimated: its points
//!   are split into consecutive buckets and each bucket keeps the points with
//!   the smallest and largest `x` and `y`, so spikes and the envelope of the
//!   curve survive while files stay small.
//! - With `equal_aspect`, one unit of `x` and one unit of `y` take the same
//!   number of pixels; the shorter range is padded around its centre.
//!
//! `draw.rs` writes the file, `render.rs` lays out and draws the figure,
//! `data.rs` turns data into points and axis ranges and `ticks.rs` places and
//! labels the ticks; this file holds the figure description and the error type.

mod data;
mod draw;
mod render;
mod ticks;

pub use draw::draw;
pub(crate) use draw::register_font;
pub(crate) use render::Axis;
pub(crate) use ticks::{Ticks, linear_axis_ticks};

use std::path::{Path, PathBuf};

/// Points kept per series after decimation.
pub const MAX_POINTS: usize = 4000;

/// Width of a figure in pixels.
pub const WIDTH: u32 = 800;

/// Height of a figure in pixels.
pub const HEIGHT: u32 = 600;

/// Font family name under which the embedded font is registered.
pub(crate) const FONT: &str = "sans-serif";

/// Output format, chosen by the file extension: `.svg` or `.png`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotFormat {
    /// Scalable vector graphics (`.svg`).
    Svg,
    /// Portable network graphics (`.png`), [`WIDTH`] × [`HEIGHT`] pixels.
    Png,
}

impl PlotFormat {
    /// The format named by the extension of `path` (ignoring case), if any.
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?;
        if ext.eq_ignore_ascii_case("svg") {
            Some(Self::Svg)
        } else if ext.eq_ignore_ascii_case("png") {
            Some(Self::Png)
        } else {
            None
        }
    }

    /// The file extension of the format, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Svg => "svg",
            Self::Png => "png",
        }
    }
}

/// A figure that could not be drawn.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlotError {
    /// The file that was to be written.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

impl std::fmt::Display for PlotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "cannot draw {}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for PlotError {}

/// One curve: points `(x[i], y[i])` joined by a line in the order given.
///
/// If `x` and `y` differ in length, the extra values of the longer are ignored.
#[derive(Debug, Clone, Copy)]
pub struct Series<'a> {
    /// Name in the legend (drawn when a figure has more than one series).
    pub label: &'a str,
    /// Abscissae.
    pub x: &'a [f64],
    /// Ordinates.
    pub y: &'a [f64],
}

/// Scale of an axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    /// Linear.
    Linear,
    /// Base-10 logarithmic; values that are not positive and finite are skipped.
    Log,
}

/// A figure: title, axes and curves.
#[derive(Debug, Clone)]
pub struct Figure<'a> {
    /// Title above the plot (none if empty).
    pub title: &'a str,
    /// Label of the horizontal axis.
    pub x_label: &'a str,
    /// Label of the vertical axis.
    pub y_label: &'a str,
    /// Scale of the horizontal axis.
    pub x_scale: Scale,
    /// Scale of the vertical axis.
    pub y_scale: Scale,
    /// Curves, each in its own colour.
    pub series: Vec<Series<'a>>,
    /// Draw a marker at each data point as well as the line. A series that
    /// had to be decimated is drawn as a line only, since markers on
    /// thousands of points would merge into a band.
    pub markers: bool,
    /// Give one unit of `x` and of `y` the same length on the page (for
    /// orbits in the plane); on a log axis the unit is a decade.
    pub equal_aspect: bool,
}
