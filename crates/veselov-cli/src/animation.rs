//! An animated GIF of a centreline (of the rod or the beam) over a run: one
//! frame per stored row, at most [`MAX_FRAMES`], drawn in the coordinate
//! plane in which the centreline moves most, with the same axes (one unit
//! the same length on both) in every frame, and the time in the title.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::gif_frames::{AnimationEncoder, LINE_COLOUR};
use crate::plot::{Axis, FONT, PlotError, Ticks, linear_axis_ticks, register_font};

/// Frames kept (rows are subsampled evenly, first and last kept).
pub const MAX_FRAMES: u64 = 120;

/// Delay between frames in milliseconds.
const FRAME_DELAY_MS: u32 = 80;

/// Size of the animation in pixels.
const SIZE: (u32, u32) = (640, 480);

/// The two coordinate axes (0 = x, 1 = y, 2 = z) over which `frames` spread
/// most, in increasing order, with their common ranges.
fn plane(frames: &[Vec<[f64; 3]>]) -> ([usize; 2], [(f64, f64); 2]) {
    let mut ranges = [(f64::INFINITY, f64::NEG_INFINITY); 3];
    for p in frames.iter().flatten() {
        for (r, v) in ranges.iter_mut().zip(p) {
            if v.is_finite() {
                *r = (r.0.min(*v), r.1.max(*v));
            }
        }
    }
    let spread = |a: usize| {
        let (lo, hi) = ranges[a];
        if hi >= lo { hi - lo } else { 0.0 }
    };
    // Drop the axis of least spread.
    let least = (0..3).min_by(|&a, &b| spread(a).total_cmp(&spread(b))).unwrap_or(1);
    let axes = match least {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    };
    // Equal units, with a 10 % margin, never degenerate.
    let half = axes.iter().map(|&a| 0.55 * spread(a)).fold(1e-9_f64, f64::max);
    let range = |a: usize| {
        let (lo, hi) = ranges[a];
        let mid = if hi >= lo { 0.5 * (lo + hi) } else { 0.0 };
        (mid - half, mid + half)
    };
    (axes, [range(axes[0]), range(axes[1])])
}

/// The chart of every frame: a square plotting area (one unit the same
/// length on both axes) below the title's band.
/// The mesh and labels are those of the plots' own axes ([`Ticks`]).
fn chart<'a, 'b>(
    root: &'a DrawingArea<BitMapBackend<'b>, Shift>,
    ranges: [(f64, f64); 2],
    axes: &[Ticks; 2],
) -> Result<ChartContext<'a, BitMapBackend<'b>, Cartesian2d<Axis, Axis>>, String> {
    let [ra, rb] = ranges;
    ChartBuilder::on(root)
        .margin(MARGIN)
        .margin_top(TITLE_BAND)
        .margin_left(SIDE_MARGIN)
        .margin_right(SIDE_MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(Axis::new(ra, &axes[0]), Axis::new(rb, &axes[1]))
        .map_err(|e| e.to_string())
}

/// The chart's margins and label areas (pixels).
const MARGIN: u32 = 15;
const SIDE_MARGIN: u32 = 80;
const X_LABEL_AREA: u32 = 40;
const Y_LABEL_AREA: u32 = 60;

/// The ticks of the chart's two axes over `ranges` ([`linear_axis_ticks`]
/// on the plotting area's width and height, about one per 60 pixels on
/// both: one unit has the same length on both axes, so the spacing agrees).
fn axis_ticks(ranges: [(f64, f64); 2]) -> [Ticks; 2] {
    let (w, h) = SIZE;
    let width = w.saturating_sub(2 * SIDE_MARGIN + Y_LABEL_AREA);
    let height = h.saturating_sub(TITLE_BAND + MARGIN + X_LABEL_AREA);
    [
        linear_axis_ticks(ranges[0], width, 60),
        linear_axis_ticks(ranges[1], height, 60),
    ]
}

/// Height of the band above the chart that holds the title (pixels).
const TITLE_BAND: u32 = 45;

/// Draw `frames` (each the points of the centreline) at `times` as an
/// animated GIF at `path`; `time_label` names the evolution parameter (`t`,
/// or `s` for the beam's space evolution). The axes, mesh and labels are
/// drawn once; each frame copies them and draws its title and centreline
/// ([`AnimationEncoder`] stores only what changed).
pub fn draw_centerline_animation(
    path: &Path,
    frames: &[Vec<[f64; 3]>],
    times: &[f64],
    time_label: &str,
) -> Result<(), PlotError> {
    let fail = |message: String| PlotError {
        path: path.to_path_buf(),
        message,
    };
    register_font().map_err(fail)?;
    let ([a, b], ranges) = plane(frames);
    let axes = axis_ticks(ranges);
    let names = ["x", "y", "z"];
    let (w, h) = SIZE;
    let mut background = vec![0u8; 3 * w as usize * h as usize];
    {
        let root = BitMapBackend::with_buffer(&mut background, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(e.to_string()))?;
        chart(&root, ranges, &axes)
            .map_err(fail)?
            .configure_mesh()
            .x_label_formatter(&|v| axes[0].label(*v))
            .y_label_formatter(&|v| axes[1].label(*v))
            .x_desc(names[a])
            .y_desc(names[b])
            .label_style((FONT, 13))
            .axis_desc_style((FONT, 15))
            .draw()
            .map_err(|e| fail(e.to_string()))?;
        root.present().map_err(|e| fail(e.to_string()))?;
    }
    let narrow = |v: u32| u16::try_from(v).unwrap_or(u16::MAX);
    let mut encoder = AnimationEncoder::create(path, (narrow(w), narrow(h)), FRAME_DELAY_MS).map_err(fail)?;
    let mut pixels = background.clone();
    let title_style = TextStyle::from((FONT, 20).into_font()).pos(Pos::new(HPos::Center, VPos::Center));
    for (k, points) in frames.iter().enumerate() {
        pixels.copy_from_slice(&background);
        {
            let root = BitMapBackend::with_buffer(&mut pixels, SIZE).into_drawing_area();
            let title = match times.get(k) {
                Some(t) => format!("Centreline, {time_label} = {t:.4}"),
                None => format!("Centreline, frame {k}"),
            };
            let centre = (
                i32::try_from(w / 2).unwrap_or(0),
                i32::try_from(TITLE_BAND / 2).unwrap_or(0),
            );
            root.draw(&Text::new(title, centre, &title_style))
                .map_err(|e| fail(e.to_string()))?;
            let [r, g, bl] = LINE_COLOUR;
            chart(&root, ranges, &axes)
                .map_err(fail)?
                .draw_series(LineSeries::new(
                    points.iter().map(|p| (p[a], p[b])),
                    RGBColor(r, g, bl).stroke_width(2),
                ))
                .map_err(|e| fail(e.to_string()))?;
            root.present().map_err(|e| fail(e.to_string()))?;
        }
        encoder.push(&pixels).map_err(fail)?;
    }
    encoder.finish().map_err(fail)
}

/// Read the centreline of every stored row (at most [`MAX_FRAMES`]) from
/// `dir/<stem>.npy` (rows of `nodes` points of `width` values, the point
/// given by `point(row, node)`), the times from the column `time` of
/// `dir/energy.csv` (a row for each stored row), and write
/// `dir/centerline.gif`.
pub fn animate_run(
    dir: &Path,
    (stem, width): (&str, usize),
    nodes: usize,
    rows: u64,
    point: impl Fn(&[f64], usize) -> [f64; 3],
    time: &str,
) -> Result<(), crate::error::CliError> {
    use crate::pipeline::readback::rows_for_plots;
    let columns: Vec<String> = (0..nodes * width).map(|i| i.to_string()).collect();
    let stored = rows_for_plots(dir, stem, &columns, rows, MAX_FRAMES)?;
    let frames: Vec<Vec<[f64; 3]>> = stored
        .rows
        .iter()
        .map(|r| (0..nodes).map(|p| point(r, p)).collect())
        .collect();
    let header = crate::output::Table::read_csv(&dir.join("energy.csv"))?.header;
    let times = rows_for_plots(dir, "energy", &header, rows, MAX_FRAMES)?
        .column(time)
        .unwrap_or_default();
    draw_centerline_animation(&dir.join("centerline.gif"), &frames, &times, time).map_err(crate::figures::plot_err)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plane_is_that_of_the_largest_spread() {
        // A rod along z bending in y: the y–z plane.
        let frames: Vec<Vec<[f64; 3]>> = (0..3)
            .map(|k| (0..5).map(|i| [0.0, 0.01 * (k * i) as f64, 0.1 * i as f64]).collect())
            .collect();
        let (axes, [ra, rb]) = plane(&frames);
        assert_eq!(axes, [1, 2]);
        assert!((ra.1 - ra.0 - (rb.1 - rb.0)).abs() < 1e-12, "equal units");
        assert!(rb.0 <= 0.0 && rb.1 >= 0.4);
    }

    /// A device that refuses every write (Linux's /dev/full): an error naming
    /// the file, no panic (the encoder's trailer and the buffered writer's
    /// flush fail at the end).
    #[test]
    fn a_full_disk_is_an_error() {
        let full = std::path::Path::new("/dev/full");
        if !full.exists() {
            return;
        }
        let frames: Vec<Vec<[f64; 3]>> = (0..2).map(|k| vec![[0.0, k as f64, 0.0], [1.0, 0.0, 0.0]]).collect();
        let e = draw_centerline_animation(full, &frames, &[0.0, 1.0], "t").expect_err("no space");
        assert_eq!(e.path, full);
    }

    #[test]
    fn writes_an_animated_gif() {
        let dir = crate::test_scratch::Scratch::new("gif");
        let path = dir.join("centerline.gif");
        let frames: Vec<Vec<[f64; 3]>> = (0..4)
            .map(|k| {
                (0..10)
                    .map(|i| [0.1 * i as f64, (0.3 * (k + i) as f64).sin(), 0.0])
                    .collect()
            })
            .collect();
        draw_centerline_animation(&path, &frames, &[0.0, 0.1, 0.2, 0.3], "t").expect("drawn");
        let bytes = std::fs::read(&path).expect("gif");
        assert!(bytes.starts_with(b"GIF89a"), "a GIF file");
    }
}
