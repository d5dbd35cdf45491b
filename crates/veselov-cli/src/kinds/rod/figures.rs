//! The figures of a rod run, drawn from its output files (so `veselov plot`
//! can redraw them): the centreline, the momenta and the energy.

use std::path::Path;

use crate::error::CliError;
use crate::output::Table;

/// Centreline snapshots (x–z and y–z), the centreline animation
/// (`centerline.gif`), momentum changes and energy, read back from the files.
pub fn draw_rod(dir: &Path, nodes: usize, rows: u64, format: &str) -> Result<(), CliError> {
    crate::centerline::draw_centerline_figures(
        dir,
        ("centerline", 3),
        (nodes, rows),
        |r, p| [r[3 * p], r[3 * p + 1], r[3 * p + 2]],
        ("t", format),
    )?;
    let momentum = Table::read_csv(&dir.join("momentum.csv"))?;
    crate::figures::draw_changes(
        &dir.join(format!("momentum.{format}")),
        &momentum,
        "t",
        &["P_x", "P_y", "P_z", "L_x", "L_y", "L_z"],
        ("Momenta: change since the start", "P(t) − P(0), L(t) − L(0)"),
    )?;
    let energy = Table::read_csv(&dir.join("energy.csv"))?;
    if let (Some(t), Some(e)) = (energy.column("t"), energy.column("energy")) {
        crate::figures::draw_curves(
            &dir.join(format!("energy.{format}")),
            ("Energy (kinetic + elastic + potential)", "time t", "E"),
            &[("energy".to_string(), t, e)],
            false,
        )?;
    }
    Ok(())
}
