//! The centreline figures of the beam and rod kinds, read back from a run's
//! files: snapshots in the x–z and y–z planes and the animation
//! `centerline.gif`.

use std::path::Path;

use crate::error::CliError;
use crate::pipeline::readback::rows_for_plots;

/// The centreline figures of a run from `dir/<stem>.npy` (`rows` rows of
/// `nodes` points of `width` values, the point given by `point(row, node)`):
/// six snapshots in the x–z and y–z planes ([`draw_centerlines`]) and the
/// animation `centerline.gif`, its frames timed by the column `time` of
/// `energy.csv`.
pub(crate) fn draw_centerline_figures(
    dir: &Path,
    (stem, width): (&str, usize),
    (nodes, rows): (usize, u64),
    point: impl Fn(&[f64], usize) -> [f64; 3] + Copy,
    (time, format): (&str, &str),
) -> Result<(), CliError> {
    let columns: Vec<String> = (0..nodes * width).map(|i| i.to_string()).collect();
    let snaps = rows_for_plots(dir, stem, &columns, rows, 6)?;
    let points: Vec<Vec<[f64; 3]>> = snaps
        .rows
        .iter()
        .map(|r| (0..nodes).map(|p| point(r, p)).collect())
        .collect();
    draw_centerlines(dir, &points, format)?;
    crate::animation::animate_run(dir, (stem, width), nodes, rows, point, time)
}

/// Centreline snapshots (each a list of points) in the x–z and y–z planes:
/// `centerline_xz` and `centerline_yz`.
pub(crate) fn draw_centerlines(dir: &Path, snapshots: &[Vec<[f64; 3]>], format: &str) -> Result<(), CliError> {
    for (name, a) in [("xz", 0), ("yz", 1)] {
        let curves: Vec<(String, Vec<f64>, Vec<f64>)> = snapshots
            .iter()
            .enumerate()
            .map(|(k, points)| {
                (
                    format!("snapshot {k}"),
                    points.iter().map(|p| p[a]).collect(),
                    points.iter().map(|p| p[2]).collect(),
                )
            })
            .collect();
        crate::figures::draw_curves(
            &dir.join(format!("centerline_{name}.{format}")),
            ("Centreline snapshots", if a == 0 { "x" } else { "y" }, "z"),
            &curves,
            true,
        )?;
    }
    Ok(())
}
