//! Space–time heat maps (a field over nodes × stored levels), drawn with the
//! embedded font and the viridis colour map, as SVG or PNG by file extension.

use std::path::Path;

use plotters::prelude::*;

use crate::plot::{FONT, HEIGHT, PlotError, PlotFormat, WIDTH, register_font};

/// Largest number of cells drawn along each axis; larger grids are
/// subsampled (nearest row and column) so that files stay small.
pub const MAX_CELLS: usize = 300;

/// A heat map of `values[row][column]`: rows run along y (time), columns
/// along x (space).
pub struct Heatmap<'a> {
    /// Title (the colour bar beside the map gives the value of each colour).
    pub title: &'a str,
    /// x-axis label.
    pub x_label: &'a str,
    /// y-axis label.
    pub y_label: &'a str,
    /// x range covered by the columns.
    pub x_range: (f64, f64),
    /// y range covered by the rows.
    pub y_range: (f64, f64),
    /// The grid, all rows of equal length.
    pub values: &'a [Vec<f64>],
}

/// Draw `map` to `path` (`.svg` or `.png`).
pub fn draw_heatmap(path: &Path, map: &Heatmap) -> Result<(), PlotError> {
    let fail = |message: String| PlotError {
        path: path.to_path_buf(),
        message,
    };
    let format = PlotFormat::from_path(path).ok_or_else(|| fail("expected a .svg or .png file name".into()))?;
    register_font().map_err(fail)?;
    // Rendering goes through a third-party library: should it panic on some
    // input, report that as an error rather than abort the command.
    let rendered = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match format {
        PlotFormat::Svg => render(SVGBackend::new(path, (WIDTH, HEIGHT)).into_drawing_area(), map),
        PlotFormat::Png => render(BitMapBackend::new(path, (WIDTH, HEIGHT)).into_drawing_area(), map),
    }));
    let result = rendered.unwrap_or_else(|_| Err("the plotting library failed".to_string()));
    result.map_err(|message| {
        let _ = std::fs::remove_file(path);
        fail(message)
    })
}

/// Width in pixels of the colour bar and its labels, right of the map.
const COLOUR_BAR_AREA: u32 = 110;

/// Colour steps drawn in the colour bar.
const COLOUR_BAR_STEPS: usize = 128;

/// The colour bar: the viridis scale from `lo` (bottom) to `hi` (top), with
/// value labels on its right.
fn draw_colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    (lo, hi): (f64, f64),
) -> Result<(), String> {
    let text = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let mut chart = ChartBuilder::on(area)
        .margin_top(20)
        .margin_bottom(70)
        .margin_left(10)
        .margin_right(5)
        .right_y_label_area_size(70)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(text)?
        .set_secondary_coord(0.0..1.0, lo..hi);
    let step = (hi - lo) / COLOUR_BAR_STEPS as f64;
    chart
        .draw_series((0..COLOUR_BAR_STEPS).map(|k| {
            let v0 = lo + k as f64 * step;
            let colour = ViridisRGB.get_color_normalized(v0 + 0.5 * step, lo, hi);
            Rectangle::new([(0.0, v0), (1.0, v0 + step)], colour.filled())
        }))
        .map_err(text)?;
    chart
        .configure_secondary_axes()
        .y_labels(6)
        .y_label_formatter(&|v| bar_label(*v, (lo, hi)))
        .label_style((FONT, 14))
        .draw()
        .map_err(text)?;
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(0.0, lo), (1.0, hi)],
            BLACK.stroke_width(1),
        )))
        .map_err(text)?;
    Ok(())
}

/// A colour-bar label: fixed decimals enough to tell labels `(hi − lo)/6`
/// apart, or scientific notation for very large or very small values.
fn bar_label(v: f64, (lo, hi): (f64, f64)) -> String {
    let (span, big) = (hi - lo, lo.abs().max(hi.abs()));
    if span > 0.0 && (1e-3..1e5).contains(&big) && span >= 1e-4 * big {
        let decimals = (2.0 - span.log10().floor()).clamp(0.0, 8.0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

/// `count` indices spread evenly over `0..len` (all of them if `len ≤ count`).
fn subsample(len: usize, count: usize) -> Vec<usize> {
    if len <= count {
        (0..len).collect()
    } else {
        (0..count).map(|k| k * (len - 1) / (count - 1).max(1)).collect()
    }
}

/// The values the colour map spans: those of the finite `values` (cells
/// of NaN or infinity are drawn white, as gaps), widened to a unit range
/// when they are all equal or none is finite, and narrowed to half the
/// largest float each way so that the span is finite.
fn colour_range(values: &[Vec<f64>]) -> (f64, f64) {
    let finite = values.iter().flatten().copied().filter(|v| v.is_finite());
    let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = if !lo.is_finite() {
        (0.0, 1.0)
    } else if hi > lo {
        (lo, hi)
    } else {
        (lo.min(0.0), lo.max(0.0) + 1.0)
    };
    let half = 0.5 * f64::MAX;
    (lo.clamp(-half, half), hi.clamp(-half, half))
}

/// An axis range that can be drawn: `range` if finite and not empty, a
/// unit range about its start if empty, `(0, 1)` if not finite.
fn axis((lo, hi): (f64, f64)) -> (f64, f64) {
    match (lo.is_finite() && hi.is_finite(), hi > lo) {
        (true, true) if (hi - lo).is_finite() => (lo, hi),
        (true, false) if (lo + 1.0).is_finite() => (lo, lo + 1.0),
        _ => (0.0, 1.0),
    }
}

fn render<DB: DrawingBackend>(root: DrawingArea<DB, plotters::coord::Shift>, map: &Heatmap) -> Result<(), String> {
    let text = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let rows = map.values.len();
    let cols = map.values.first().map_or(0, Vec::len);
    let (lo, hi) = colour_range(map.values);
    let (x_range, y_range) = (axis(map.x_range), axis(map.y_range));
    root.fill(&WHITE).map_err(text)?;
    let area = root.titled(map.title, (FONT, 22)).map_err(text)?;
    let (width, _) = area.dim_in_pixel();
    let (main, bar) = area.split_horizontally(width.saturating_sub(COLOUR_BAR_AREA));
    draw_colour_bar(&bar, (lo, hi))?;
    let mut chart = ChartBuilder::on(&main)
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)
        .map_err(text)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(map.x_label)
        .y_desc(map.y_label)
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 18))
        .draw()
        .map_err(text)?;
    if rows == 0 || cols == 0 {
        return root.present().map_err(text);
    }
    let (ri, ci) = (subsample(rows, MAX_CELLS), subsample(cols, MAX_CELLS));
    let dx = (x_range.1 - x_range.0) / ci.len() as f64;
    let dy = (y_range.1 - y_range.0) / ri.len() as f64;
    let cells = ri.iter().enumerate().flat_map(|(a, &r)| {
        ci.iter().enumerate().map(move |(b, &c)| {
            let v = map.values[r].get(c).copied().unwrap_or(f64::NAN);
            let colour = if v.is_finite() {
                ViridisRGB.get_color_normalized(v, lo, hi)
            } else {
                RGBColor(255, 255, 255)
            };
            let x0 = x_range.0 + b as f64 * dx;
            let y0 = y_range.0 + a as f64 * dy;
            Rectangle::new([(x0, y0), (x0 + dx, y0 + dy)], colour.filled())
        })
    });
    chart.draw_series(cells).map_err(text)?;
    root.present().map_err(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_bar_labels_are_short_and_tell_values_apart() {
        assert_eq!(bar_label(0.5, (-0.8, 0.8)), "0.50");
        assert_eq!(bar_label(12.25, (0.0, 20.0)), "12.2");
        assert_eq!(bar_label(1.0000005, (1.0, 1.000001)), "1.000e0");
        assert_eq!(bar_label(3e7, (0.0, 1e8)), "3.000e7");
    }

    #[test]
    fn subsample_keeps_ends_and_count() {
        assert_eq!(subsample(5, 10), vec![0, 1, 2, 3, 4]);
        let s = subsample(1000, 300);
        assert_eq!(s.len(), 300);
        assert_eq!((s[0], s[299]), (0, 999));
        assert!(s.windows(2).all(|w| w[0] < w[1]));
    }

    /// NaN and infinite cells are gaps, extreme values and degenerate or
    /// non-finite axis ranges are drawn: no value makes the colour map
    /// (which panics on NaN bounds) or the drawing fail.
    #[test]
    fn non_finite_and_extreme_values_are_drawn() {
        let dir = crate::test_scratch::Scratch::new("heatmap-non-finite");
        let grids = [
            vec![vec![f64::NAN; 5]; 4],
            vec![vec![f64::NAN, 1.0, f64::INFINITY, f64::NEG_INFINITY]; 3],
            vec![vec![-f64::MAX, f64::MAX]; 2],
            vec![vec![1.7e308; 3]; 2],
        ];
        for values in &grids {
            let (lo, hi) = colour_range(values);
            assert!(lo.is_finite() && hi.is_finite() && hi > lo && (hi - lo).is_finite());
            for y_range in [(0.0, 1.0), (f64::NAN, 1.0), (2.0, 2.0), (-f64::MAX, f64::MAX)] {
                let map = Heatmap {
                    title: "test",
                    x_label: "x",
                    y_label: "t",
                    x_range: (0.0, 4.0),
                    y_range,
                    values,
                };
                draw_heatmap(&dir.join("map.png"), &map).expect("drawn");
            }
        }
    }

    #[test]
    fn draws_svg_and_png() {
        let dir = crate::test_scratch::Scratch::new("heatmap");
        let values: Vec<Vec<f64>> = (0..50)
            .map(|r| (0..40).map(|c| ((r * c) as f64).sin()).collect())
            .collect();
        for ext in ["svg", "png"] {
            let path = dir.join(format!("map.{ext}"));
            let map = Heatmap {
                title: "test",
                x_label: "x",
                y_label: "t",
                x_range: (0.0, 40.0),
                y_range: (0.0, 10.0),
                values: &values,
            };
            draw_heatmap(&path, &map).expect("drawn");
            assert!(std::fs::metadata(&path).expect("file").len() > 1000);
        }
    }
}
