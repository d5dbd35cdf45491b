//! Laying out and drawing a figure on a `plotters` backend: frame, grid,
//! ticks, series, markers and legend.

use plotters::coord::Shift;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::data::{axis_range, equalise, extent, offset, offset_label, prepare};
use super::ticks::{TICK_LABEL_SIZE, Ticks, ticks};
use super::{FONT, Figure, Scale};

const TITLE_SIZE: u32 = 24;
const AXIS_LABEL_SIZE: u32 = 18;
const LEGEND_SIZE: u32 = 15;
const MARGIN: u32 = 20;
const X_LABEL_AREA: u32 = 60;
/// The y-label area grows with the widest tick label, from this minimum.
const MIN_Y_LABEL_AREA: u32 = 70;
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
pub(crate) struct Axis {
    inner: RangedCoordf64,
    major: Vec<f64>,
    minor: Vec<f64>,
}

impl Axis {
    /// The axis over `(lo, hi)` with the major and minor ticks of `ticks`.
    pub(crate) fn new((lo, hi): (f64, f64), ticks: &Ticks) -> Self {
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
pub(super) fn render<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    figure: &Figure,
    segmented: bool,
) -> Result<(), String> {
    let text = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (xs, ys) = (figure.x_scale, figure.y_scale);
    let mut prepared: Vec<(Vec<(f64, f64)>, bool)> = figure.series.iter().map(|s| prepare(s, xs, ys)).collect();
    // Values that differ only far into their digits are drawn as deviations
    // from a round offset named in the axis label.
    let all = || prepared.iter().flat_map(|p| p.0.iter());
    let shift = (
        offset(extent(all().map(|p| p.0)), xs),
        offset(extent(all().map(|p| p.1)), ys),
    );
    for (points, _) in &mut prepared {
        for p in points.iter_mut() {
            p.0 -= shift.0.map_or(0.0, |o| o.0);
            p.1 -= shift.1.map_or(0.0, |o| o.0);
        }
    }
    let x_desc = shift
        .0
        .map_or_else(|| figure.x_label.to_string(), |o| offset_label(figure.x_label, o));
    let y_desc = shift
        .1
        .map_or_else(|| figure.y_label.to_string(), |o| offset_label(figure.y_label, o));
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
        .x_desc(&x_desc)
        .y_desc(&y_desc)
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
