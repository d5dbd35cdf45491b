//! Drawing a figure to an SVG or PNG file, with the embedded font.

use std::path::Path;
use std::sync::OnceLock;

use plotters::prelude::*;

use super::render::render;
use super::{FONT, Figure, HEIGHT, PlotError, PlotFormat, WIDTH};

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::data::{axis_range, equalise, extent, prepare, to_axis};
    use crate::plot::ticks::ticks;
    use crate::plot::{MAX_POINTS, Scale, Series};
    use crate::test_scratch::Scratch;

    /// A fresh directory for this test's files.
    fn out_dir(test: &str) -> Scratch {
        Scratch::new(&format!("plot-{test}"))
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
    }
}
