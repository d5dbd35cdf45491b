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
use crate::pipeline::readback::npy_shape;

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
    let summary = read_summary(dir)?;
    let text = |key: &str| summary.as_ref().and_then(|s| s.get(key)).and_then(Value::as_str);
    let has = |key: &str| summary.as_ref().is_some_and(|s| s.get(key).is_some());
    if has("order_claimed") {
        redraw_verify(dir, summary.as_ref().unwrap_or(&Value::Null), format)?;
    } else if dir.join("trajectory.csv").exists() {
        figures::draw_all(dir, &Table::read_csv(&dir.join("trajectory.csv"))?, format)?;
    } else if text("model") == Some("beam") {
        let shape = npy_shape(&dir.join("frames.npy"))?;
        let x = if text("evolution") == Some("space") { "s" } else { "t" };
        crate::kinds::beam::figures::draw_beam(dir, dimension(&shape, 1)?, rows(&shape), x, format)?;
    } else if text("model") == Some("cosserat-rod") {
        let shape = npy_shape(&dir.join("centerline.npy"))?;
        crate::kinds::rod::figures::draw_rod(dir, dimension(&shape, 1)?, rows(&shape), format)?;
    } else if text("lattice") == Some("cfk") {
        let s = summary.as_ref().unwrap_or(&Value::Null);
        let nodes = s.get("nodes").and_then(Value::as_array).map(|a| {
            a.iter()
                .filter_map(Value::as_u64)
                .map(|n| n as usize)
                .collect::<Vec<_>>()
        });
        let Some(&[nx, ny]) = nodes.as_deref() else {
            return Err(summary_key(dir, "nodes", "two node counts"));
        };
        let dx = number(dir, s, "dx")?;
        let shape = npy_shape(&dir.join("snapshots.npy"))?;
        let per_row = shape.iter().skip(1).product::<usize>();
        let components = (per_row / (nx * ny).max(1)).max(1);
        crate::kinds::cfk::figures::draw(dir, ([nx, ny], dx), components, rows(&shape), format)?;
    } else if has("scheme") {
        redraw_field(dir, summary.as_ref().unwrap_or(&Value::Null), format)?;
    } else {
        return Err(CliError::Setup(format!(
            "{}: nothing to plot (no trajectory.csv, and no summary.json naming a lattice, beam, rod or \
             verify study)",
            dir.display()
        )));
    }
    let after = figure_files(dir)?;
    Ok(after
        .into_iter()
        .filter(|(path, modified)| before.get(path) != Some(modified))
        .map(|(path, _)| path)
        .collect())
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

/// Rows of an array of `shape`.
fn rows(shape: &[usize]) -> u64 {
    shape.first().map_or(0, |&r| r as u64)
}

/// Entry `axis` of an array's shape.
fn dimension(shape: &[usize], axis: usize) -> Result<usize, CliError> {
    shape
        .get(axis)
        .copied()
        .ok_or_else(|| CliError::Setup(format!("an output array has shape {shape:?}, expected a row shape")))
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
    let (dts, errors) = (list("dt")?, list("errors")?);
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
    )
}

/// The figures of a 1+1 lattice-field run.
fn redraw_field(dir: &Path, summary: &Value, format: &str) -> Result<(), CliError> {
    let nodes = summary
        .get("nodes")
        .and_then(Value::as_u64)
        .filter(|&n| n > 0)
        .ok_or_else(|| summary_key(dir, "nodes", "a node count"))? as usize;
    let (dx, length) = (number(dir, summary, "dx")?, number(dir, summary, "length")?);
    let energy = Table::read_csv(&dir.join("energy.csv"))?;
    let shape = npy_shape(&dir.join("snapshots.npy"))?;
    let components = (shape.iter().skip(1).product::<usize>() / nodes).max(1);
    let model = summary.get("model").and_then(Value::as_str).unwrap_or_default();
    crate::kinds::lattice::figures::draw_field_files(
        dir,
        (model, components),
        (nodes, dx, length),
        (&energy, rows(&shape)),
        format,
    )
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
