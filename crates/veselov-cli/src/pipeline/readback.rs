//! Reading a streamed table back for plots, with bounded memory: at most
//! [`MAX_PLOT_ROWS`] rows are kept (every k-th row and the last one), so a
//! run of any length is drawn from a fixed amount of data.

use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use crate::error::CliError;
use crate::output::Table;

/// Rows kept for plotting.
pub const MAX_PLOT_ROWS: u64 = 50_000;

fn io(path: &Path, e: impl ToString) -> CliError {
    CliError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Snapshot rows (whole lattice levels) kept for plotting.
pub const MAX_PLOT_SNAPSHOTS: u64 = 2_000;

/// The stride that keeps at most `max` of `rows` rows.
fn stride(rows: u64, max: u64) -> u64 {
    rows.div_ceil(max).max(1)
}

/// Read `dir/<stem>.csv` (or `.npy` when that is the only format written),
/// `rows` rows of `header`, keeping every k-th row and the last.
pub fn table_for_plots(dir: &Path, stem: &str, header: &[String], rows: u64) -> Result<Table, CliError> {
    rows_for_plots(dir, stem, header, rows, MAX_PLOT_ROWS)
}

/// As [`table_for_plots`], keeping at most `max` rows.
pub fn rows_for_plots(dir: &Path, stem: &str, header: &[String], rows: u64, max: u64) -> Result<Table, CliError> {
    let k = stride(rows, max);
    let mut table = Table {
        header: header.to_vec(),
        rows: Vec::new(),
    };
    let mut keep = |i: u64, row: Vec<f64>| {
        if i.is_multiple_of(k) || i + 1 == rows {
            table.rows.push(row);
        }
    };
    let csv = dir.join(format!("{stem}.csv"));
    if csv.exists() {
        let f = std::fs::File::open(&csv).map_err(|e| io(&csv, e))?;
        for (i, line) in BufReader::new(f).lines().skip(1).enumerate() {
            let line = line.map_err(|e| io(&csv, e))?;
            let row = line
                .split(',')
                .map(|s| s.parse::<f64>())
                .collect::<Result<Vec<f64>, _>>()
                .map_err(|e| io(&csv, format!("line {}: {e}", i + 2)))?;
            keep(i as u64, row);
        }
        return Ok(table);
    }
    let npy = dir.join(format!("{stem}.npy"));
    let mut f = BufReader::new(std::fs::File::open(&npy).map_err(|e| io(&npy, e))?);
    let mut pre = [0u8; 10];
    f.read_exact(&mut pre).map_err(|e| io(&npy, e))?;
    let mut dict = vec![0u8; u16::from_le_bytes([pre[8], pre[9]]) as usize];
    f.read_exact(&mut dict).map_err(|e| io(&npy, e))?;
    let mut buf = vec![0u8; 8 * header.len()];
    for i in 0..rows {
        f.read_exact(&mut buf).map_err(|e| io(&npy, e))?;
        let row = buf
            .chunks_exact(8)
            .map(|b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
            .collect();
        keep(i, row);
    }
    Ok(table)
}

/// The shape of the float64 NPY array `path` (rows first), read from its
/// header.
pub fn npy_shape(path: &Path) -> Result<Vec<usize>, CliError> {
    let bad = |m: &str| io(path, format!("not a float64 NPY file written by a run: {m}"));
    let mut f = BufReader::new(std::fs::File::open(path).map_err(|e| io(path, e))?);
    let mut pre = [0u8; 10];
    f.read_exact(&mut pre).map_err(|e| io(path, e))?;
    if &pre[..6] != b"\x93NUMPY" {
        return Err(bad("no NPY magic"));
    }
    let mut dict = vec![0u8; u16::from_le_bytes([pre[8], pre[9]]) as usize];
    f.read_exact(&mut dict).map_err(|e| io(path, e))?;
    let dict = String::from_utf8_lossy(&dict);
    if !dict.contains("'<f8'") {
        return Err(bad("its dtype is not '<f8'"));
    }
    let shape = dict
        .split_once("'shape': (")
        .and_then(|(_, rest)| rest.split_once(')'))
        .ok_or_else(|| bad("no shape"))?
        .0;
    shape
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<usize>()
                .map_err(|_| bad("a shape entry is not a whole number"))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn npy_shape_reads_back_what_the_header_says() {
        let dir = crate::test_scratch::Scratch::new("npy-shape");
        let path = dir.join("a.npy");
        for shape in [vec![7usize], vec![3, 4], vec![5, 6, 12]] {
            let mut bytes = crate::output::npy_header_shape(&shape);
            bytes.extend(std::iter::repeat_n(0u8, 8 * shape.iter().product::<usize>()));
            std::fs::write(&path, bytes).expect("write");
            assert_eq!(npy_shape(&path).expect("shape"), shape);
        }
        std::fs::write(&path, b"not an npy file at all").expect("write");
        assert!(npy_shape(&path).is_err());
    }
}
