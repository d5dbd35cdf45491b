//! Streaming writers: rows go to disk as they are computed, so memory does
//! not grow with the length of a run.
//!
//! * CSV: one line per row, `f64` `Display` (the shortest string that round-trips).
//! * NPY (format 1.0, `<f8`, C order): the header is written first with room
//!   for the planned row count and completed with the true count at close, so
//!   a file is valid up to its last row once closed (and after an
//!   interruption, which closes it too).
//!
//! Both report their byte length and row count for checkpoints, and reopen
//! a file truncated to such a position to continue it.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use crate::error::CliError;
use crate::output::npy_header_shape;

fn io(path: &Path) -> impl Fn(std::io::Error) -> CliError + '_ {
    move |e| CliError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Where a streamed file stood at a checkpoint: its length and rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Position {
    /// Bytes written.
    pub bytes: u64,
    /// Rows written.
    pub rows: u64,
}

impl Position {
    /// Append this position to checkpoint words (its two counts, exactly).
    pub fn save(&self, out: &mut Vec<f64>) {
        out.extend([self.bytes, self.rows].map(f64::from_bits));
    }

    /// Read `K` positions written by [`Position::save`].
    ///
    /// # Errors
    /// If the words run out.
    pub fn read_all<const K: usize>(w: &mut veselov::run::Words<'_>) -> veselov::Result<[Position; K]> {
        let mut p = [Position::default(); K];
        for q in &mut p {
            q.bytes = w.one()?.to_bits();
            q.rows = w.one()?.to_bits();
        }
        Ok(p)
    }
}

/// Open `path` for writing: created fresh, or (resuming) truncated to `at`
/// and positioned at its end.
fn open(path: &Path, at: Option<Position>) -> Result<(BufWriter<File>, Position), CliError> {
    match at {
        None => Ok((
            BufWriter::new(File::create(path).map_err(io(path))?),
            Position::default(),
        )),
        Some(p) => {
            let mut f = OpenOptions::new().write(true).open(path).map_err(io(path))?;
            let len = f.metadata().map_err(io(path))?.len();
            if len < p.bytes {
                return Err(CliError::Io {
                    path: path.to_path_buf(),
                    message: format!("shorter ({len} bytes) than at the checkpoint ({} bytes)", p.bytes),
                });
            }
            f.set_len(p.bytes).map_err(io(path))?;
            f.seek(SeekFrom::End(0)).map_err(io(path))?;
            Ok((BufWriter::new(f), p))
        }
    }
}

/// A CSV file written row by row.
pub struct CsvStream {
    path: PathBuf,
    w: BufWriter<File>,
    line: String,
    at: Position,
}

impl CsvStream {
    /// Create `path` with `header`, or continue it from `resume`.
    pub fn create(path: &Path, header: &[String], resume: Option<Position>) -> Result<Self, CliError> {
        let (mut w, mut at) = open(path, resume)?;
        if resume.is_none() {
            let line = header.join(",") + "\n";
            w.write_all(line.as_bytes()).map_err(io(path))?;
            at.bytes += line.len() as u64;
        }
        Ok(Self {
            path: path.to_path_buf(),
            w,
            line: String::new(),
            at,
        })
    }

    /// Append one row.
    pub fn row(&mut self, row: &[f64]) -> Result<(), CliError> {
        self.line.clear();
        for (i, x) in row.iter().enumerate() {
            if i > 0 {
                self.line.push(',');
            }
            crate::output::push_number(&mut self.line, *x);
        }
        self.line.push('\n');
        self.w.write_all(self.line.as_bytes()).map_err(io(&self.path))?;
        self.at.bytes += self.line.len() as u64;
        self.at.rows += 1;
        Ok(())
    }

    /// Flush and report the position.
    pub fn position(&mut self) -> Result<Position, CliError> {
        self.w.flush().map_err(io(&self.path))?;
        Ok(self.at)
    }
}

/// A float64 NPY array of shape `(rows, tail…)` written row by row.
pub struct NpyStream {
    path: PathBuf,
    w: BufWriter<File>,
    tail: Vec<usize>,
    header_len: usize,
    at: Position,
}

impl NpyStream {
    /// Create `path` for rows of shape `tail` (room in the header for
    /// `planned_rows`), or continue it from `resume`.
    pub fn create(path: &Path, tail: &[usize], planned_rows: u64, resume: Option<Position>) -> Result<Self, CliError> {
        let mut shape = vec![usize::try_from(planned_rows).unwrap_or(usize::MAX)];
        shape.extend_from_slice(tail);
        let header_len = npy_header_shape(&shape).len();
        let (mut w, mut at) = open(path, resume)?;
        if resume.is_none() {
            // Valid from the start: an empty array until rows are counted in.
            let header = padded_header(0, tail, header_len);
            w.write_all(&header).map_err(io(path))?;
            at.bytes = header.len() as u64;
        }
        Ok(Self {
            path: path.to_path_buf(),
            w,
            tail: tail.to_vec(),
            header_len,
            at,
        })
    }

    /// Append one row (`Π tail` values).
    pub fn row(&mut self, row: &[f64]) -> Result<(), CliError> {
        for x in row {
            self.w.write_all(&x.to_le_bytes()).map_err(io(&self.path))?;
        }
        self.at.bytes += 8 * row.len() as u64;
        self.at.rows += 1;
        Ok(())
    }

    /// Flush, write the header with the rows so far, and report the position.
    pub fn position(&mut self) -> Result<Position, CliError> {
        self.w.flush().map_err(io(&self.path))?;
        let header = padded_header(self.at.rows, &self.tail, self.header_len);
        let f = self.w.get_mut();
        f.seek(SeekFrom::Start(0)).map_err(io(&self.path))?;
        f.write_all(&header).map_err(io(&self.path))?;
        f.seek(SeekFrom::End(0)).map_err(io(&self.path))?;
        Ok(self.at)
    }
}

/// The NPY header for `rows` rows, padded with spaces to `len` bytes (the
/// length reserved for the planned count; a longer count cannot occur since
/// the reserved one is padded to 64 bytes from at least as many digits).
fn padded_header(rows: u64, tail: &[usize], len: usize) -> Vec<u8> {
    let mut shape = vec![usize::try_from(rows).unwrap_or(usize::MAX)];
    shape.extend_from_slice(tail);
    let mut h = npy_header_shape(&shape);
    if h.len() < len {
        // Replace the final newline by spaces and put it back at the end.
        h.pop();
        h.resize(len - 1, b' ');
        h.push(b'\n');
        let dict_len = (len - 10) as u16;
        h[8..10].copy_from_slice(&dict_len.to_le_bytes());
    }
    h
}

/// The main table of a run: CSV and/or NPY, the same rows in each.
pub struct TableSink {
    csv: Option<CsvStream>,
    npy: Option<NpyStream>,
}

impl TableSink {
    /// `<stem>.csv` and/or `<stem>.npy` in `dir` as `formats` asks.
    pub fn create(
        dir: &Path,
        stem: &str,
        header: &[String],
        formats: &[String],
        planned_rows: u64,
        resume: Option<(Position, Position)>,
    ) -> Result<Self, CliError> {
        let wants = |f: &str| formats.iter().any(|x| x == f);
        let csv = wants("csv")
            .then(|| CsvStream::create(&dir.join(format!("{stem}.csv")), header, resume.map(|r| r.0)))
            .transpose()?;
        let npy = wants("npy")
            .then(|| {
                NpyStream::create(
                    &dir.join(format!("{stem}.npy")),
                    &[header.len()],
                    planned_rows,
                    resume.map(|r| r.1),
                )
            })
            .transpose()?;
        Ok(Self { csv, npy })
    }

    /// Append a row to every file.
    pub fn row(&mut self, row: &[f64]) -> Result<(), CliError> {
        if let Some(c) = &mut self.csv {
            c.row(row)?;
        }
        if let Some(n) = &mut self.npy {
            n.row(row)?;
        }
        Ok(())
    }

    /// Flush every file (NPY header completed); the positions for a checkpoint.
    pub fn position(&mut self) -> Result<(Position, Position), CliError> {
        let c = self
            .csv
            .as_mut()
            .map(CsvStream::position)
            .transpose()?
            .unwrap_or_default();
        let n = self
            .npy
            .as_mut()
            .map(NpyStream::position)
            .transpose()?
            .unwrap_or_default();
        Ok((c, n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::Table;

    #[test]
    fn streamed_files_equal_whole_writes_and_resume_after_truncation() {
        let dir = crate::test_scratch::Scratch::new("stream");
        let table = Table {
            header: vec!["t".into(), "x".into()],
            rows: (0..7).map(|k| vec![k as f64 * 0.1, 1.0 / (k as f64 + 3.0)]).collect(),
        };
        table.write_csv(&dir.join("whole.csv")).expect("csv");
        table.write_npy(&dir.join("whole.npy")).expect("npy");
        let formats = ["csv".to_string(), "npy".to_string()];
        let mut sink = TableSink::create(&dir, "part", &table.header, &formats, 7, None).expect("sink");
        for r in &table.rows[..3] {
            sink.row(r).expect("row");
        }
        let at = sink.position().expect("checkpoint");
        // Rows written after the checkpoint are dropped on resume.
        sink.row(&[9.0, 9.0]).expect("row");
        sink.position().expect("flush");
        drop(sink);
        let mut sink = TableSink::create(&dir, "part", &table.header, &formats, 7, Some(at)).expect("resume");
        for r in &table.rows[3..] {
            sink.row(r).expect("row");
        }
        sink.position().expect("close");
        drop(sink);
        for ext in ["csv", "npy"] {
            let whole = std::fs::read(dir.join(format!("whole.{ext}"))).expect("read");
            let part = std::fs::read(dir.join(format!("part.{ext}"))).expect("read");
            assert_eq!(whole, part, "{ext}");
        }
    }

    #[test]
    fn padded_header_keeps_the_reserved_length() {
        let long = npy_header_shape(&[usize::MAX, 3]).len();
        let h = padded_header(5, &[3], long);
        assert_eq!(h.len(), long);
        assert_eq!(u16::from_le_bytes([h[8], h[9]]) as usize + 10, long);
        assert!(String::from_utf8_lossy(&h).contains("'shape': (5, 3)"));
        assert_eq!(h.last(), Some(&b'\n'));
    }
}
