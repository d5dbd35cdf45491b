//! The centreline of the beam and rod kinds: its file `centerline.npy`
//! (`centerline_stream`, one layout for both kinds), what a held
//! structure did (`measure`: the tip, the deflection, the reaction), and
//! its figures, read back from a run's files: snapshots in the x–z and y–z
//! planes, labelled with their times, and the animation `centerline.gif`.

mod measure;

pub(crate) use measure::{Reaction, ShapeChange, single_support};

use std::path::Path;

use crate::error::CliError;
use crate::pipeline::readback::rows_for_plots;
use crate::pipeline::stream::{NpyStream, Position};

/// `dir/centerline.npy` for `nodes` nodes and about `rows` rows: rows ×
/// nodes × 3, the centreline r (m) of every node at the output times
/// (continuing from `resume` when a run resumes).
pub(crate) fn centerline_stream(
    dir: &Path,
    nodes: usize,
    rows: u64,
    resume: Option<Position>,
) -> Result<NpyStream, CliError> {
    NpyStream::create(&dir.join("centerline.npy"), &[nodes, 3], rows, resume)
}

/// Snapshots drawn in the centreline figures.
const SNAPSHOTS: u64 = 6;

/// The centreline figures of a run from `dir/<stem>.npy` (`rows` rows of
/// `nodes` points of `width` values, the point given by `point(row, node)`):
/// six snapshots in the x–z and y–z planes ([`draw_centerlines`]), labelled
/// with their times from the column `time` of `energy.csv`, and the
/// animation `centerline.gif`.
pub(crate) fn draw_centerline_figures(
    dir: &Path,
    (stem, width): (&str, usize),
    (nodes, rows): (usize, u64),
    point: impl Fn(&[f64], usize) -> [f64; 3] + Copy,
    (time, format): (&str, &str),
) -> Result<(), CliError> {
    let columns: Vec<String> = (0..nodes * width).map(|i| i.to_string()).collect();
    let snaps = rows_for_plots(dir, stem, &columns, rows, SNAPSHOTS)?;
    let points: Vec<Vec<[f64; 3]>> = snaps
        .rows
        .iter()
        .map(|r| (0..nodes).map(|p| point(r, p)).collect())
        .collect();
    // The times of the same rows (energy.csv has a row for each row of the
    // centreline); "snapshot k" where they cannot be read.
    let times = crate::output::Table::read_csv(&dir.join("energy.csv"))
        .and_then(|t| rows_for_plots(dir, "energy", &t.header, rows, SNAPSHOTS))
        .ok()
        .and_then(|t| t.column(time))
        .filter(|t| t.len() == points.len());
    let unit = if time == "t" { "s" } else { "m" };
    let labels: Vec<String> = match times {
        Some(times) => times.iter().map(|&t| format!("{time} = {} {unit}", short(t))).collect(),
        None => (0..points.len()).map(|k| format!("snapshot {k}")).collect(),
    };
    draw_centerlines(dir, &points, &labels, format)?;
    crate::animation::animate_run(dir, (stem, width), nodes, rows, point, time)
}

/// `x` in at most four significant digits, without trailing zeros (in
/// exponent form outside 10⁻³ … 10⁴).
fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    if (1e-3..1e4).contains(&x.abs()) {
        let digits = (3 - x.abs().log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.3e}")
    }
}

/// Below this ratio of its extents (the narrow axis against the wide one)
/// a centreline figure is not drawn to scale: the narrow axis is stretched
/// so that a deflection of 1 % of the length fills a visible part of it.
const TO_SCALE_RATIO: f64 = 0.2;

/// Width over height of the plotting area of a figure (800 × 600 pixels,
/// less the title, margins and label areas): for the stretch stated in an
/// axis label, to two significant digits.
const PLOT_AREA_ASPECT: f64 = 1.45;

/// How one plane of the centreline is drawn: to scale, or with the narrow
/// axis stretched (its label says by about how much), with a scale bar of
/// 1 % of the length where the deflection is smaller still.
#[derive(Debug, Clone, PartialEq)]
struct PlaneLayout {
    equal_aspect: bool,
    /// Labels of the horizontal and vertical axes.
    labels: [String; 2],
    /// A bar of 1 % of the length along the narrow axis (its two ends).
    scale_bar: Option<[[f64; 2]; 2]>,
}

/// The layout of the snapshots `curves` (horizontal and vertical
/// coordinates of each point) on axes named `names`, for a structure of
/// length `length`.
fn plane_layout(curves: &[Vec<[f64; 2]>], names: [&str; 2], length: f64) -> PlaneLayout {
    let extent = |a: usize| {
        let (lo, hi) = curves
            .iter()
            .flatten()
            .map(|p| p[a])
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
        (lo, hi)
    };
    let ranges = [extent(0), extent(1)];
    let span = |a: usize| (ranges[a].1 - ranges[a].0).max(0.0);
    let labels = names.map(|n| format!("{n} (m)"));
    let (narrow, wide) = if span(0) < span(1) { (0, 1) } else { (1, 0) };
    if !(span(wide) > 0.0 && span(wide).is_finite()) || span(narrow) >= TO_SCALE_RATIO * span(wide) {
        return PlaneLayout {
            equal_aspect: true,
            labels,
            scale_bar: None,
        };
    }
    // The narrow axis spans at least 1 % of the length: a bar of that size
    // where the deflection is smaller (round-off in a plane the structure
    // does not move in stays invisible).
    let bar = 0.01 * length;
    let scale_bar = (span(narrow) < bar && bar > 0.0).then(|| {
        let mid = 0.5 * (ranges[narrow].0 + ranges[narrow].1);
        let at = ranges[wide].0;
        let mut ends = [[0.0; 2]; 2];
        for (end, offset) in ends.iter_mut().zip([-0.5 * bar, 0.5 * bar]) {
            end[narrow] = mid + offset;
            end[wide] = at;
        }
        ends
    });
    let shown = span(narrow).max(if scale_bar.is_some() { bar } else { 0.0 });
    // Pixels per metre along the narrow axis over those along the wide one.
    let area = if narrow == 0 {
        PLOT_AREA_ASPECT
    } else {
        1.0 / PLOT_AREA_ASPECT
    };
    let stretch = area * span(wide) / shown;
    let mut labels = labels;
    labels[narrow] = format!(
        "{} (m), stretched about ×{} against {}",
        names[narrow],
        two_digits(stretch),
        names[wide]
    );
    PlaneLayout {
        equal_aspect: false,
        labels,
        scale_bar,
    }
}

/// `x` rounded to two significant digits, as an integer above 10.
fn two_digits(x: f64) -> String {
    if !(x.is_finite() && x > 0.0) {
        return format!("{x}");
    }
    let unit = 10f64.powi(x.log10().floor() as i32 - 1);
    let rounded = (x / unit).round() * unit;
    if rounded >= 10.0 {
        format!("{rounded:.0}")
    } else {
        format!("{rounded:.1}")
    }
}

/// Centreline snapshots (each a list of points, labelled `labels`) in the
/// x–z and y–z planes: `centerline_xz` and `centerline_yz`. A plane where
/// the centreline's shape is small against its length is drawn stretched
/// across it ([`plane_layout`]).
pub(crate) fn draw_centerlines(
    dir: &Path,
    snapshots: &[Vec<[f64; 3]>],
    labels: &[String],
    format: &str,
) -> Result<(), CliError> {
    let length = snapshots.first().map_or(0.0, |points| {
        points
            .windows(2)
            .map(|w| (0..3).map(|a| (w[1][a] - w[0][a]).powi(2)).sum::<f64>().sqrt())
            .filter(|d| d.is_finite())
            .sum()
    });
    for (name, a) in [("xz", 0), ("yz", 1)] {
        let planar: Vec<Vec<[f64; 2]>> = snapshots
            .iter()
            .map(|points| points.iter().map(|p| [p[a], p[2]]).collect())
            .collect();
        let axis = if a == 0 { "x" } else { "y" };
        let layout = plane_layout(&planar, [axis, "z"], length);
        let mut curves: Vec<(String, Vec<f64>, Vec<f64>)> = planar
            .iter()
            .zip(labels)
            .map(|(points, label)| {
                (
                    label.clone(),
                    points.iter().map(|p| p[0]).collect(),
                    points.iter().map(|p| p[1]).collect(),
                )
            })
            .collect();
        if let Some(bar) = layout.scale_bar {
            curves.push((
                "1 % of the length".to_string(),
                bar.iter().map(|p| p[0]).collect(),
                bar.iter().map(|p| p[1]).collect(),
            ));
        }
        crate::figures::draw_curves(
            &dir.join(format!("centerline_{name}.{format}")),
            ("Centreline snapshots", &layout.labels[0], &layout.labels[1]),
            &curves,
            layout.equal_aspect,
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cantilever along z bent by `tip` at its end, in the x–z plane.
    fn cantilever(tip: f64) -> Vec<[f64; 2]> {
        (0..=10)
            .map(|k| {
                let s = k as f64 / 10.0;
                [tip * s * s, s]
            })
            .collect()
    }

    #[test]
    fn a_small_deflection_is_drawn_stretched_and_said_so() {
        // 3 % of the length: the narrow axis has 1/0.03 times fewer metres
        // per pixel than it would to scale, times the plotting area's aspect.
        let l = plane_layout(&[cantilever(0.0), cantilever(0.03)], ["x", "z"], 1.0);
        assert!(!l.equal_aspect);
        let stretch = two_digits(PLOT_AREA_ASPECT / 0.03);
        assert_eq!(l.labels[0], format!("x (m), stretched about ×{stretch} against z"));
        assert_eq!(l.labels[1], "z (m)");
        assert!(l.scale_bar.is_none());
        // Round-off across the plane: a bar of 1 % of the length sets the scale.
        let l = plane_layout(&[cantilever(0.0), cantilever(1e-17)], ["y", "z"], 1.0);
        let bar = l.scale_bar.expect("a scale bar");
        assert!((bar[1][0] - bar[0][0] - 0.01).abs() < 1e-15 && bar[0][1] == 0.0);
        let stretch = two_digits(PLOT_AREA_ASPECT / 0.01);
        assert!(
            l.labels[0].ends_with(&format!("×{stretch} against z")),
            "{}",
            l.labels[0]
        );
        // A large deflection is drawn to scale.
        let l = plane_layout(&[cantilever(0.0), cantilever(0.4)], ["x", "z"], 1.0);
        assert!(l.equal_aspect && l.scale_bar.is_none() && l.labels[0] == "x (m)");
        // A structure lying across: the vertical axis is the narrow one.
        let across: Vec<[f64; 2]> = cantilever(0.02).iter().map(|p| [p[1], p[0]]).collect();
        let l = plane_layout(&[across], ["x", "z"], 1.0);
        assert!(l.labels[1].starts_with("z (m), stretched about ×") && l.labels[0] == "x (m)");
    }

    #[test]
    fn snapshot_times_are_short() {
        assert_eq!(short(0.0), "0");
        assert_eq!(short(1.5), "1.5");
        assert_eq!(short(0.333333), "0.3333");
        assert_eq!(short(20.0), "20");
        assert_eq!(short(1e-6), "1.000e-6");
        assert_eq!(two_digits(48.3), "48");
        assert_eq!(two_digits(7.26), "7.3");
    }
}
