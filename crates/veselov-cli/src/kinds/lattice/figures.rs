//! The figures of a lattice-field run, drawn from its output files (so
//! `veselov plot` can redraw them): energy error, final waveform and the
//! space–time heat map of the stored snapshots.

use std::path::Path;

use crate::error::CliError;
use crate::figures::{draw_energy_error, plot_err};
use crate::output::Table;
use crate::pipeline::readback::{MAX_PLOT_SNAPSHOTS, rows_for_plots};
use crate::plot::{Figure, Scale, Series, draw};

/// The figures of a 1+1 lattice run of `model` (`components` values per
/// node) on `nodes` nodes `dx` apart over `length`, from its `energy` table
/// and its `snapshot_rows` stored snapshots (first component; a circle-valued
/// sine-Gordon field as sin²(φ/2), a complex one as Re φ).
pub fn draw_field_files(
    dir: &std::path::Path,
    (model, components): (&str, usize),
    (nodes, dx, length): (usize, f64, f64),
    (energy, snapshot_rows): (&Table, u64),
    format: &str,
) -> Result<(), CliError> {
    let width: Vec<String> = (0..nodes * components).map(|i| i.to_string()).collect();
    let snaps = rows_for_plots(dir, "snapshots", &width, snapshot_rows, MAX_PLOT_SNAPSHOTS)?;
    let times = rows_for_plots(
        dir,
        "snapshot_times",
        &["t".to_string()],
        snapshot_rows,
        MAX_PLOT_SNAPSHOTS,
    )?;
    let first_component: Vec<Vec<f64>> = snaps
        .rows
        .iter()
        .map(|row| row.iter().step_by(components).copied().collect())
        .collect();
    let times: Vec<f64> = times.rows.iter().map(|r| r[0]).collect();
    let view = match (model, components) {
        ("sine-gordon", _) => FieldView::Circle,
        (_, 1) => FieldView::Real,
        _ => FieldView::RealPart,
    };
    draw_field(dir, energy, &first_component, &times, (dx, length), view, format)
}

/// How a field's values are shown in the space–time heat map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldView {
    /// A real field, as it is.
    Real,
    /// An S¹-valued field, as sin²(φ/2).
    Circle,
    /// The first component (Re φ) of a complex field.
    RealPart,
}

/// The figures of a lattice-field run with node spacing `dx` over a domain
/// of `length`: energy error against time, the final waveform (in `format`)
/// and the space–time heat map of the stored snapshots
/// (always PNG; sin²(φ/2) for a circle-valued field).
pub fn draw_field(
    dir: &Path,
    energy: &Table,
    snapshots: &[Vec<f64>],
    times: &[f64],
    (dx, length): (f64, f64),
    view: FieldView,
    format: &str,
) -> Result<(), CliError> {
    let file = |name: &str| dir.join(format!("{name}.{format}"));
    if let (Some(t), Some(e)) = (energy.column("t"), energy.column("energy")) {
        draw_energy_error(&file("energy_error"), "Discrete energy error", &t, &e)?;
    }
    if let Some(last) = snapshots.last() {
        let n = last.len();
        let x: Vec<f64> = (0..n).map(|i| i as f64 * dx).collect();
        let title = format!("Waveform at t = {}", times.last().copied().unwrap_or(0.0));
        let (y_label, label) = match view {
            FieldView::RealPart => ("Re φ", "Re φ(x)"),
            FieldView::Real | FieldView::Circle => ("φ", "φ(x)"),
        };
        let fig = Figure {
            title: &title,
            x_label: "x",
            y_label,
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: vec![Series { label, x: &x, y: last }],
            markers: false,
            equal_aspect: false,
        };
        draw(&file("final_waveform"), &fig).map_err(plot_err)?;
    }
    if snapshots.len() >= 2 {
        // An S¹-valued field is shown as sin²(φ/2): 0 in every vacuum 2πn,
        // 1 at the centre of a kink, independent of the winding.
        let shown: Vec<Vec<f64>> = if view == FieldView::Circle {
            snapshots
                .iter()
                .map(|row| row.iter().map(|v| (0.5 * v).sin().powi(2)).collect())
                .collect()
        } else {
            snapshots.to_vec()
        };
        let map = crate::heatmap::Heatmap {
            title: match view {
                FieldView::Circle => "Space–time, sin²(φ/2)",
                FieldView::Real => "Space–time, φ",
                FieldView::RealPart => "Space–time, Re φ",
            },
            x_label: "x",
            y_label: "t",
            x_range: (0.0, length),
            y_range: (times[0], times[times.len() - 1]),
            values: &shown,
        };
        // A raster image suits a dense grid; SVG would hold one rectangle per cell.
        crate::heatmap::draw_heatmap(&dir.join("spacetime.png"), &map).map_err(plot_err)?;
    }
    Ok(())
}
