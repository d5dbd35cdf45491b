//! The figures of a CFK-lattice field run, drawn from its output files (so
//! `veselov plot` can redraw them): the energy error and heat maps of a few
//! snapshots.

use std::path::Path;

use crate::error::CliError;
use crate::output::Table;
use crate::pipeline::readback::rows_for_plots;

/// Values per vertex of the field of `model`: 2 for the complex
/// Klein–Gordon field, else 1.
pub fn components(model: &str) -> usize {
    if model == "klein-gordon-complex" { 2 } else { 1 }
}

/// Energy error and heat maps (first component) of a few snapshots spread
/// over the run, read back from the files: `nodes` per axis with spacing
/// `dx`, `components` values per vertex.
pub fn draw(
    dir: &Path,
    (nodes, dx): ([usize; 2], f64),
    components: usize,
    snapshot_rows: u64,
    format: &str,
) -> Result<(), CliError> {
    let energy = Table::read_csv(&dir.join("energy.csv"))?;
    if let (Some(t), Some(e)) = (energy.column("t"), energy.column("energy")) {
        crate::figures::draw_energy_error(
            &dir.join(format!("energy_error.{format}")),
            "Discrete energy error",
            &t,
            &e,
        )?;
    }
    let [nx, ny] = nodes;
    let width: Vec<String> = (0..nx * ny * components).map(|i| i.to_string()).collect();
    let snaps = rows_for_plots(dir, "snapshots", &width, snapshot_rows, 4)?;
    let times = rows_for_plots(dir, "snapshot_times", &["t".to_string()], snapshot_rows, 4)?;
    for (k, (values, t)) in snaps.rows.iter().zip(&times.rows).enumerate() {
        // Rows along y, columns along x.
        let grid: Vec<Vec<f64>> = (0..ny)
            .map(|gy| (0..nx).map(|gx| values[(gx * ny + gy) * components]).collect())
            .collect();
        let title = format!("{} at t = {:.3}", if components == 2 { "Re φ" } else { "φ" }, t[0]);
        let map = crate::heatmap::Heatmap {
            title: &title,
            x_label: "x",
            y_label: "y",
            x_range: (0.0, nx as f64 * dx),
            y_range: (0.0, ny as f64 * dx),
            values: &grid,
        };
        crate::heatmap::draw_heatmap(&dir.join(format!("field_{k}.png")), &map).map_err(crate::figures::plot_err)?;
    }
    Ok(())
}
