//! What goes wrong around a run rather than in it: a resume of a completed
//! run, two runs into one directory, `--force` over a directory that also
//! holds a user's files, an interrupted run's plots, checkpoints that cost
//! more than the run, and `veselov plot` on damaged or foreign files.

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::common::{Scratch, example, scenario, set, veselov};

/// The binary, as a plain process (for runs started side by side).
fn binary() -> Command {
    Command::new(env!("CARGO_BIN_EXE_veselov"))
}

/// A Kepler run of `t_end` (steps of 0.01), rows every 100 steps.
fn kepler(t_end: &str, plots: bool) -> String {
    let text = set(&example("kepler.toml"), "t_end", t_end);
    let text = set(&text, "every", "100");
    set(&text, "plots", if plots { "true" } else { "false" })
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `veselov run --quiet <args…> <file>`.
fn run(file: &Path, args: &[&std::ffi::OsStr]) -> Output {
    binary()
        .args(["run", "--quiet"])
        .args(args)
        .arg(file)
        .output()
        .expect("run")
}

/// Every file of `dir` with its bytes, sorted by name.
fn contents(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .expect("dir")
        .map(|e| e.expect("entry"))
        .filter(|e| e.path().is_file())
        .map(|e| {
            let bytes = std::fs::read(e.path()).expect("file");
            (e.file_name().to_string_lossy().into_owned(), bytes)
        })
        .collect();
    files.sort();
    files
}

/// A completed run resumed: nothing is run or rewritten (its summary keeps
/// its counters), the command succeeds and says why.
#[test]
fn resuming_a_completed_run_leaves_it_as_it_is() {
    let dir = Scratch::new("faults-complete");
    let file = scenario(&dir, &kepler("20.0", true));
    let out = dir.join("out");
    assert!(run(&file, &["--out".as_ref(), out.as_ref()]).status.success());
    let before = contents(&out);
    let o = binary()
        .args(["run", "--resume"])
        .arg(&out)
        .arg(&file)
        .output()
        .expect("resume");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("already complete") && stderr(&o).contains("time.t_end"),
        "{}",
        stderr(&o)
    );
    assert!(contents(&out) == before, "the completed run's files changed");
    // A longer run still extends it.
    let longer = scenario(&dir, &kepler("30.0", false));
    assert!(run(&longer, &["--resume".as_ref(), out.as_ref()]).status.success());
    let s = crate::common::summary(&out);
    assert!((s["t_final"].as_f64().expect("t_final") - 30.0).abs() < 1e-9, "{s}");
    assert!(s["iterations_mean"].as_f64().expect("iterations") > 1.0, "{s}");
}

/// Two runs started together into one directory (both with `--force`, so
/// that only the lock stands between them): never both succeed, and the
/// one refused names the directory and the other run's process.
#[test]
fn two_runs_into_one_directory_never_both_succeed() {
    let dir = Scratch::new("faults-two-runs");
    let file = scenario(&dir, &kepler("20000.0", false));
    for trial in 0..4 {
        let out = dir.join(format!("out{trial}"));
        let start = || {
            binary()
                .args(["run", "--quiet", "--force", "--out"])
                .arg(&out)
                .arg(&file)
                .stderr(Stdio::piped())
                .spawn()
                .expect("spawn")
        };
        let (a, b) = (start(), start());
        let (a, b) = (a.wait_with_output().expect("a"), b.wait_with_output().expect("b"));
        assert!(
            !(a.status.success() && b.status.success()),
            "trial {trial}: both runs into one directory succeeded"
        );
        let refused = if a.status.success() { &b } else { &a };
        let message = stderr(refused);
        assert!(
            message.contains("in use by another run") && message.contains(&format!("out{trial}")),
            "trial {trial}: {message}"
        );
        assert!(!out.join(".veselov.lock").exists(), "trial {trial}: the lock was left");
    }
}

/// A run holds its directory: a second run is refused naming the first
/// one's process; once the first is interrupted, the lock is gone. A lock
/// left by a process that no longer runs is replaced, with a note.
#[test]
fn a_lock_names_its_run_and_a_stale_one_is_replaced() {
    let dir = Scratch::new("faults-lock");
    let long = scenario(&dir, &kepler("1000000.0", false));
    let out = dir.join("out");
    let mut first = binary()
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(&long)
        .stderr(Stdio::null())
        .spawn()
        .expect("spawn");
    let start = Instant::now();
    while !out.join("trajectory.csv").exists() {
        assert!(start.elapsed() < Duration::from_secs(60), "the first run did not start");
        assert!(first.try_wait().expect("wait").is_none(), "the first run ended");
        std::thread::sleep(Duration::from_millis(20));
    }
    let short = dir.join("short.toml");
    std::fs::write(&short, kepler("1.0", false)).expect("scenario");
    let second = run(&short, &["--force".as_ref(), "--out".as_ref(), out.as_ref()]);
    let message = stderr(&second);
    assert!(!second.status.success(), "{message}");
    assert!(
        message.contains(&format!("process {}", first.id())) && message.contains(&out.display().to_string()),
        "{message}"
    );
    Command::new("kill")
        .args(["-TERM", &first.id().to_string()])
        .status()
        .expect("kill");
    assert!(!first.wait().expect("wait").success(), "interrupted");
    assert!(!out.join(".veselov.lock").exists(), "an interrupted run left its lock");

    let stale = dir.join("stale");
    std::fs::create_dir_all(&stale).expect("dir");
    std::fs::write(stale.join(".veselov.lock"), "pid 4294967295\n").expect("a stale lock");
    let o = binary()
        .args(["run", "--force", "--out"])
        .arg(&stale)
        .arg(&short)
        .output()
        .expect("run");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("no longer running"), "{}", stderr(&o));
    assert!(!stale.join(".veselov.lock").exists());
}

/// `--force` removes the files the earlier run recorded as its own (a data
/// file the new run does not write included) and keeps the user's, even
/// those named like a run's outputs.
#[test]
fn force_removes_only_what_the_earlier_run_wrote() {
    let dir = Scratch::new("faults-force");
    let out = dir.join("out");
    let first = scenario(&dir, &kepler("5.0", true));
    assert!(run(&first, &["--out".as_ref(), out.as_ref()]).status.success());
    let recorded = std::fs::read_to_string(out.join("outputs.json")).expect("outputs.json");
    for f in ["trajectory.csv", "trajectory.npy", "summary.json", "orbit.svg"] {
        assert!(recorded.contains(&format!("\"{f}\"")), "{f} not recorded: {recorded}");
    }
    let mine = ["field_9.png", "orbit.png", "energy.csv", "notes.txt"];
    for f in mine {
        std::fs::write(out.join(f), b"the user's").expect("user file");
    }
    let second = dir.join("csv-only.toml");
    std::fs::write(
        &second,
        kepler("5.0", true).replace("formats = [\"csv\", \"npy\"]", "formats = [\"csv\"]"),
    )
    .expect("scenario");
    let o = run(&second, &["--force".as_ref(), "--out".as_ref(), out.as_ref()]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in mine {
        assert_eq!(std::fs::read(out.join(f)).expect(f), b"the user's", "{f}");
    }
    assert!(!out.join("trajectory.npy").exists(), "the earlier run's file was kept");
    let recorded = std::fs::read_to_string(out.join("outputs.json")).expect("outputs.json");
    assert!(
        !recorded.contains("trajectory.npy") && !recorded.contains("field_9"),
        "{recorded}"
    );

    // A directory an earlier version wrote has no record: the files named
    // as run outputs go, the others stay.
    let older = dir.join("older");
    std::fs::create_dir_all(&older).expect("dir");
    for f in ["summary.json", "trajectory.npy", "notes.txt"] {
        std::fs::write(older.join(f), b"old").expect("file");
    }
    let o = run(&second, &["--force".as_ref(), "--out".as_ref(), older.as_ref()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!older.join("trajectory.npy").exists() && older.join("notes.txt").exists());
}

/// An interrupted run writes no plots (they would read back its whole
/// output) and says how to draw them; `veselov plot` then does.
#[test]
fn an_interrupted_run_leaves_its_plots_to_veselov_plot() {
    let dir = Scratch::new("faults-interrupted-plots");
    let file = scenario(&dir, &kepler("1000000.0", true));
    let out = dir.join("out");
    let o = run(
        &file,
        &["--time-limit".as_ref(), "0.5".as_ref(), "--out".as_ref(), out.as_ref()],
    );
    let message = stderr(&o);
    assert!(!o.status.success() && message.contains("interrupted"), "{message}");
    assert!(
        message.contains(&format!("veselov plot {}", out.display())),
        "{message}"
    );
    let plots = || {
        std::fs::read_dir(&out)
            .expect("dir")
            .filter_map(Result::ok)
            .filter(|e| {
                let name = e.file_name().to_string_lossy().into_owned();
                name.ends_with(".svg") || name.ends_with(".png")
            })
            .count()
    };
    assert_eq!(plots(), 0, "an interrupted run drew plots");
    let o = veselov().arg("plot").arg(&out).output().expect("plot");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(plots() > 0);
}

/// Checkpoints after every step of a cheap system cost far more than the
/// steps: the run says so, naming the key and an interval that would do.
#[test]
fn checkpoints_that_dominate_a_run_are_warned() {
    let dir = Scratch::new("faults-checkpoint-cost");
    let text = kepler("30.0", false) + "\ncheckpoint_every = 1\n";
    let o = run(&scenario(&dir, &text), &["--out".as_ref(), dir.join("out").as_ref()]);
    let message = stderr(&o);
    assert!(o.status.success(), "{message}");
    assert!(
        message.contains("warning: writing checkpoints") && message.contains("output.checkpoint_every"),
        "{message}"
    );
    let o = run(
        &scenario(&dir, &kepler("30.0", false)),
        &["--force".as_ref(), "--out".as_ref(), dir.join("out").as_ref()],
    );
    assert!(!stderr(&o).contains("checkpoint"), "{}", stderr(&o));
}
