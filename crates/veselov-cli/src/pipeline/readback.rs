//! Reading a streamed table back for plots, with bounded memory: at most
//! [`MAX_PLOT_ROWS`] rows are kept (every k-th row and the last one), so a
//! run of any length is drawn from a fixed amount of data.

use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
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
            if row.len() != header.len() {
                return Err(io(
                    &csv,
                    format!("line {}: {} values for {} columns", i + 2, row.len(), header.len()),
                ));
            }
            keep(i as u64, row);
        }
        return Ok(table);
    }
    let npy = dir.join(format!("{stem}.npy"));
    let info = npy_info(&npy)?;
    let per_row: usize = info.shape.iter().skip(1).product();
    if per_row != header.len() || info.shape.is_empty() {
        return Err(io(
            &npy,
            format!(
                "its rows hold {per_row} values (shape {:?}), expected {}",
                info.shape,
                header.len()
            ),
        ));
    }
    if rows > info.rows() {
        return Err(io(&npy, format!("holds {} rows, expected {rows}", info.rows())));
    }
    let mut f = BufReader::new(std::fs::File::open(&npy).map_err(|e| io(&npy, e))?);
    f.seek(SeekFrom::Start(info.data_offset)).map_err(|e| io(&npy, e))?;
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

/// The header and the number of rows of the CSV file `path` (one pass
/// over it, keeping nothing but the count): what [`rows_for_plots`] needs
/// to read back a file whose length is not known otherwise.
pub fn csv_shape(path: &Path) -> Result<(Vec<String>, u64), CliError> {
    let f = std::fs::File::open(path).map_err(|e| io(path, e))?;
    let mut lines = BufReader::new(f).lines();
    let header = match lines.next() {
        Some(line) => line.map_err(|e| io(path, e))?,
        None => return Err(io(path, "empty file")),
    };
    let mut rows = 0u64;
    for line in lines {
        line.map_err(|e| io(path, e))?;
        rows += 1;
    }
    Ok((header.split(',').map(|s| s.trim().to_string()).collect(), rows))
}

/// What the header of a float64 NPY file says: its shape (rows first) and
/// where its data begin.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NpyInfo {
    /// The array's shape.
    pub shape: Vec<usize>,
    /// Bytes before the data.
    pub data_offset: u64,
}

impl NpyInfo {
    /// Rows of the array (its first dimension; 1 for a scalar).
    pub fn rows(&self) -> u64 {
        self.shape.first().map_or(1, |&r| r as u64)
    }
}

/// Largest NPY header read (runs write 64 to 128 bytes).
const MAX_NPY_HEADER: usize = 1 << 16;

/// Read and check the header of the NPY file `path`: a little-endian
/// float64 (`'<f8'`) array in C order, whose file holds every value its
/// shape counts (a file cut short, a Fortran-ordered array or another
/// dtype is an error naming the file, before anything is allocated from
/// the shape).
pub fn npy_info(path: &Path) -> Result<NpyInfo, CliError> {
    let bad = |m: &str| io(path, format!("not a float64 NPY file written by a run: {m}"));
    let mut f = BufReader::new(std::fs::File::open(path).map_err(|e| io(path, e))?);
    let mut pre = [0u8; 8];
    f.read_exact(&mut pre).map_err(|_| bad("too short for an NPY header"))?;
    if &pre[..6] != b"\x93NUMPY" {
        return Err(bad("no NPY magic"));
    }
    let header_len = match pre[6] {
        1 => {
            let mut n = [0u8; 2];
            f.read_exact(&mut n).map_err(|_| bad("its header is cut short"))?;
            u16::from_le_bytes(n) as usize
        }
        2 | 3 => {
            let mut n = [0u8; 4];
            f.read_exact(&mut n).map_err(|_| bad("its header is cut short"))?;
            usize::try_from(u32::from_le_bytes(n)).unwrap_or(usize::MAX)
        }
        v => return Err(bad(&format!("unknown NPY version {v}"))),
    };
    if header_len > MAX_NPY_HEADER {
        return Err(bad(&format!("a header of {header_len} bytes")));
    }
    let mut dict = vec![0u8; header_len];
    f.read_exact(&mut dict).map_err(|_| bad("its header is cut short"))?;
    let dict = String::from_utf8_lossy(&dict);
    let value = |key: &str| -> Option<&str> {
        let (_, rest) = dict.split_once(&format!("'{key}':"))?;
        Some(rest.trim_start())
    };
    let descr = value("descr").ok_or_else(|| bad("no dtype"))?;
    if !(descr.starts_with("'<f8'") || descr.starts_with("\"<f8\"")) {
        return Err(bad("its dtype is not '<f8' (little-endian float64)"));
    }
    let fortran = value("fortran_order").ok_or_else(|| bad("no fortran_order"))?;
    if fortran.starts_with("True") {
        return Err(io(
            path,
            "the array is stored in Fortran (column-major) order; runs write C order, in which it is read: \
             save it with numpy.ascontiguousarray or fortran_order=False",
        ));
    }
    if !fortran.starts_with("False") {
        return Err(bad("fortran_order is neither True nor False"));
    }
    let shape = value("shape")
        .and_then(|rest| rest.strip_prefix('('))
        .and_then(|rest| rest.split_once(')'))
        .ok_or_else(|| bad("no shape"))?
        .0;
    let shape = shape
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<usize>()
                .map_err(|_| bad("a shape entry is not a whole number"))
        })
        .collect::<Result<Vec<usize>, _>>()?;
    let data_offset = (pre.len() + if pre[6] == 1 { 2 } else { 4 } + header_len) as u64;
    let values = shape
        .iter()
        .try_fold(1u64, |n, &d| n.checked_mul(d as u64))
        .and_then(|n| n.checked_mul(8))
        .ok_or_else(|| bad(&format!("its shape {shape:?} counts more values than a file can hold")))?;
    let length = std::fs::metadata(path).map_err(|e| io(path, e))?.len();
    let held = length.saturating_sub(data_offset);
    if held < values {
        return Err(io(
            path,
            format!("cut short: its shape {shape:?} needs {values} bytes of data, the file holds {held}"),
        ));
    }
    Ok(NpyInfo { shape, data_offset })
}

/// The shape of the float64 NPY array `path` (rows first), read from its
/// header and checked as [`npy_info`] does.
pub fn npy_shape(path: &Path) -> Result<Vec<usize>, CliError> {
    Ok(npy_info(path)?.shape)
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

    #[test]
    fn a_long_csv_is_read_back_bounded() {
        let dir = crate::test_scratch::Scratch::new("csv-bounded");
        let path = dir.join("trajectory.csv");
        let rows: Vec<String> = (0..120_001).map(|k| format!("{k},{}", 2 * k)).collect();
        std::fs::write(&path, format!("t,x\n{}\n", rows.join("\n"))).expect("write");
        let (header, count) = csv_shape(&path).expect("shape");
        assert_eq!(
            (header.as_slice(), count),
            (["t", "x"].map(String::from).as_slice(), 120_001)
        );
        let table = table_for_plots(&dir, "trajectory", &header, count).expect("rows");
        assert!(table.rows.len() as u64 <= MAX_PLOT_ROWS + 1, "{}", table.rows.len());
        assert_eq!(table.rows.last(), Some(&vec![120_000.0, 240_000.0]));
        std::fs::write(&path, "t,x\n1,2\n3\n").expect("write");
        let e = table_for_plots(&dir, "trajectory", &header, 2).expect_err("a short row");
        assert!(e.to_string().contains("line 3"), "{e}");
    }

    /// A header that is not that of a C-ordered float64 array whose file
    /// holds its values is an error naming the file, whatever the shape
    /// claims (nothing is allocated from it).
    #[test]
    fn npy_headers_other_than_a_runs_are_refused() {
        let dir = crate::test_scratch::Scratch::new("npy-refused");
        let path = dir.join("snapshots.npy");
        let write = |header: Vec<u8>, values: usize| {
            let mut bytes = header;
            bytes.extend(std::iter::repeat_n(0u8, 8 * values));
            std::fs::write(&path, bytes).expect("write");
        };
        let good = crate::output::npy_header_shape(&[2, 3]);
        // The dict after the 10-byte preamble, edited (same length).
        let edit = |from: &str, to: &str| {
            let text = String::from_utf8_lossy(&good[10..]).replacen(from, to, 1);
            [&good[..10], text.as_bytes()].concat()
        };
        write(good.clone(), 6);
        assert_eq!(npy_info(&path).expect("a run's file").shape, [2, 3]);
        let cases = [
            (edit("'fortran_order': False", "'fortran_order': True "), 6, "Fortran"),
            (edit("'<f8'", "'>f8'"), 6, "dtype"),
            (edit("'<f8'", "'<f4'"), 6, "dtype"),
            (good.clone(), 5, "cut short"),
            (edit("(2, 3)", "(2, x)"), 6, "not a whole number"),
            (
                crate::output::npy_header_shape(&[1 << 32, 1 << 32]),
                6,
                "more values than",
            ),
            (
                crate::output::npy_header_shape(&[1_000_000_000, 1_000_000_000]),
                6,
                "cut short",
            ),
        ];
        for (header, values, expected) in cases {
            write(header, values);
            let e = npy_info(&path).expect_err(expected).to_string();
            assert!(e.contains("snapshots.npy") && e.contains(expected), "{e}");
        }
    }
}
