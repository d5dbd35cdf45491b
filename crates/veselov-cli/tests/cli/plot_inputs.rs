//! `veselov plot DIR` reads files anyone may have edited, truncated or
//! written with other tools: it draws what it can (non-finite values as
//! gaps) and refuses the rest with an error naming the file, never a panic.

use std::path::Path;
use std::process::Output;

use crate::common::{Scratch, example, npy_shape, scenario, set, veselov};

/// Run the example `name` with `settings` into `dir/out`, plots drawn.
fn run_example(dir: &Path, name: &str, settings: &[(&str, &str)]) -> std::path::PathBuf {
    let mut text = example(&format!("{name}.toml"));
    for (key, value) in settings {
        text = set(&text, key, value);
    }
    let out = dir.join("out");
    let o = veselov()
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(scenario(dir, &text))
        .output()
        .expect("run");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out
}

fn plot(dir: &Path) -> Output {
    veselov().arg("plot").arg(dir).output().expect("plot")
}

/// `veselov plot` failed cleanly: exit status 1, one error line naming
/// `file` and saying `what`, no panic.
fn refused(o: &Output, file: &str, what: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.starts_with("error: "), "{err}");
    assert!(
        err.contains(file) && err.contains(what),
        "expected `{file}` and `{what}`: {err}"
    );
}

/// The header's length and the whole bytes of an NPY file.
fn npy_bytes(path: &Path) -> (usize, Vec<u8>) {
    let bytes = std::fs::read(path).expect("npy");
    (10 + u16::from_le_bytes([bytes[8], bytes[9]]) as usize, bytes)
}

/// Every value of the NPY file `path` replaced by `value`.
fn fill_npy(path: &Path, value: f64) {
    let (header, mut bytes) = npy_bytes(path);
    for chunk in bytes[header..].chunks_exact_mut(8) {
        chunk.copy_from_slice(&value.to_le_bytes());
    }
    std::fs::write(path, bytes).expect("write");
}

/// `path`'s header text edited (`from` → `to`, of the same length).
fn edit_npy_header(path: &Path, from: &str, to: &str) {
    assert_eq!(from.len(), to.len());
    let (header, mut bytes) = npy_bytes(path);
    // The dict after the 10-byte preamble (whose magic is not UTF-8).
    let text = String::from_utf8_lossy(&bytes[10..header]).replacen(from, to, 1);
    assert!(text.contains(to), "no `{from}` in the header");
    bytes[10..header].copy_from_slice(text.as_bytes());
    std::fs::write(path, bytes).expect("write");
}

/// `summary.json` of `dir` with `key` set to `value`.
fn set_summary(dir: &Path, key: &str, value: serde_json::Value) {
    let mut s = crate::common::summary(dir);
    s[key] = value;
    std::fs::write(dir.join("summary.json"), s.to_string()).expect("write");
}

/// NaN (and infinite) snapshots of a 2+1 field are drawn, as gaps.
#[test]
fn non_finite_snapshots_are_drawn_as_gaps() {
    for (name, settings, figure) in [
        (
            "sine_gordon_2d",
            &[("t_end", "0.5"), ("snapshot_every", "1"), ("nodes", "[12, 12]")][..],
            "field_0.png",
        ),
        (
            "sine_gordon",
            &[("t_end", "2.0"), ("snapshot_every", "10")][..],
            "spacetime.png",
        ),
    ] {
        for value in [f64::NAN, f64::INFINITY] {
            let dir = Scratch::new(&format!("plot-nan-{name}"));
            let out = run_example(&dir, name, settings);
            fill_npy(&out.join("snapshots.npy"), value);
            std::fs::remove_file(out.join(figure)).expect("drawn by the run");
            let o = plot(&out);
            assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
            assert!(out.join(figure).exists(), "{name}: {figure} not drawn");
        }
    }
}

/// A summary whose lattice is absurd, or does not match the snapshots, is
/// refused before anything is allocated from it.
#[test]
fn absurd_summaries_are_refused() {
    let dir = Scratch::new("plot-absurd-summary");
    let out = run_example(
        &dir,
        "sine_gordon_2d",
        &[("t_end", "0.5"), ("snapshot_every", "1"), ("nodes", "[12, 12]")],
    );
    let original = std::fs::read(out.join("summary.json")).expect("summary");
    for nodes in [
        serde_json::json!([1e9, 1e9]),
        serde_json::json!([-3, 12]),
        serde_json::json!([12]),
        serde_json::json!("many"),
    ] {
        set_summary(&out, "nodes", nodes);
        refused(&plot(&out), "summary.json", "nodes");
    }
    set_summary(&out, "nodes", serde_json::json!([1_000_000_000u64, 1_000_000_000u64]));
    refused(&plot(&out), "snapshots.npy", "1000000000");
    set_summary(&out, "nodes", serde_json::json!([12, 12]));
    set_summary(&out, "dx", serde_json::json!(1e308));
    refused(&plot(&out), "summary.json", "dx");
    std::fs::write(out.join("summary.json"), &original).expect("restore");
    assert!(plot(&out).status.success());

    let dir = Scratch::new("plot-absurd-summary-1d");
    let out = run_example(&dir, "sine_gordon", &[("t_end", "2.0"), ("snapshot_every", "10")]);
    set_summary(&out, "nodes", serde_json::json!(1e9));
    refused(&plot(&out), "summary.json", "nodes");
    set_summary(&out, "nodes", serde_json::json!(1_000_000_000u64));
    refused(&plot(&out), "snapshots.npy", "1000000000");
}

/// A snapshots file in Fortran order, of another dtype, cut short, or with
/// times missing is refused naming the file; it is never drawn scrambled.
#[test]
fn foreign_or_damaged_arrays_are_refused() {
    let dir = Scratch::new("plot-foreign-arrays");
    let out = run_example(
        &dir,
        "sine_gordon_2d",
        &[("t_end", "0.5"), ("snapshot_every", "1"), ("nodes", "[12, 12]")],
    );
    let snapshots = out.join("snapshots.npy");
    let original = std::fs::read(&snapshots).expect("snapshots");
    edit_npy_header(&snapshots, "'fortran_order': False", "'fortran_order': True ");
    refused(&plot(&out), "snapshots.npy", "Fortran");
    std::fs::write(&snapshots, &original).expect("restore");
    edit_npy_header(&snapshots, "'<f8'", "'<f4'");
    refused(&plot(&out), "snapshots.npy", "dtype");
    std::fs::write(&snapshots, &original[..original.len() - 8]).expect("cut short");
    refused(&plot(&out), "snapshots.npy", "cut short");
    std::fs::write(&snapshots, &original).expect("restore");
    let shape = npy_shape(&snapshots);
    assert_eq!(shape[1..], [12, 12]);
    let times = out.join("snapshot_times.csv");
    std::fs::write(&times, "t\n0\n").expect("one time");
    refused(&plot(&out), "snapshot_times.csv", "times");

    // The rod's centreline file, of the wrong width.
    let dir = Scratch::new("plot-foreign-centreline");
    let out = run_example(&dir, "rod_helix", &[("t_end", "0.02")]);
    let centreline = out.join("centerline.npy");
    let shape = npy_shape(&centreline);
    let (from, to) = (format!("{}, 3)", shape[1]), format!("{}, 1)", shape[1]));
    edit_npy_header(&centreline, &from, &to);
    refused(&plot(&out), "centerline.npy", "shape");
}
