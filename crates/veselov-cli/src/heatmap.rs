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
    /// Title (the colour range is appended).
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
    let result = match format {
        PlotFormat::Svg => render(SVGBackend::new(path, (WIDTH, HEIGHT)).into_drawing_area(), map),
        PlotFormat::Png => render(BitMapBackend::new(path, (WIDTH, HEIGHT)).into_drawing_area(), map),
    };
    result.map_err(|message| {
        let _ = std::fs::remove_file(path);
        fail(message)
    })
}

/// `count` indices spread evenly over `0..len` (all of them if `len ≤ count`).
fn subsample(len: usize, count: usize) -> Vec<usize> {
    if len <= count {
        (0..len).collect()
    } else {
        (0..count).map(|k| k * (len - 1) / (count - 1).max(1)).collect()
    }
}

fn render<DB: DrawingBackend>(root: DrawingArea<DB, plotters::coord::Shift>, map: &Heatmap) -> Result<(), String> {
    let text = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let rows = map.values.len();
    let cols = map.values.first().map_or(0, Vec::len);
    let finite = map.values.iter().flatten().copied().filter(|v| v.is_finite());
    let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = if lo.is_finite() && hi > lo {
        (lo, hi)
    } else {
        (lo.min(0.0), lo.max(0.0) + 1.0)
    };
    root.fill(&WHITE).map_err(text)?;
    let title = format!("{} (colour: {lo:.3} to {hi:.3})", map.title);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 22))
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(map.x_range.0..map.x_range.1, map.y_range.0..map.y_range.1)
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
    let dx = (map.x_range.1 - map.x_range.0) / ci.len() as f64;
    let dy = (map.y_range.1 - map.y_range.0) / ri.len() as f64;
    let cells = ri.iter().enumerate().flat_map(|(a, &r)| {
        ci.iter().enumerate().map(move |(b, &c)| {
            let v = map.values[r].get(c).copied().unwrap_or(f64::NAN);
            let colour = if v.is_finite() {
                ViridisRGB.get_color_normalized(v, lo, hi)
            } else {
                RGBColor(255, 255, 255)
            };
            let x0 = map.x_range.0 + b as f64 * dx;
            let y0 = map.y_range.0 + a as f64 * dy;
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
    fn subsample_keeps_ends_and_count() {
        assert_eq!(subsample(5, 10), vec![0, 1, 2, 3, 4]);
        let s = subsample(1000, 300);
        assert_eq!(s.len(), 300);
        assert_eq!((s[0], s[299]), (0, 999));
        assert!(s.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn draws_svg_and_png() {
        let dir = std::env::temp_dir().join(format!("veselov-heatmap-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
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
