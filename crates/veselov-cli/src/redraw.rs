//! `veselov plot DIR`: redraw the figures of any run, or of a `verify`
//! study, from the files in its output directory alone.
//!
//! The kind of output is recognised from what the directory holds:
//!
//! | directory holds | kind | figures |
//! |---|---|---|
//! | `summary.json` with `order_claimed` | a `verify` study | `convergence` |
//! | `trajectory.csv` | mechanics or rigid body | energy, momenta, phase, orbit, body momentum |
//! | `summary.json` with `model = "beam"` | beam | centreline, momentum map, energy |
//! | `summary.json` with `model = "cosserat-rod"` | rod | centreline, momenta, energy |
//! | `summary.json` with `lattice = "cfk"` | field on a CFK lattice | energy error, `field_<k>.png` |
//! | `summary.json` with `scheme` | 1+1 lattice field | energy error, final waveform, `spacetime.png` |
//!
//! Every figure a run draws is drawn again, in the format asked for (heat
//! maps always as PNG), and the files written are listed.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

use serde_json::Value;

use crate::error::CliError;
use crate::figures;
use crate::output::Table;
use crate::pipeline::manifest::{self, Snapshot};
use crate::pipeline::readback::{csv_shape, npy_info, table_for_plots};

/// Redraw the figures of the run or study in `dir` as `format` (`svg` or
/// `png`); returns the files written, sorted.
pub fn redraw(dir: &Path, format: &str) -> Result<Vec<PathBuf>, CliError> {
    if let Some(problem) = crate::scenario::plot_format_problem(format) {
        return Err(CliError::Setup(format!("--format: {problem}")));
    }
    if !dir.is_dir() {
        return Err(CliError::Setup(format!(
            "{}: not a directory (expected the output directory of a run)",
            dir.display()
        )));
    }
    let before = figure_files(dir)?;
    let files = Snapshot::take(dir);
    let drawn = draw_figures(dir, format);
    // The figures join the run's record of its files, if it keeps one (a
    // directory of an earlier version keeps none, and is cleaned by name).
    if matches!(manifest::recorded(dir), Ok(Some(_))) {
        manifest::record(dir, &files)?;
    }
    drawn?;
    let after = figure_files(dir)?;
    Ok(after
        .into_iter()
        .filter(|(path, modified)| before.get(path) != Some(modified))
        .map(|(path, _)| path)
        .collect())
}

/// Draw the figures of the run or study in `dir`, recognised by its files.
fn draw_figures(dir: &Path, format: &str) -> Result<(), CliError> {
    let summary = read_summary(dir)?;
    let text = |key: &str| summary.as_ref().and_then(|s| s.get(key)).and_then(Value::as_str);
    let has = |key: &str| summary.as_ref().is_some_and(|s| s.get(key).is_some());
    if has("order_claimed") {
        redraw_verify(dir, summary.as_ref().unwrap_or(&Value::Null), format)?;
    } else if dir.join("trajectory.csv").exists() {
        figures::draw_all(dir, &bounded(dir, "trajectory")?, format)?;
    } else if text("model") == Some("beam") {
        let (cross, rows) = centreline_rows(dir, "frames.npy", 12)?;
        let x = if text("evolution") == Some("space") { "s" } else { "t" };
        crate::kinds::beam::figures::draw_beam(dir, cross, rows, x, format)?;
    } else if text("model") == Some("cosserat-rod") {
        let (nodes, rows) = centreline_rows(dir, "centerline.npy", 3)?;
        crate::kinds::rod::figures::draw_rod(dir, nodes, rows, format)?;
    } else if text("lattice") == Some("cfk") {
        let s = summary.as_ref().unwrap_or(&Value::Null);
        let nodes = s.get("nodes").and_then(Value::as_array).map(|a| {
            a.iter()
                .map(|n| n.as_u64().and_then(|n| usize::try_from(n).ok()).filter(|&n| n > 0))
                .collect::<Option<Vec<usize>>>()
        });
        let Some(Some(&[nx, ny])) = nodes.as_ref().map(Option::as_deref) else {
            return Err(summary_key(dir, "nodes", "two node counts"));
        };
        let dx = number(dir, s, "dx")?;
        extent(dir, "dx", dx, nx.max(ny))?;
        let (components, rows) = snapshot_rows(dir, &[nx, ny], "nodes")?;
        crate::kinds::cfk::figures::draw(dir, ([nx, ny], dx), components, rows, format)?;
    } else if has("scheme") {
        redraw_field(dir, summary.as_ref().unwrap_or(&Value::Null), format)?;
    } else {
        return Err(CliError::Setup(format!(
            "{}: nothing to plot (no trajectory.csv, and no summary.json naming a lattice, beam, rod or \
             verify study)",
            dir.display()
        )));
    }
    Ok(())
}

/// `dir/summary.json`, if there is one.
fn read_summary(dir: &Path) -> Result<Option<Value>, CliError> {
    let path = dir.join("summary.json");
    if !path.exists() {
        return Ok(None);
    }
    let text = std::fs::read_to_string(&path).map_err(|e| CliError::Io {
        path: path.clone(),
        message: e.to_string(),
    })?;
    serde_json::from_str(&text).map(Some).map_err(|e| CliError::Io {
        path,
        message: e.to_string(),
    })
}

fn summary_key(dir: &Path, key: &str, expected: &str) -> CliError {
    CliError::Io {
        path: dir.join("summary.json"),
        message: format!("`{key}`: expected {expected}"),
    }
}

fn number(dir: &Path, summary: &Value, key: &str) -> Result<f64, CliError> {
    summary
        .get(key)
        .and_then(Value::as_f64)
        .filter(|v| v.is_finite() && *v > 0.0)
        .ok_or_else(|| summary_key(dir, key, "a positive number"))
}

/// The convergence plot of a `verify` study, from its summary.
fn redraw_verify(dir: &Path, summary: &Value, format: &str) -> Result<(), CliError> {
    let list = |key: &str| -> Result<Vec<f64>, CliError> {
        summary
            .get(key)
            .and_then(Value::as_array)
            .map(|a| a.iter().map(|v| v.as_f64().unwrap_or(f64::NAN)).collect())
            .ok_or_else(|| summary_key(dir, key, "a list of numbers"))
    };
    // The step of the study: `dt`, or `dx` for a refinement study.
    let step = summary.get("step").and_then(Value::as_str).unwrap_or("dt");
    let (dts, errors) = (list(step)?, list("errors")?);
    let order = summary
        .get("order_claimed")
        .and_then(Value::as_u64)
        .ok_or_else(|| summary_key(dir, "order_claimed", "a whole number"))?;
    let fitted = summary.get("order_fitted").and_then(Value::as_f64);
    figures::draw_convergence(
        &dir.join(format!("convergence.{format}")),
        &dts,
        &errors,
        order as usize,
        fitted,
        (
            summary
                .get("step_label")
                .and_then(Value::as_str)
                .unwrap_or(crate::verify::TIME_STEP.label),
            summary
                .get("error_label")
                .and_then(Value::as_str)
                .unwrap_or(crate::verify::STATE_ERROR),
        ),
    )
}

/// The figures of a 1+1 lattice-field run.
fn redraw_field(dir: &Path, summary: &Value, format: &str) -> Result<(), CliError> {
    let nodes = summary
        .get("nodes")
        .and_then(Value::as_u64)
        .and_then(|n| usize::try_from(n).ok())
        .filter(|&n| n > 0)
        .ok_or_else(|| summary_key(dir, "nodes", "a node count"))?;
    let (dx, length) = (number(dir, summary, "dx")?, number(dir, summary, "length")?);
    extent(dir, "dx", dx, nodes)?;
    let energy = bounded(dir, "energy")?;
    let (components, rows) = snapshot_rows(dir, &[nodes], "nodes")?;
    let model = summary.get("model").and_then(Value::as_str).unwrap_or_default();
    crate::kinds::lattice::figures::draw_field_files(
        dir,
        (model, components),
        (nodes, dx, length),
        (&energy, rows),
        format,
    )
}

/// `dir/<stem>.csv` read back as a run reads it for its plots: at most
/// [`MAX_PLOT_ROWS`](crate::pipeline::readback::MAX_PLOT_ROWS) rows (every
/// k-th and the last), so that a long run's file is drawn from a bounded
/// amount of memory, and the figures equal the run's own.
fn bounded(dir: &Path, stem: &str) -> Result<Table, CliError> {
    let (header, rows) = csv_shape(&dir.join(format!("{stem}.csv")))?;
    table_for_plots(dir, stem, &header, rows)
}

/// Refuse a spacing `dx` (the summary's `key`) over `nodes` nodes whose
/// extent is not a finite number.
fn extent(dir: &Path, key: &str, dx: f64, nodes: usize) -> Result<(), CliError> {
    if (dx * nodes as f64).is_finite() {
        Ok(())
    } else {
        Err(summary_key(dir, key, "a spacing whose lattice has a finite extent"))
    }
}

/// The values per node (1, or 2 for a complex field) and the rows of
/// `dir/snapshots.npy`, checked against the lattice's `nodes` per axis
/// (the summary's `key`): its shape must be `(rows, nodes…)` or `(rows,
/// nodes…, 2)`; and `snapshot_times.csv` must hold a time for each row.
fn snapshot_rows(dir: &Path, nodes: &[usize], key: &str) -> Result<(usize, u64), CliError> {
    let path = dir.join("snapshots.npy");
    let shape = npy_info(&path)?.shape;
    let lattice = shape.get(1..=nodes.len());
    let components = match shape.get(nodes.len() + 1..) {
        Some([]) => Some(1),
        Some([2]) => Some(2),
        _ => None,
    };
    let (Some(lattice), Some(components)) = (lattice, components) else {
        return Err(CliError::Io {
            path,
            message: format!(
                "its shape {shape:?} is not that of snapshots of the lattice in summary.json (`{key}` = \
                 {nodes:?}): expected (rows, {}) or (rows, {}, 2)",
                join(nodes),
                join(nodes)
            ),
        });
    };
    if lattice != nodes {
        return Err(CliError::Io {
            path,
            message: format!(
                "its shape {shape:?} holds a lattice of {lattice:?} nodes, but summary.json says `{key}` = \
                 {nodes:?}"
            ),
        });
    }
    let rows = shape.first().copied().unwrap_or(0) as u64;
    let times_path = dir.join("snapshot_times.csv");
    let times = Table::read_csv(&times_path)?;
    if times.rows.len() as u64 != rows {
        return Err(CliError::Io {
            path: times_path,
            message: format!(
                "holds {} times, but snapshots.npy holds {rows} snapshots",
                times.rows.len()
            ),
        });
    }
    if let Some(k) = times
        .rows
        .iter()
        .position(|r| !r.first().is_some_and(|t| t.is_finite()))
    {
        return Err(CliError::Io {
            path: times_path,
            message: format!("line {}: not a finite time", k + 2),
        });
    }
    Ok((components, rows))
}

fn join(nodes: &[usize]) -> String {
    nodes.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")
}

/// The nodes and rows of a centreline file `dir/<name>` of shape `(rows,
/// nodes, width)`.
fn centreline_rows(dir: &Path, name: &str, width: usize) -> Result<(usize, u64), CliError> {
    let path = dir.join(name);
    let shape = npy_info(&path)?.shape;
    match shape.as_slice() {
        &[rows, nodes, w] if w == width && nodes > 0 => Ok((nodes, rows as u64)),
        _ => Err(CliError::Io {
            path,
            message: format!("its shape {shape:?} is not (rows, nodes, {width})"),
        }),
    }
}

/// The figure files (`.svg`, `.png`, `.gif`) in `dir` with their modification times.
fn figure_files(dir: &Path) -> Result<BTreeMap<PathBuf, Option<SystemTime>>, CliError> {
    let entries = std::fs::read_dir(dir).map_err(|e| CliError::Io {
        path: dir.to_path_buf(),
        message: e.to_string(),
    })?;
    Ok(entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("svg" | "png" | "gif")))
        .map(|p| {
            let modified = std::fs::metadata(&p).and_then(|m| m.modified()).ok();
            (p, modified)
        })
        .collect())
}
