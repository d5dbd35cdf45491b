//! Publication-quality line plots as SVG, drawn with `plotters` without any
//! system library (no font files: SVG text is laid out by the viewer).
//!
//! Log axes are drawn by plotting `log₁₀` of the data on linear axes with
//! tick labels `10^v`; non-positive and non-finite values are skipped there.
//! Long series are decimated to at most [`MAX_POINTS`] points per series,
//! keeping each bucket's minimum and maximum so that spikes survive.

use std::path::{Path, PathBuf};

use plotters::prelude::*;

/// Points kept per series after decimation.
pub const MAX_POINTS: usize = 4000;

/// Output format, from the file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotFormat {
    /// `.svg`.
    Svg,
}

/// A plot that could not be drawn.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlotError {
    /// The file.
    pub path: PathBuf,
    /// Why.
    pub message: String,
}

impl std::fmt::Display for PlotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "cannot draw {}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for PlotError {}

/// One curve.
pub struct Series<'a> {
    /// Legend label.
    pub label: &'a str,
    /// Abscissae.
    pub x: &'a [f64],
    /// Ordinates.
    pub y: &'a [f64],
}

/// Axis scale.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    /// Linear.
    Linear,
    /// Base-10 logarithmic.
    Log,
}

/// A figure: axes, labels and curves.
pub struct Figure<'a> {
    /// Title.
    pub title: &'a str,
    /// Label of the horizontal axis.
    pub x_label: &'a str,
    /// Label of the vertical axis.
    pub y_label: &'a str,
    /// Horizontal scale.
    pub x_scale: Scale,
    /// Vertical scale.
    pub y_scale: Scale,
    /// Curves.
    pub series: Vec<Series<'a>>,
    /// Draw markers at the data points as well as lines.
    pub markers: bool,
    /// Same data scale on both axes (orbits in the plane).
    pub equal_aspect: bool,
}

fn transform(v: f64, scale: Scale) -> Option<f64> {
    match scale {
        Scale::Linear => v.is_finite().then_some(v),
        Scale::Log => (v.is_finite() && v > 0.0).then(|| v.log10()),
    }
}

/// Transformed, finite points of a series, decimated by min/max buckets.
fn points(s: &Series, xs: Scale, ys: Scale) -> Vec<(f64, f64)> {
    let pts: Vec<(f64, f64)> =
        s.x.iter()
            .zip(s.y)
            .filter_map(|(&x, &y)| Some((transform(x, xs)?, transform(y, ys)?)))
            .collect();
    if pts.len() <= MAX_POINTS {
        return pts;
    }
    let buckets = MAX_POINTS / 2;
    let size = pts.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(2 * buckets);
    for chunk in pts.chunks(size) {
        let lo = chunk.iter().min_by(|a, b| a.1.total_cmp(&b.1));
        let hi = chunk.iter().max_by(|a, b| a.1.total_cmp(&b.1));
        if let (Some(&lo), Some(&hi)) = (lo, hi) {
            if lo.0 <= hi.0 {
                out.extend([lo, hi]);
            } else {
                out.extend([hi, lo]);
            }
        }
    }
    out
}

/// `[lo, hi]` padded by 5%, never degenerate.
fn range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !lo.is_finite() {
        return None;
    }
    let span = hi - lo;
    let pad = if span > 0.0 {
        0.05 * span
    } else {
        0.5 * lo.abs().max(1.0)
    };
    Some((lo - pad, hi + pad))
}

fn tick(v: f64, scale: Scale) -> String {
    match scale {
        Scale::Linear => {
            let a = v.abs();
            if a != 0.0 && !(1e-3..1e4).contains(&a) {
                format!("{v:.1e}")
            } else {
                format!("{}", (v * 1e6).round() / 1e6)
            }
        }
        Scale::Log => format!("{:.0e}", 10f64.powf(v)),
    }
}

const WIDTH: u32 = 800;
const HEIGHT: u32 = 600;

/// Draw `figure` to `path` (`.svg`).
pub fn draw(path: &Path, figure: &Figure) -> Result<(), PlotError> {
    let err = |message: String| PlotError {
        path: path.to_path_buf(),
        message,
    };
    match path.extension().and_then(|e| e.to_str()) {
        Some("svg") => {}
        Some("png") => {
            return Err(err(
                "PNG output needs font files; use SVG (plot_format = \"svg\")".into()
            ));
        }
        other => {
            return Err(err(format!(
                "unknown plot format `{}`, expected .svg",
                other.unwrap_or("")
            )));
        }
    }
    let data: Vec<Vec<(f64, f64)>> = figure
        .series
        .iter()
        .map(|s| points(s, figure.x_scale, figure.y_scale))
        .collect();
    let all = || data.iter().flatten();
    let (mut x0, mut x1) = range(all().map(|p| p.0)).unwrap_or((0.0, 1.0));
    let (mut y0, mut y1) = range(all().map(|p| p.1)).unwrap_or((0.0, 1.0));
    if figure.equal_aspect {
        // Plot area is about (WIDTH − 110) × (HEIGHT − 110) pixels.
        let (pw, ph) = (f64::from(WIDTH - 110), f64::from(HEIGHT - 110));
        let per_px = ((x1 - x0) / pw).max((y1 - y0) / ph);
        let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        (x0, x1) = (cx - 0.5 * per_px * pw, cx + 0.5 * per_px * pw);
        (y0, y1) = (cy - 0.5 * per_px * ph, cy + 0.5 * per_px * ph);
    }
    let root = SVGBackend::new(path, (WIDTH, HEIGHT)).into_drawing_area();
    let e = |x: &dyn std::fmt::Display| err(x.to_string());
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(figure.title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(75)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|x| e(&x))?;
    let (xs, ys) = (figure.x_scale, figure.y_scale);
    chart
        .configure_mesh()
        .x_desc(figure.x_label)
        .y_desc(figure.y_label)
        .x_label_formatter(&|v| tick(*v, xs))
        .y_label_formatter(&|v| tick(*v, ys))
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(|x| e(&x))?;
    if data.iter().all(|d| d.is_empty()) {
        chart
            .draw_series(std::iter::once(Text::new(
                "no finite data to show on these axes",
                (0.5 * (x0 + x1), 0.5 * (y0 + y1)),
                ("sans-serif", 18),
            )))
            .map_err(|x| e(&x))?;
    }
    for (k, (s, pts)) in figure.series.iter().zip(&data).enumerate() {
        let color = Palette99::pick(k).to_rgba();
        let style = color.stroke_width(2);
        chart
            .draw_series(LineSeries::new(pts.iter().copied(), style))
            .map_err(|x| e(&x))?
            .label(s.label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
        if figure.markers {
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                .map_err(|x| e(&x))?;
        }
    }
    if figure.series.len() > 1 {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|x| e(&x))?;
    }
    root.present().map_err(|x| e(&x))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir() -> PathBuf {
        let d = std::env::temp_dir().join(format!("veselov-plot-{}", std::process::id()));
        std::fs::create_dir_all(&d).expect("temp dir");
        d
    }

    fn figure<'a>(series: Vec<Series<'a>>, xs: Scale, ys: Scale) -> Figure<'a> {
        Figure {
            title: "Title T",
            x_label: "x label",
            y_label: "y label",
            x_scale: xs,
            y_scale: ys,
            series,
            markers: true,
            equal_aspect: false,
        }
    }

    #[test]
    fn draws_linear_log_constant_and_large_plots() {
        let d = dir();
        let x: Vec<f64> = (0..50).map(|i| i as f64 * 0.1).collect();
        let y1: Vec<f64> = x.iter().map(|x| x.sin()).collect();
        let y2: Vec<f64> = x.iter().map(|x| x.cos()).collect();
        let p = d.join("lin.svg");
        draw(
            &p,
            &figure(
                vec![
                    Series {
                        label: "sin",
                        x: &x,
                        y: &y1,
                    },
                    Series {
                        label: "cos",
                        x: &x,
                        y: &y2,
                    },
                ],
                Scale::Linear,
                Scale::Linear,
            ),
        )
        .expect("drawn");
        let text = std::fs::read_to_string(&p).expect("svg");
        assert!(text.contains("Title T") && text.contains("x label") && text.contains("cos"));
        // Log axes with a zero and a NaN.
        let ylog = vec![1.0, 0.0, f64::NAN, 1e-8, 1e-12];
        let xlog = vec![1.0, 0.5, 0.25, 0.125, 0.0625];
        draw(
            &d.join("log.svg"),
            &figure(
                vec![Series {
                    label: "e",
                    x: &xlog,
                    y: &ylog,
                }],
                Scale::Log,
                Scale::Log,
            ),
        )
        .expect("drawn");
        // Nothing positive on a log axis: an empty frame with a note.
        let zeros = vec![0.0; 5];
        draw(
            &d.join("empty.svg"),
            &figure(
                vec![Series {
                    label: "z",
                    x: &xlog,
                    y: &zeros,
                }],
                Scale::Log,
                Scale::Log,
            ),
        )
        .expect("drawn");
        // Constant series.
        let c = vec![2.0; 50];
        draw(
            &d.join("const.svg"),
            &figure(
                vec![Series {
                    label: "c",
                    x: &x,
                    y: &c,
                }],
                Scale::Linear,
                Scale::Linear,
            ),
        )
        .expect("drawn");
        // Equal-aspect orbit.
        let (ox, oy): (Vec<f64>, Vec<f64>) = (0..200)
            .map(|i| {
                let t = i as f64 * 0.0315;
                (2.0 * t.cos(), t.sin())
            })
            .unzip();
        let mut f = figure(
            vec![Series {
                label: "orbit",
                x: &ox,
                y: &oy,
            }],
            Scale::Linear,
            Scale::Linear,
        );
        f.equal_aspect = true;
        draw(&d.join("orbit.svg"), &f).expect("drawn");
        // 10⁶ points are decimated.
        let bx: Vec<f64> = (0..1_000_000).map(|i| i as f64).collect();
        let by: Vec<f64> = bx.iter().map(|x| (x * 1e-3).sin()).collect();
        let mut f = figure(
            vec![Series {
                label: "big",
                x: &bx,
                y: &by,
            }],
            Scale::Linear,
            Scale::Linear,
        );
        f.markers = false;
        let p = d.join("big.svg");
        draw(&p, &f).expect("drawn");
        assert!(std::fs::metadata(&p).expect("file").len() < 1_000_000);
        assert_eq!(
            points(
                &Series {
                    label: "",
                    x: &bx,
                    y: &by
                },
                Scale::Linear,
                Scale::Linear
            )
            .len(),
            MAX_POINTS
        );
        std::fs::remove_dir_all(&d).ok();
    }

    #[test]
    fn unknown_extension_is_an_error() {
        let x = [1.0];
        let e = draw(
            Path::new("plot.jpg"),
            &figure(
                vec![Series {
                    label: "a",
                    x: &x,
                    y: &x,
                }],
                Scale::Linear,
                Scale::Linear,
            ),
        )
        .expect_err("jpg");
        assert!(e.to_string().contains("jpg"));
    }
}
