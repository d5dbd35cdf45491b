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

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Points kept per series after decimation.
pub const MAX_POINTS: usize = 4000;

/// Width of a figure in pixels.
pub const WIDTH: u32 = 800;

/// Height of a figure in pixels.
pub const HEIGHT: u32 = 600;

/// Font family name under which the embedded font is registered.
pub(crate) const FONT: &str = "sans-serif";
const TITLE_SIZE: u32 = 24;
const AXIS_LABEL_SIZE: u32 = 18;
const TICK_LABEL_SIZE: u32 = 15;
const LEGEND_SIZE: u32 = 15;
const MARGIN: u32 = 20;
const X_LABEL_AREA: u32 = 60;
/// The y-label area grows with the widest tick label, from this minimum.
const MIN_Y_LABEL_AREA: u32 = 70;
/// Fraction of the data span added on each side of an axis range.
const PAD: f64 = 0.05;
/// Radius of the data-point markers in pixels.
const MARKER_RADIUS: i32 = 4;

/// Line colours (the Tableau 10 palette), cycled through by series index.
const COLOURS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];
const MAJOR_GRID: RGBColor = RGBColor(215, 215, 215);
const MINOR_GRID: RGBColor = RGBColor(240, 240, 240);

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

/// Draw `figure` to `path`, in the format named by its extension (`.svg` or
/// `.png`); any other extension is an error that names it.
///
/// A file that could not be completed is removed.
pub fn draw(path: &Path, figure: &Figure) -> Result<(), PlotError> {
    let fail = |message: String| PlotError {
        path: path.to_path_buf(),
        message,
    };
    let format = PlotFormat::from_path(path).ok_or_else(|| {
        fail(match path.extension() {
            Some(ext) => format!(
                "unknown plot format `.{}`, expected .svg or .png",
                ext.to_string_lossy()
            ),
            None => "the file name has no extension, expected .svg or .png".to_string(),
        })
    })?;
    register_font().map_err(fail)?;
    // Rendering goes through a third-party library: should it panic on some
    // input, report that as an error rather than abort the caller.
    let rendered = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match format {
        PlotFormat::Svg => render(
            SVGBackend::new(path, (WIDTH, HEIGHT)).into_drawing_area(),
            figure,
            false,
        ),
        PlotFormat::Png => render(
            BitMapBackend::new(path, (WIDTH, HEIGHT)).into_drawing_area(),
            figure,
            true,
        ),
    }));
    let result = match rendered {
        Ok(result) => result,
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown cause".to_string());
            Err(format!("the plotting library failed: {what}"))
        }
    };
    result.map_err(|message| {
        // The backend writes what it has when it is dropped; do not leave a
        // half-drawn file behind.
        let _ = std::fs::remove_file(path);
        fail(message)
    })
}

/// Register the embedded font with `plotters`, once per process. Both
/// backends need it: text extents for the layout come from its metrics.
pub(crate) fn register_font() -> Result<(), String> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| plotters::style::register_font(FONT, FontStyle::Normal, ttf_noto_sans::REGULAR).is_ok());
    if ok {
        Ok(())
    } else {
        Err("the embedded font could not be loaded".to_string())
    }
}

/// `v` in display coordinates (`log₁₀ v` on a log axis), if it can be shown.
fn to_axis(v: f64, scale: Scale) -> Option<f64> {
    match scale {
        Scale::Linear => v.is_finite().then_some(v),
        Scale::Log => (v.is_finite() && v > 0.0).then(|| v.log10()),
    }
}

/// The displayable points of a series in display coordinates, decimated to
/// at most [`MAX_POINTS`]; `true` if decimation dropped points.
fn prepare(series: &Series, xs: Scale, ys: Scale) -> (Vec<(f64, f64)>, bool) {
    let points: Vec<(f64, f64)> = series
        .x
        .iter()
        .zip(series.y)
        .filter_map(|(&x, &y)| Some((to_axis(x, xs)?, to_axis(y, ys)?)))
        .collect();
    if points.len() <= MAX_POINTS {
        (points, false)
    } else {
        (decimate(&points, MAX_POINTS), true)
    }
}

/// At most `max_points` of `points`, in their original order: consecutive
/// buckets each keep their points of smallest and largest `x` and `y`. For a
/// time series (monotone `x`) these are the bucket's first and last points
/// and its extremes, so the drawn envelope, spikes included, is unchanged.
fn decimate(points: &[(f64, f64)], max_points: usize) -> Vec<(f64, f64)> {
    if points.len() <= max_points {
        return points.to_vec();
    }
    let buckets = (max_points / 4).max(1);
    let size = points.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(max_points);
    for chunk in points.chunks(size) {
        // Indices of the smallest x, largest x, smallest y, largest y.
        let mut idx = [0usize; 4];
        for (i, p) in chunk.iter().enumerate() {
            if p.0 < chunk[idx[0]].0 {
                idx[0] = i;
            }
            if p.0 > chunk[idx[1]].0 {
                idx[1] = i;
            }
            if p.1 < chunk[idx[2]].1 {
                idx[2] = i;
            }
            if p.1 > chunk[idx[3]].1 {
                idx[3] = i;
            }
        }
        idx.sort_unstable();
        for (j, &i) in idx.iter().enumerate() {
            if j == 0 || i != idx[j - 1] {
                out.push(chunk[i]);
            }
        }
    }
    out
}

/// Smallest and largest of `values`, or `None` if there are none.
fn extent(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// The axis range for data spanning `[lo, hi]` (display coordinates), with
/// a margin, never degenerate and always finite.
fn axis_range(data: Option<(f64, f64)>, scale: Scale) -> (f64, f64) {
    let Some((lo, hi)) = data else {
        // Nothing to show: a unit frame (1 to 10 on a log axis).
        return (0.0, 1.0);
    };
    // Halves first, so that extreme values cannot overflow.
    let mid = 0.5 * lo + 0.5 * hi;
    let half = 0.5 * hi - 0.5 * lo;
    let constant = match scale {
        Scale::Linear => half <= 1e-12 * lo.abs().max(hi.abs()),
        Scale::Log => half <= 1e-12,
    };
    let half = if !constant {
        half * (1.0 + 2.0 * PAD)
    } else {
        match scale {
            Scale::Linear if mid == 0.0 => 1.0,
            Scale::Linear => 0.1 * mid.abs(),
            Scale::Log => 0.5,
        }
    };
    (
        (mid - half).clamp(-f64::MAX, f64::MAX),
        (mid + half).clamp(-f64::MAX, f64::MAX),
    )
}

/// Widen the shorter of two ranges so that both have the same number of
/// units per pixel on a plotting area of `pixels` (width, height).
fn equalise(x: (f64, f64), y: (f64, f64), pixels: (u32, u32)) -> ((f64, f64), (f64, f64)) {
    let (w, h) = (f64::from(pixels.0.max(1)), f64::from(pixels.1.max(1)));
    let per_pixel = ((x.1 - x.0) / w).max((y.1 - y.0) / h);
    if !per_pixel.is_finite() || per_pixel <= 0.0 {
        return (x, y);
    }
    let widen = |(lo, hi): (f64, f64), len: f64| {
        if (hi - lo) / len >= per_pixel {
            return (lo, hi);
        }
        let mid = 0.5 * lo + 0.5 * hi;
        let half = 0.5 * per_pixel * len;
        (mid - half, mid + half)
    };
    (widen(x, w), widen(y, h))
}

/// Tick marks of one axis: labelled major ticks (with grid lines) and
/// unlabelled minor grid lines, at display coordinates.
#[derive(Debug, Default)]
struct Ticks {
    major: Vec<(f64, String)>,
    minor: Vec<f64>,
}

impl Ticks {
    /// The label of the major tick at `v`.
    fn label(&self, v: f64) -> String {
        self.major
            .iter()
            .min_by(|a, b| (a.0 - v).abs().total_cmp(&(b.0 - v).abs()))
            .map(|t| t.1.clone())
            .unwrap_or_default()
    }

    /// Estimated width in pixels of the widest label.
    fn label_width(&self) -> u32 {
        let chars = self.major.iter().map(|t| t.1.chars().count()).max();
        // Noto Sans digits are 0.57 em wide.
        (0.6 * f64::from(TICK_LABEL_SIZE) * chars.unwrap_or(0) as f64).ceil() as u32
    }
}

/// A "nice" step (1, 2 or 5 times a power of ten) splitting `span` into
/// about `target` intervals, with the number of minor intervals per step.
fn nice_step(span: f64, target: usize) -> Option<(f64, usize)> {
    let raw = span / target.max(1) as f64;
    if !(raw.is_finite() && raw > 0.0) {
        return None;
    }
    let magnitude = 10f64.powf(raw.log10().floor());
    let m = raw / magnitude;
    let (nice, minor) = if m < 1.5 {
        (1.0, 5)
    } else if m < 3.5 {
        (2.0, 4)
    } else if m < 7.5 {
        (5.0, 5)
    } else {
        (10.0, 5)
    };
    let step = nice * magnitude;
    (step.is_finite() && step > 0.0).then_some((step, minor))
}

/// Multiples of `step` within `[lo, hi]` (none if there would be hundreds).
fn multiples(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    // The tolerance keeps a multiple that falls on an end despite rounding.
    let (first, last) = ((lo / step - 1e-9).ceil(), (hi / step + 1e-9).floor());
    if !(first.is_finite() && last.is_finite()) || last - first > 500.0 {
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut k = first;
    while k <= last {
        let v = k * step;
        // Avoid labels such as "-0" or "1e-17" for zero.
        out.push(if v.abs() < 1e-9 * step { 0.0 } else { v });
        k += 1.0;
    }
    out
}

/// `v` in scientific notation with `digits` digits after the point, trailing
/// zeros dropped: `1e-12`, `2.5e3`.
fn scientific(v: f64, digits: usize) -> String {
    let s = format!("{:.*e}", digits.min(15), v);
    match s.split_once('e') {
        Some((mantissa, exp)) if mantissa.contains('.') => {
            let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
            format!("{mantissa}e{exp}")
        }
        _ => s,
    }
}

/// Digits after the point needed to tell multiples of `step` apart at `v`.
fn digits_for(v: f64, step: f64) -> usize {
    let e = v.abs().log10().floor();
    let step_e = step.log10().floor();
    (e - step_e).clamp(0.0, 15.0) as usize
}

/// Ticks of a linear axis over `[lo, hi]`.
fn linear_ticks(lo: f64, hi: f64, target: usize) -> Ticks {
    let Some((step, minor_per_step)) = nice_step(hi - lo, target) else {
        return Ticks::default();
    };
    let big = lo.abs().max(hi.abs());
    let scientific_labels = !(1e-3..1e5).contains(&big);
    let decimals = (-step.log10().floor()).clamp(0.0, 15.0) as usize;
    let major = multiples(lo, hi, step)
        .into_iter()
        .map(|v| {
            let label = if !scientific_labels {
                format!("{v:.decimals$}")
            } else if v == 0.0 {
                "0".to_string()
            } else {
                scientific(v, digits_for(v, step))
            };
            (v, label)
        })
        .collect();
    let minor_step = step / minor_per_step as f64;
    let minor = multiples(lo, hi, minor_step)
        .into_iter()
        .filter(|v| ((v / step).round() * step - v).abs() > 1e-6 * step)
        .collect();
    Ticks { major, minor }
}

/// Ticks of a logarithmic axis over `[lo, hi]`, given in decades
/// (`log₁₀` of the data); labels in scientific notation.
fn log_ticks(lo: f64, hi: f64, target: usize) -> Ticks {
    if !(lo.is_finite() && hi.is_finite() && hi > lo) {
        return Ticks::default();
    }
    let (first, last) = (lo.ceil() as i64, hi.floor() as i64);
    let decades = last - first + 1;
    if decades >= 3 {
        // Label every k-th decade, k = 1, 2, 5, 10, 20, 50, ...
        let mut k = 1i64;
        let mut scale = 1i64;
        let mut mantissas = [2, 5, 10].into_iter().cycle();
        while decades > k * (target.max(1) as i64 + 1) {
            match mantissas.next() {
                Some(10) | None => {
                    scale *= 10;
                    k = scale;
                }
                Some(m) => k = m * scale,
            }
        }
        let major: Vec<(f64, String)> = (first..=last)
            .filter(|e| e.rem_euclid(k) == 0)
            .map(|e| (e as f64, format!("1e{e}")))
            .collect();
        let minor = if k == 1 && decades <= 16 {
            // 2, 3, ..., 9 times each power of ten.
            (first - 1..=last)
                .flat_map(|e| (2..10).map(move |m| e as f64 + f64::from(m).log10()))
                .filter(|v| (lo..=hi).contains(v))
                .collect()
        } else if decades <= 60 {
            (first..=last)
                .filter(|e| e.rem_euclid(k) != 0)
                .map(|e| e as f64)
                .collect()
        } else {
            Vec::new()
        };
        return Ticks { major, minor };
    }
    // Up to two decades: 1, 2 and 5 times powers of ten.
    let candidates = |ms: &'static [u32]| {
        (lo.floor() as i64 - 1..=hi.ceil() as i64).flat_map(move |e| {
            ms.iter()
                .map(move |&m| (e as f64 + f64::from(m).log10(), format!("{m}e{e}")))
        })
    };
    let major: Vec<(f64, String)> = candidates(&[1, 2, 5]).filter(|t| (lo..=hi).contains(&t.0)).collect();
    if major.len() >= 2 {
        let minor = candidates(&[1, 2, 3, 4, 5, 6, 7, 8, 9])
            .filter(|t| !major.iter().any(|m| m.1 == t.1))
            .map(|t| t.0)
            .filter(|v| (lo..=hi).contains(v))
            .collect();
        return Ticks { major, minor };
    }
    // Narrower still: evenly spaced values, placed on the log axis.
    let (a, b) = (10f64.powf(lo), 10f64.powf(hi));
    let Some((step, _)) = nice_step(b - a, target.min(5)) else {
        return Ticks::default();
    };
    let major = multiples(a, b, step)
        .into_iter()
        .filter(|&v| v > 0.0)
        .map(|v| (v.log10(), scientific(v, digits_for(v, step))))
        .collect();
    Ticks {
        major,
        minor: Vec::new(),
    }
}

/// Ticks for an axis of `scale` over `range`, about one per `spacing` pixels
/// of its `length`.
fn ticks(range: (f64, f64), scale: Scale, length: u32, spacing: u32) -> Ticks {
    let target = (length / spacing).clamp(3, 10) as usize;
    match scale {
        Scale::Linear => linear_ticks(range.0, range.1, target),
        Scale::Log => log_ticks(range.0, range.1, target),
    }
}

/// The corner of the plotting area where the legend hides the fewest points.
fn legend_corner(data: &[Vec<(f64, f64)>], x: (f64, f64), y: (f64, f64)) -> SeriesLabelPosition {
    // Each corner's box as fractions of the frame: (left, right), (bottom, top).
    let corners = [
        (SeriesLabelPosition::UpperRight, (0.6, 1.0), (0.7, 1.0)),
        (SeriesLabelPosition::UpperLeft, (0.0, 0.4), (0.7, 1.0)),
        (SeriesLabelPosition::LowerRight, (0.6, 1.0), (0.0, 0.3)),
        (SeriesLabelPosition::LowerLeft, (0.0, 0.4), (0.0, 0.3)),
    ];
    let count = |(fx0, fx1): (f64, f64), (fy0, fy1): (f64, f64)| {
        let (ax, bx) = (x.0 + fx0 * (x.1 - x.0), x.0 + fx1 * (x.1 - x.0));
        let (ay, by) = (y.0 + fy0 * (y.1 - y.0), y.0 + fy1 * (y.1 - y.0));
        data.iter()
            .flatten()
            .filter(|p| (ax..=bx).contains(&p.0) && (ay..=by).contains(&p.1))
            .count()
    };
    let mut best = (SeriesLabelPosition::UpperRight, usize::MAX);
    for (corner, fx, fy) in corners {
        let n = count(fx, fy);
        if n < best.1 {
            best = (corner, n);
        }
    }
    best.0
}

/// An axis with the ticks chosen here, mapped linearly in display
/// coordinates.
#[derive(Clone)]
struct Axis {
    inner: RangedCoordf64,
    major: Vec<f64>,
    minor: Vec<f64>,
}

impl Axis {
    fn new((lo, hi): (f64, f64), ticks: &Ticks) -> Self {
        Self {
            inner: (lo..hi).into(),
            major: ticks.major.iter().map(|t| t.0).collect(),
            minor: ticks.minor.clone(),
        }
    }
}

impl Ranged for Axis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.minor.clone()
        } else {
            self.major.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.inner.range()
    }
}

/// Outline of marker `shape` (by series index: circle, square, triangle,
/// diamond), in pixels around its centre.
fn marker_outline(shape: usize) -> Vec<(i32, i32)> {
    let r = MARKER_RADIUS;
    match shape % 4 {
        0 => (0..12)
            .map(|i| {
                let a = f64::from(i) * std::f64::consts::TAU / 12.0;
                let r = f64::from(r);
                ((r * a.cos()).round() as i32, (r * a.sin()).round() as i32)
            })
            .collect(),
        1 => vec![(-r + 1, -r + 1), (r - 1, -r + 1), (r - 1, r - 1), (-r + 1, r - 1)],
        2 => vec![(0, -r - 1), (r, r - 1), (-r, r - 1)],
        _ => vec![(0, -r - 1), (r + 1, 0), (0, r + 1), (-r - 1, 0)],
    }
}

/// Draw `figure` on `root`. With `segmented`, each segment of a line is a
/// path of its own: the bitmap backend fills a wide polyline as one polygon,
/// which leaves holes where a dense curve crosses itself.
fn render<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, figure: &Figure, segmented: bool) -> Result<(), String> {
    let text = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (xs, ys) = (figure.x_scale, figure.y_scale);
    let prepared: Vec<(Vec<(f64, f64)>, bool)> = figure.series.iter().map(|s| prepare(s, xs, ys)).collect();
    let data: Vec<Vec<(f64, f64)>> = prepared.iter().map(|p| p.0.clone()).collect();
    let empty = data.iter().all(Vec::is_empty);

    root.fill(&WHITE).map_err(text)?;
    let area = if figure.title.is_empty() {
        root.clone()
    } else {
        root.titled(figure.title, (FONT, TITLE_SIZE)).map_err(text)?
    };

    // Ranges and ticks depend on the size of the plotting area (equal aspect,
    // tick density), which depends on the width of the y tick labels: lay out
    // with a first guess, then again with the labels found.
    let mut x_range = axis_range(extent(data.iter().flatten().map(|p| p.0)), xs);
    let mut y_range = axis_range(extent(data.iter().flatten().map(|p| p.1)), ys);
    let (area_w, area_h) = area.dim_in_pixel();
    let plot_size = |y_area: u32| {
        (
            area_w.saturating_sub(2 * MARGIN + y_area).max(1),
            area_h.saturating_sub(2 * MARGIN + X_LABEL_AREA).max(1),
        )
    };
    let mut y_area = MIN_Y_LABEL_AREA + 20;
    for _ in 0..2 {
        let (w, h) = plot_size(y_area);
        let y_ticks = if figure.equal_aspect {
            ticks(equalise(x_range, y_range, (w, h)).1, ys, h, 60)
        } else {
            ticks(y_range, ys, h, 60)
        };
        y_area = (y_ticks.label_width() + 45).clamp(MIN_Y_LABEL_AREA, 220);
    }
    let size = plot_size(y_area);
    if figure.equal_aspect {
        (x_range, y_range) = equalise(x_range, y_range, size);
    }
    let x_ticks = ticks(x_range, xs, size.0, 100);
    let y_ticks = ticks(y_range, ys, size.1, 60);

    let mut chart = ChartBuilder::on(&area)
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(y_area)
        .build_cartesian_2d(Axis::new(x_range, &x_ticks), Axis::new(y_range, &y_ticks))
        .map_err(text)?;
    let x_label = |v: &f64| x_ticks.label(*v);
    let y_label = |v: &f64| y_ticks.label(*v);
    chart
        .configure_mesh()
        .x_desc(figure.x_label)
        .y_desc(figure.y_label)
        .axis_desc_style((FONT, AXIS_LABEL_SIZE))
        .label_style((FONT, TICK_LABEL_SIZE))
        .x_label_formatter(&x_label)
        .y_label_formatter(&y_label)
        .bold_line_style(MAJOR_GRID.stroke_width(1))
        .light_line_style(MINOR_GRID.stroke_width(1))
        .axis_style(BLACK.stroke_width(1))
        .draw()
        .map_err(text)?;

    for (k, (series, (points, decimated))) in figure.series.iter().zip(&prepared).enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        let with_markers = figure.markers && !decimated;
        let line = colour.stroke_width(2);
        let annotation = if points.len() == 1 {
            // A lone point has no line: show it as a dot.
            chart.draw_series(
                points
                    .iter()
                    .map(|&p| EmptyElement::at(p) + Circle::new((0, 0), 2, colour.filled())),
            )
        } else if segmented {
            chart.draw_series(points.windows(2).map(|w| PathElement::new(w.to_vec(), line)))
        } else {
            chart.draw_series(std::iter::once(PathElement::new(points.clone(), line)))
        }
        .map_err(text)?;
        if !series.label.is_empty() {
            let label = if points.is_empty() {
                format!("{} (no data)", series.label)
            } else {
                series.label.to_string()
            };
            annotation.label(label).legend(move |(x, y)| {
                let (outline, fill) = if with_markers {
                    (marker_outline(k), colour.filled())
                } else {
                    (Vec::new(), TRANSPARENT.filled())
                };
                EmptyElement::at((x + 12, y))
                    + PathElement::new(vec![(-12, 0), (12, 0)], colour.stroke_width(2))
                    + Polygon::new(outline, fill)
            });
        }
        if with_markers {
            let fill = colour.filled();
            if k % 4 == 0 {
                chart.draw_series(
                    points
                        .iter()
                        .map(|&p| EmptyElement::at(p) + Circle::new((0, 0), MARKER_RADIUS, fill)),
                )
            } else {
                let outline = marker_outline(k);
                chart.draw_series(
                    points
                        .iter()
                        .map(|&p| EmptyElement::at(p) + Polygon::new(outline.clone(), fill)),
                )
            }
            .map_err(text)?;
        }
    }

    // Frame the plotting area on all four sides.
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(x_range.0, y_range.0), (x_range.1, y_range.1)],
            BLACK.stroke_width(1),
        )))
        .map_err(text)?;

    if empty {
        let note = if xs == Scale::Log || ys == Scale::Log {
            "no data to show: log axes need positive, finite values"
        } else {
            "no data to show: no finite values"
        };
        let style = TextStyle::from((FONT, AXIS_LABEL_SIZE))
            .color(&RGBColor(90, 90, 90))
            .pos(Pos::new(HPos::Center, VPos::Center));
        chart
            .draw_series(std::iter::once(Text::new(
                note,
                (0.5 * x_range.0 + 0.5 * x_range.1, 0.5 * y_range.0 + 0.5 * y_range.1),
                style,
            )))
            .map_err(text)?;
    }

    let labelled = figure.series.iter().filter(|s| !s.label.is_empty()).count();
    if figure.series.len() > 1 && labelled > 0 {
        chart
            .configure_series_labels()
            .position(legend_corner(&data, x_range, y_range))
            .label_font((FONT, LEGEND_SIZE))
            .background_style(WHITE.mix(0.9))
            .border_style(RGBColor(160, 160, 160))
            .margin(12)
            .legend_area_size(30)
            .draw()
            .map_err(text)?;
    }
    root.present().map_err(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh directory for this test's files.
    fn out_dir(test: &str) -> PathBuf {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos())
            .unwrap_or(0);
        let dir = std::env::temp_dir().join(format!("veselov-plot-{test}-{}-{nanos}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("create the temporary directory");
        dir
    }

    fn figure<'a>(series: Vec<Series<'a>>, x_scale: Scale, y_scale: Scale) -> Figure<'a> {
        Figure {
            title: "Title of the figure",
            x_label: "time t",
            y_label: "|E(t) − E(0)|",
            x_scale,
            y_scale,
            series,
            markers: false,
            equal_aspect: false,
        }
    }

    /// Draw `figure` as SVG and PNG under `dir`, check both files, and
    /// return the SVG text.
    fn draw_both(dir: &Path, name: &str, figure: &Figure) -> String {
        let png = dir.join(format!("{name}.png"));
        draw(&png, figure).expect("draw the PNG");
        let bytes = std::fs::read(&png).expect("read the PNG");
        assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "{name}.png is a PNG");
        let svg = dir.join(format!("{name}.svg"));
        draw(&svg, figure).expect("draw the SVG");
        let text = std::fs::read_to_string(&svg).expect("read the SVG");
        assert!(text.starts_with("<svg"), "{name}.svg is an SVG");
        for needle in [figure.title, figure.x_label, figure.y_label] {
            assert!(text.contains(needle), "{name}.svg shows {needle:?}");
        }
        text
    }

    #[test]
    fn linear_plot_with_two_series_has_a_legend() {
        let dir = out_dir("linear");
        let x: Vec<f64> = (0..200).map(|i| f64::from(i) * 0.05).collect();
        let sin: Vec<f64> = x.iter().map(|x| x.sin()).collect();
        let cos: Vec<f64> = x.iter().map(|x| x.cos()).collect();
        let mut fig = figure(
            vec![
                Series {
                    label: "sine",
                    x: &x,
                    y: &sin,
                },
                Series {
                    label: "cosine",
                    x: &x,
                    y: &cos,
                },
            ],
            Scale::Linear,
            Scale::Linear,
        );
        fig.markers = true;
        let svg = draw_both(&dir, "linear", &fig);
        assert!(svg.contains(">\nsine\n") || svg.contains(">sine<"), "legend");
        assert!(svg.contains("cosine"), "legend");
        // Two colours for the two lines.
        assert!(svg.contains("#1F77B4") && svg.contains("#FF7F0E"), "colours");
        fig.markers = false;
        let svg = draw_both(&dir, "linear-lines", &fig);
        assert!(!svg.contains("<circle"), "no markers");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn log_log_plot_skips_zero_and_nan() {
        let dir = out_dir("loglog");
        let dt = [0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125];
        let err = [1e-4, 6.25e-6, 0.0, f64::NAN, 2.4e-10, 1.5e-12];
        let slope: Vec<f64> = dt.iter().map(|h| 1e-4 * (h / 0.1f64).powi(4)).collect();
        let mut fig = figure(
            vec![
                Series {
                    label: "measured",
                    x: &dt,
                    y: &err,
                },
                Series {
                    label: "slope 4",
                    x: &dt,
                    y: &slope,
                },
            ],
            Scale::Log,
            Scale::Log,
        );
        fig.markers = true;
        let svg = draw_both(&dir, "loglog", &fig);
        assert!(svg.contains("1e-12"), "scientific tick labels");
        let (points, _) = prepare(&fig.series[0], Scale::Log, Scale::Log);
        assert_eq!(points.len(), 4, "zero and NaN skipped");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn nothing_to_show_on_log_axes_gives_an_empty_frame_with_a_note() {
        let dir = out_dir("empty");
        let x = [1.0, 2.0, 3.0];
        let y = [0.0, -1.0, f64::INFINITY];
        let fig = figure(
            vec![Series {
                label: "zero",
                x: &x,
                y: &y,
            }],
            Scale::Linear,
            Scale::Log,
        );
        let svg = draw_both(&dir, "empty", &fig);
        assert!(svg.contains("no data to show"), "note");
        let fig = figure(Vec::new(), Scale::Log, Scale::Log);
        draw_both(&dir, "no-series", &fig);
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn constant_series_gets_a_proper_axis() {
        let dir = out_dir("constant");
        let x: Vec<f64> = (0..100).map(f64::from).collect();
        let two = vec![2.0; 100];
        let zero = vec![0.0; 100];
        let tiny = vec![1e-14; 100];
        for (name, y, scale) in [
            ("two", &two, Scale::Linear),
            ("zero", &zero, Scale::Linear),
            ("tiny", &tiny, Scale::Log),
        ] {
            let fig = figure(vec![Series { label: name, x: &x, y }], Scale::Linear, scale);
            let svg = draw_both(&dir, name, &fig);
            let y_range = axis_range(extent(y.iter().filter_map(|&v| to_axis(v, scale))), scale);
            assert!(y_range.1 > y_range.0, "{name}: non-degenerate range");
            let ticks = ticks(y_range, scale, 400, 60);
            assert!(ticks.major.len() >= 2, "{name}: {ticks:?}");
            assert!(svg.contains(&ticks.major[0].1), "{name}: tick labels");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn equal_aspect_orbit_has_equal_scales() {
        let dir = out_dir("orbit");
        let (x, y): (Vec<f64>, Vec<f64>) = (0..=400)
            .map(|i| {
                let t = f64::from(i) * std::f64::consts::TAU / 400.0;
                (3.0 * t.cos() + 1.0, 0.5 * t.sin())
            })
            .unzip();
        let mut fig = figure(
            vec![Series {
                label: "orbit",
                x: &x,
                y: &y,
            }],
            Scale::Linear,
            Scale::Linear,
        );
        fig.title = "Orbit in the plane";
        fig.x_label = "q0";
        fig.y_label = "q1";
        fig.equal_aspect = true;
        draw_both(&dir, "orbit", &fig);
        let xr = axis_range(extent(x.iter().copied()), Scale::Linear);
        let yr = axis_range(extent(y.iter().copied()), Scale::Linear);
        let (ex, ey) = equalise(xr, yr, (600, 450));
        assert_eq!(ex, xr, "the longer range is kept");
        let (sx, sy) = ((ex.1 - ex.0) / 600.0, (ey.1 - ey.0) / 450.0);
        assert!((sx - sy).abs() <= 1e-12 * sx, "{sx} vs {sy}");
        assert!(ey.0 < yr.0 && ey.1 > yr.1, "the shorter range is padded");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn a_million_points_are_decimated_and_spikes_kept() {
        let dir = out_dir("large");
        let n = 1_000_000usize;
        let x: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
        let mut y: Vec<f64> = x.iter().map(|t| 1e-3 * (7.0 * t).sin()).collect();
        y[123_457] = 5.0;
        y[765_433] = -4.0;
        let series = Series {
            label: "signal",
            x: &x,
            y: &y,
        };
        let (points, decimated) = prepare(&series, Scale::Linear, Scale::Linear);
        assert!(decimated && points.len() <= MAX_POINTS, "{}", points.len());
        assert!(points.contains(&(x[123_457], 5.0)), "upward spike kept");
        assert!(points.contains(&(x[765_433], -4.0)), "downward spike kept");
        assert!(points.windows(2).all(|w| w[0].0 < w[1].0), "order kept");
        assert_eq!(points.first(), Some(&(x[0], y[0])));
        assert_eq!(points.last(), Some(&(x[n - 1], y[n - 1])));
        let mut fig = figure(vec![series], Scale::Linear, Scale::Linear);
        fig.markers = true;
        draw_both(&dir, "large", &fig);
        let size = std::fs::metadata(dir.join("large.svg")).expect("SVG written").len();
        assert!(size < 1_000_000, "SVG of {size} bytes");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn unknown_extension_is_an_error_naming_it() {
        let dir = out_dir("unknown");
        let x = [1.0, 2.0];
        let fig = figure(
            vec![Series {
                label: "a",
                x: &x,
                y: &x,
            }],
            Scale::Linear,
            Scale::Linear,
        );
        let path = dir.join("plot.jpg");
        let e = draw(&path, &fig).expect_err("a .jpg file is refused");
        assert_eq!(e.path, path);
        let message = e.to_string();
        assert!(message.starts_with("cannot draw "), "{message}");
        assert!(message.contains(".jpg"), "{message}");
        assert!(!path.exists());
        let e = draw(&dir.join("plot"), &fig).expect_err("no extension");
        assert!(e.message.contains("no extension"), "{e}");
        assert_eq!(PlotFormat::from_path(Path::new("a.SVG")), Some(PlotFormat::Svg));
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn unwritable_path_is_an_error() {
        let dir = out_dir("unwritable");
        let x = [1.0, 2.0];
        let fig = figure(
            vec![Series {
                label: "a",
                x: &x,
                y: &x,
            }],
            Scale::Linear,
            Scale::Linear,
        );
        for ext in ["svg", "png"] {
            let path = dir.join("missing").join(format!("plot.{ext}"));
            let e = draw(&path, &fig).expect_err("no such directory");
            assert!(e.to_string().starts_with("cannot draw "), "{e}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn extreme_values_do_not_break_the_axes() {
        let dir = out_dir("extreme");
        let x = [-f64::MAX, 0.0, f64::MAX];
        let y = [f64::MIN_POSITIVE, 1.0, f64::MAX];
        let fig = figure(
            vec![Series {
                label: "wide",
                x: &x,
                y: &y,
            }],
            Scale::Linear,
            Scale::Log,
        );
        draw_both(&dir, "extreme", &fig);
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn tick_labels() {
        let t = linear_ticks(-0.05, 1.05, 6);
        let labels: Vec<&str> = t.major.iter().map(|m| m.1.as_str()).collect();
        assert_eq!(labels, ["0.0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
        let t = log_ticks(-12.3, -3.7, 6);
        assert!(t.major.iter().any(|m| m.1 == "1e-12"), "{t:?}");
        let t = log_ticks(0.1, 0.9, 6);
        let labels: Vec<&str> = t.major.iter().map(|m| m.1.as_str()).collect();
        assert_eq!(labels, ["2e0", "5e0"]);
        let t = linear_ticks(0.0, 1e6, 6);
        assert!(t.major.iter().any(|m| m.1 == "2e5"), "{t:?}");
        assert_eq!(scientific(1.5e-7, 3), "1.5e-7");
    }
}
