//! Writers and readers of run outputs: CSV (shortest round-trip formatting),
//! NumPy `.npy` (format 1.0, little-endian float64, C order) and JSON.
//!
//! The `.npy` header is a fixed 10-byte preamble plus a Python dict literal;
//! writing it takes a dozen lines, less than wiring a dependency for it.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::Path;

use crate::error::CliError;

pub(crate) fn io(path: &Path) -> impl Fn(std::io::Error) -> CliError + '_ {
    move |e| CliError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// A table of named float64 columns stored row by row.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Table {
    /// Column names.
    pub header: Vec<String>,
    /// Rows, each as long as the header.
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    /// The column called `name`.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.header.iter().position(|h| h == name)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }

    /// Write as CSV, numbers as [`push_number`] writes them.
    pub fn write_csv(&self, path: &Path) -> Result<(), CliError> {
        let mut w = BufWriter::new(File::create(path).map_err(io(path))?);
        writeln!(w, "{}", self.header.join(",")).map_err(io(path))?;
        let mut line = String::new();
        for row in &self.rows {
            line.clear();
            for (i, x) in row.iter().enumerate() {
                if i > 0 {
                    line.push(',');
                }
                push_number(&mut line, *x);
            }
            writeln!(w, "{line}").map_err(io(path))?;
        }
        w.flush().map_err(io(path))
    }

    /// Read a CSV written by [`Table::write_csv`].
    pub fn read_csv(path: &Path) -> Result<Self, CliError> {
        let r = BufReader::new(File::open(path).map_err(io(path))?);
        let mut lines = r.lines();
        let header: Vec<String> = match lines.next() {
            Some(h) => h.map_err(io(path))?.split(',').map(|s| s.trim().to_string()).collect(),
            None => {
                return Err(CliError::Io {
                    path: path.to_path_buf(),
                    message: "empty file".into(),
                });
            }
        };
        let mut rows = Vec::new();
        for (k, line) in lines.enumerate() {
            let line = line.map_err(io(path))?;
            if line.trim().is_empty() {
                continue;
            }
            let row = line
                .split(',')
                .map(|s| s.trim().parse::<f64>())
                .collect::<Result<Vec<f64>, _>>()
                .map_err(|e| CliError::Io {
                    path: path.to_path_buf(),
                    message: format!("line {}: {e}", k + 2),
                })?;
            if row.len() != header.len() {
                return Err(CliError::Io {
                    path: path.to_path_buf(),
                    message: format!("line {}: {} values for {} columns", k + 2, row.len(), header.len()),
                });
            }
            rows.push(row);
        }
        Ok(Self { header, rows })
    }

    /// Write as a 2-D float64 `.npy` array (rows × columns).
    pub fn write_npy(&self, path: &Path) -> Result<(), CliError> {
        let mut w = BufWriter::new(File::create(path).map_err(io(path))?);
        w.write_all(&npy_header(self.rows.len(), self.header.len()))
            .map_err(io(path))?;
        for row in &self.rows {
            for x in row {
                w.write_all(&x.to_le_bytes()).map_err(io(path))?;
            }
        }
        w.flush().map_err(io(path))
    }
}

/// The `.npy` 1.0 header for a C-order `<f8` array of shape `(rows, cols)`, padded to 64 bytes.
pub fn npy_header(rows: usize, cols: usize) -> Vec<u8> {
    npy_header_shape(&[rows, cols])
}

/// The `.npy` 1.0 header for a C-order `<f8` array of any shape.
pub fn npy_header_shape(shape: &[usize]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let tuple = if dims.len() == 1 {
        format!("({},)", dims[0])
    } else {
        format!("({})", dims.join(", "))
    };
    let mut dict = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {tuple}, }}");
    let unpadded = 10 + dict.len() + 1;
    dict.push_str(&" ".repeat((64 - unpadded % 64) % 64));
    dict.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(dict.len() as u16).to_le_bytes());
    out.extend_from_slice(dict.as_bytes());
    out
}

/// Write pretty JSON.
pub fn write_json(path: &Path, value: &serde_json::Value) -> Result<(), CliError> {
    let text = serde_json::to_string_pretty(value).map_err(|e| CliError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    std::fs::write(path, text + "\n").map_err(io(path))
}

/// The stems of the files a run of any kind writes (with an extension of
/// [`OUTPUT_EXTENSIONS`]): data, plots in either plot format, the
/// animation; `field_<k>` snapshots besides ([`is_run_output`]).
const OUTPUT_STEMS: &[&str] = &[
    "trajectory",
    "energy",
    "momentum",
    "snapshots",
    "snapshot_times",
    "centerline",
    "frames",
    "convergence",
    "energy_error",
    "energy_change",
    "energy_balance",
    "momentum_error",
    "body_momentum",
    "phase",
    "orbit",
    "final_waveform",
    "centerline_xz",
    "centerline_yz",
    "spacetime",
    "energy_blocks",
];

/// The extensions of the files of [`OUTPUT_STEMS`].
const OUTPUT_EXTENSIONS: &[&str] = &["csv", "npy", "svg", "png", "gif"];

/// Whether `name` is a file a run writes into its output directory (every
/// kind's data, plots, animation, `summary.json` and `checkpoint.json`):
/// the files `--force` removes from a directory of a run that recorded no
/// list of its files (one written by an earlier version).
pub fn is_run_output(name: &str) -> bool {
    if name == "summary.json" || name == "checkpoint.json" {
        return true;
    }
    let Some((stem, extension)) = name.rsplit_once('.') else {
        return false;
    };
    if !OUTPUT_EXTENSIONS.contains(&extension) {
        return false;
    }
    OUTPUT_STEMS.contains(&stem)
        || stem
            .strip_prefix("field_")
            .is_some_and(|k| !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit()))
}

/// Append `x` in the shortest form that reads back to the same `f64`:
/// positional for `10⁻⁴ ≤ |x| < 10¹⁶` and zero (`0.125`, `314.159`), with an
/// exponent otherwise (`1e300`, `2.220446049250313e-16`), never hundreds of
/// digits. Non-finite values are written `NaN`, `inf`, `-inf`.
pub fn push_number(out: &mut String, x: f64) {
    use std::fmt::Write as _;
    let a = x.abs();
    let _ = if x == 0.0 || !x.is_finite() || (1e-4..1e16).contains(&a) {
        write!(out, "{x}")
    } else {
        write!(out, "{x:e}")
    };
}

/// `x` in the shortest form that reads back to the same `f64`, as every
/// message echoes a number: positional for 10⁻⁴ ≤ |x| < 10⁶ and zero
/// (`0.125`, `314.159`), with an exponent otherwise (`1e308`, `3e14`,
/// `1e-300`), never hundreds of digits.
pub fn number(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-4..1e6).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `n` and the noun `one` or its plural `many`: `1 step`, `2 steps`,
/// `1 time step`, `0 levels`.
pub fn count(n: u64, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// `x` rounded to three significant digits, positional for
/// 10⁻⁴ ≤ |x| < 10⁶ and with an exponent otherwise: the form of a measured
/// or suggested value (`148 %`, `dt ≤ 0.00233`, `2e11 %`, `dt ≤ 1.5e-7`).
pub fn approx(x: f64) -> String {
    significant(x, 3)
}

/// `x` rounded to `digits` significant digits (at least 1), in the form of
/// [`approx`]: `24.52`, `-2.417e-10`, `0`.
pub fn significant(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return number(x);
    }
    // Through the exponent form, which rounds to the digits exactly.
    let r: f64 = format!("{x:.*e}", digits.max(1) - 1).parse().unwrap_or(x);
    if (1e-4..1e6).contains(&r.abs()) {
        number(r)
    } else {
        format!("{r:e}")
    }
}

/// Whether [`say`] has reported a write error (it reports one).
static STDOUT_FAILED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Writes `args` and a newline to standard output, as `println!` does, but
/// a closed pipe (`veselov models | head -3`) is not an error: the rest of
/// the text is dropped, where `println!` would panic. Another write error
/// is reported once, on standard error.
pub fn say(args: std::fmt::Arguments<'_>) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.write_all(b"\n"))
        && e.kind() != std::io::ErrorKind::BrokenPipe
        && !STDOUT_FAILED.swap(true, std::sync::atomic::Ordering::Relaxed)
    {
        eprintln!("warning: could not write to standard output: {e}");
    }
}

/// `println!` through [`say`](crate::output::say): a closed standard output
/// does not panic.
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::output::say(format_args!($($arg)*))
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_outputs_are_recognised_and_nothing_else() {
        for name in [
            "summary.json",
            "checkpoint.json",
            "trajectory.csv",
            "trajectory.npy",
            "energy_error.png",
            "centerline.gif",
            "field_0.png",
            "field_12.svg",
        ] {
            assert!(is_run_output(name), "{name}");
        }
        for name in [
            "notes.txt",
            "scenario.toml",
            "energy.csv.bak",
            "field_.png",
            "field_x.png",
            "data.json",
            "trajectory",
            "plot.svg",
        ] {
            assert!(!is_run_output(name), "{name}");
        }
    }

    #[test]
    fn npy_header_is_aligned_and_well_formed() {
        let h = npy_header(3, 5);
        assert_eq!(h.len() % 64, 0);
        assert_eq!(&h[..8], b"\x93NUMPY\x01\x00");
        let len = u16::from_le_bytes([h[8], h[9]]) as usize;
        assert_eq!(len + 10, h.len());
        let text = String::from_utf8_lossy(&h[10..]);
        assert!(text.contains("'shape': (3, 5)"));
        assert!(text.ends_with('\n'));
    }

    #[test]
    fn csv_round_trips_exactly() {
        let dir = crate::test_scratch::Scratch::new("csv");
        let t = Table {
            header: vec!["t".into(), "x".into()],
            rows: vec![vec![0.1, 1.0 / 3.0], vec![1e-300, -2.5e17]],
        };
        let p = dir.join("t.csv");
        t.write_csv(&p).expect("write");
        assert_eq!(Table::read_csv(&p).expect("read"), t);
        // Extreme values are short and exact, not hundreds of digits.
        let text = std::fs::read_to_string(&p).expect("text");
        assert!(text.contains("1e-300,-2.5e17"), "{text}");
    }

    /// Every number is written in its shortest round-trip form, with an
    /// exponent outside [1e-4, 1e16): short for 1e300 and ε, plain for 0.125.
    #[test]
    fn numbers_are_short_and_read_back_exactly() {
        let cases = [
            (1e300, "1e300"),
            (f64::EPSILON, "2.220446049250313e-16"),
            (0.125, "0.125"),
            (-314.159, "-314.159"),
            (0.0, "0"),
            (1e-4, "0.0001"),
            (9.5e-5, "9.5e-5"),
            (1e16, "1e16"),
            (f64::MIN_POSITIVE, "2.2250738585072014e-308"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ];
        for (x, want) in cases {
            let mut s = String::new();
            push_number(&mut s, x);
            assert_eq!(s, want);
        }
        // Round trip over many magnitudes and bit patterns.
        let mut bits = 0x3ff0_0000_0000_0001_u64;
        for k in 0..2000 {
            bits = bits.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let x = f64::from_bits(bits);
            if !x.is_finite() {
                continue;
            }
            let mut s = String::new();
            push_number(&mut s, x);
            assert!(s.len() <= 24, "{k}: {s}");
            assert_eq!(s.parse::<f64>().expect("parses").to_bits(), x.to_bits(), "{s}");
        }
    }
}
