//! The figures of a beam run, drawn from its output files (so `veselov
//! plot` can redraw them): the centreline, the momentum map and the energy.

use std::path::Path;

use crate::error::CliError;
use crate::output::Table;

/// Centreline snapshots (positions of the frames), the centreline animation
/// (`centerline.gif`), momentum-map changes and energy, read back from the
/// files.
pub fn draw_beam(dir: &Path, cross: usize, rows: u64, x: &str, format: &str) -> Result<(), CliError> {
    // Time evolution writes the centreline itself (runs before it did: the
    // positions in frames.npy); space evolution's levels are columns.
    if x == "t" && dir.join("centerline.npy").exists() {
        crate::centerline::draw_centerline_figures(
            dir,
            ("centerline", 3),
            (cross, rows),
            |r, c| [r[3 * c], r[3 * c + 1], r[3 * c + 2]],
            (x, format),
        )?;
    } else {
        crate::centerline::draw_centerline_figures(
            dir,
            ("frames", 12),
            (cross, rows),
            |r, c| [r[12 * c + 9], r[12 * c + 10], r[12 * c + 11]],
            (x, format),
        )?;
    }
    let momentum = Table::read_csv(&dir.join("momentum.csv"))?;
    crate::figures::draw_changes(
        &dir.join(format!("momentum.{format}")),
        &momentum,
        x,
        &["J_wx", "J_wy", "J_wz", "J_vx", "J_vy", "J_vz"],
        ("Evolution momentum map: change since the start", "J − J(first row)"),
    )?;
    let energy = Table::read_csv(&dir.join("energy.csv"))?;
    if let (Some(t), Some(e)) = (energy.column(x), energy.column("energy")) {
        crate::figures::draw_curves(
            &dir.join(format!("energy.{format}")),
            ("Energy", x, "E"),
            &[("energy".to_string(), t, e)],
            false,
        )?;
    }
    Ok(())
}
