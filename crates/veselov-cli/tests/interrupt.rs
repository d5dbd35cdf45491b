//! A run killed with SIGTERM mid-way leaves parseable CSV and NPY files and
//! `status = "interrupted"`; `--resume` then finishes it with files
//! bit-identical to an uninterrupted run.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use veselov_cli::output::Table;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("veselov-interrupt-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn binary() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_veselov"))
}

fn summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    serde_json::from_str(&text).expect("valid JSON")
}

/// Rows in the shape of an NPY file's header, and the data bytes after it.
fn npy_rows(path: &Path) -> (usize, usize) {
    let bytes = std::fs::read(path).expect("npy");
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = String::from_utf8_lossy(&bytes[10..10 + len]).to_string();
    let shape = header.split("'shape': (").nth(1).expect("shape");
    let rows: usize = shape
        .split(',')
        .next()
        .expect("rows")
        .trim()
        .parse()
        .expect("row count");
    (rows, bytes.len() - 10 - len)
}

/// Run `text` to the end in one go, and again killed with SIGTERM once
/// `trajectory.csv` holds rows, then resumed; compare.
fn interrupt_and_resume(name: &str, text: &str) {
    let dir = temp_dir(name);
    let file = dir.join("scenario.toml");
    std::fs::write(&file, text).expect("scenario");
    let whole = dir.join("whole");
    let status = Command::new(binary())
        .args(["run", "--quiet", "--out"])
        .arg(&whole)
        .arg(&file)
        .status()
        .expect("run");
    assert!(status.success());

    let part = dir.join("part");
    let mut child = Command::new(binary())
        .args(["run", "--quiet", "--out"])
        .arg(&part)
        .arg(&file)
        .spawn()
        .expect("spawn");
    let start = Instant::now();
    // Wait for a checkpoint and some rows on disk, then terminate.
    while !(part.join("checkpoint.json").exists()
        && std::fs::metadata(part.join("trajectory.csv")).is_ok_and(|m| m.len() > 100_000))
    {
        assert!(start.elapsed() < Duration::from_secs(60), "no progress");
        assert!(
            child.try_wait().expect("wait").is_none(),
            "finished before it could be interrupted"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .expect("kill");
    let status = child.wait().expect("wait");
    assert!(!status.success(), "an interrupted run exits non-zero");
    assert_eq!(summary(&part)["status"], "interrupted");
    let table = Table::read_csv(&part.join("trajectory.csv")).expect("parseable CSV");
    let whole_rows = Table::read_csv(&whole.join("trajectory.csv")).expect("CSV").rows.len();
    assert!(table.rows.len() < whole_rows, "stopped mid-way");
    let (rows, data) = npy_rows(&part.join("trajectory.npy"));
    assert_eq!(rows, table.rows.len());
    assert_eq!(data, rows * table.header.len() * 8);

    let status = Command::new(binary())
        .args(["run", "--quiet", "--resume"])
        .arg(&part)
        .arg(&file)
        .status()
        .expect("resume");
    assert!(status.success());
    assert_eq!(summary(&part)["status"], "ok");
    assert_eq!(summary(&part)["steps"], summary(&whole)["steps"]);
    for f in ["trajectory.csv", "trajectory.npy"] {
        let a = std::fs::read(whole.join(f)).expect("whole");
        let b = std::fs::read(part.join(f)).expect("resumed");
        assert!(a == b, "{name}: {f} differs after resume");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn mechanics_run_survives_sigterm_and_resumes_bit_for_bit() {
    interrupt_and_resume(
        "mechanics",
        r#"
[model]
name = "double-pendulum"
[method]
name = "galerkin-lobatto"
stages = 3
dt = 0.001
[time]
steps = 400000
[initial]
q = [1.5, -0.5]
v = [0.0, 0.0]
[output]
every = 7
formats = ["csv", "npy"]
plots = false
checkpoint_every = 5000
"#,
    );
}

#[test]
fn rigid_body_run_survives_sigterm_and_resumes_bit_for_bit() {
    interrupt_and_resume(
        "rigid",
        r#"
[model]
name = "heavy-top"
[method]
dt = 0.0005
[time]
steps = 1000000
[output]
every = 3
formats = ["csv", "npy"]
plots = false
checkpoint_every = 10000
"#,
    );
}
