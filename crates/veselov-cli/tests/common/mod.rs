//! Helpers shared by the command-line tests: scratch directories, the
//! binary, scenario files, and readers of the outputs.
#![allow(dead_code)] // each test crate uses its own subset

use std::path::{Path, PathBuf};

use assert_cmd::Command;

#[path = "../../src/test_scratch.rs"]
mod test_scratch;
pub use test_scratch::Scratch;

/// The repository root (for `examples/`).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `veselov` binary.
pub fn veselov() -> Command {
    Command::cargo_bin("veselov").expect("binary built")
}

/// `veselov run --quiet --out <out> <scenario>`, asserted on: the caller
/// says whether it must succeed or fail.
pub fn run_scenario(
    out: impl AsRef<std::ffi::OsStr>,
    scenario: impl AsRef<std::ffi::OsStr>,
) -> assert_cmd::assert::Assert {
    veselov()
        .args(["run", "--quiet", "--out"])
        .arg(out)
        .arg(scenario)
        .assert()
}

/// `veselov verify --quiet --dt <dts> --out <out> <scenario>`, for the
/// caller to run and assert on.
pub fn verify_command(dts: &str, out: impl AsRef<std::ffi::OsStr>, scenario: impl AsRef<std::ffi::OsStr>) -> Command {
    let mut command = veselov();
    command
        .args(["verify", "--quiet", "--dt", dts, "--out"])
        .arg(out)
        .arg(scenario);
    command
}

/// Run `command`, which must succeed, and return its standard output.
pub fn succeeds(command: &mut Command) -> String {
    let out = command.assert().success();
    String::from_utf8_lossy(&out.get_output().stdout).into_owned()
}

/// Assert that `text` (named `what` in the message) contains every needle.
pub fn assert_mentions(text: &str, needles: &[&str], what: &str) {
    for needle in needles {
        assert!(text.contains(needle), "{what} lacks `{needle}`: {text}");
    }
}

/// Write `text` as a scenario file in `dir` and return its path.
pub fn scenario(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("scenario.toml");
    std::fs::write(&p, text).expect("write scenario");
    p
}

/// The text of `examples/<file>`.
pub fn example(file: &str) -> String {
    std::fs::read_to_string(workspace_root().join("examples").join(file)).expect("example")
}

/// `summary.json` of a run directory.
pub fn summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    serde_json::from_str(&text).expect("valid JSON")
}

/// Replace the first line starting with `key =` by `key = value`.
pub fn set(text: &str, key: &str, value: &str) -> String {
    let mut done = false;
    text.lines()
        .map(|l| {
            if !done && l.trim_start().starts_with(&format!("{key} =")) {
                done = true;
                format!("{key} = {value}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Run the scenario `text` quietly in a fresh directory `name`; returns
/// (success, stderr, output directory).
pub fn run(name: &str, text: &str) -> (bool, String, Scratch) {
    let dir = Scratch::new(name);
    let file = scenario(&dir, text);
    let out = dir.at("out");
    let o = veselov()
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(&file)
        .output()
        .expect("run");
    (o.status.success(), String::from_utf8_lossy(&o.stderr).into_owned(), out)
}

/// Run the scenario `text` with its messages (not quiet) in a fresh
/// directory `name`; returns the command's output and the directory (its
/// outputs in `out`).
pub fn run_loud(name: &str, text: &str) -> (std::process::Output, Scratch) {
    let dir = Scratch::new(name);
    let file = scenario(&dir, text);
    let o = veselov()
        .args(["run", "--out"])
        .arg(dir.join("out"))
        .arg(&file)
        .output()
        .expect("run");
    (o, dir)
}

/// A CSV file's header names and rows.
pub fn csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).expect("csv");
    let mut lines = text.lines();
    let header = lines.next().expect("header").split(',').map(str::to_string).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.trim().parse::<f64>().expect("number")).collect())
        .collect();
    (header, rows)
}

/// The shape in the header of an NPY file.
pub fn npy_shape(path: &Path) -> Vec<usize> {
    let bytes = std::fs::read(path).expect("npy");
    assert!(bytes.starts_with(b"\x93NUMPY"));
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = String::from_utf8_lossy(&bytes[10..10 + len]).into_owned();
    let inner = &header[header.find("'shape': (").expect("shape") + 10..];
    inner[..inner.find(')').expect("end")]
        .split(',')
        .filter(|s| !s.trim().is_empty())
        .map(|s| s.trim().parse().expect("dim"))
        .collect()
}

/// The float64 data of an NPY file written by a run (after its header).
pub fn npy_data(path: &Path) -> Vec<f64> {
    let bytes = std::fs::read(path).expect("npy");
    assert!(bytes.starts_with(b"\x93NUMPY"));
    let header = 10 + u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    bytes[header..]
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
        .collect()
}
