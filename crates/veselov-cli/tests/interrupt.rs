//! A run killed with SIGTERM mid-way leaves parseable CSV and NPY files and
//! `status = "interrupted"`; `--resume` then finishes it with files
//! bit-identical to an uninterrupted run.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use veselov_cli::output::Table;

mod common;
use common::{Scratch, summary};

fn binary() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_veselov"))
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

/// The files of a run kind: the CSV file watched for progress, the NPY file
/// whose rows match a CSV file's, and every file compared after resuming.
struct Files {
    watch: &'static str,
    /// Bytes the watched file must hold before the run is killed.
    watch_bytes: u64,
    /// (csv, npy, values per NPY row; 0: the CSV's column count).
    paired: (&'static str, &'static str, usize),
    compared: &'static [&'static str],
    /// Extra arguments of the interrupted run.
    args: &'static [&'static str],
    /// A change of the scenario beyond its run length (text, replacement,
    /// the key named), with which a resume must be refused, leaving the
    /// files as they were.
    changed: Option<(&'static str, &'static str, &'static str)>,
}

const TRAJECTORY: Files = Files {
    watch: "trajectory.csv",
    watch_bytes: 100_000,
    paired: ("trajectory.csv", "trajectory.npy", 0),
    compared: &["trajectory.csv", "trajectory.npy"],
    args: &[],
    changed: None,
};

/// Run `text` to the end in one go, and again killed with SIGTERM once
/// the watched file holds rows, then resumed; compare.
fn interrupt_and_resume(name: &str, text: &str, files: &Files) {
    let dir = Scratch::new(name);
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
        .args(["run", "--quiet"])
        .args(files.args)
        .arg("--out")
        .arg(&part)
        .arg(&file)
        .spawn()
        .expect("spawn");
    let start = Instant::now();
    // Wait for a checkpoint and some rows on disk, then terminate.
    while !(part.join("checkpoint.json").exists()
        && std::fs::metadata(part.join(files.watch)).is_ok_and(|m| m.len() > files.watch_bytes))
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
    let watched = Table::read_csv(&part.join(files.watch)).expect("parseable CSV");
    let whole_rows = Table::read_csv(&whole.join(files.watch)).expect("CSV").rows.len();
    assert!(watched.rows.len() < whole_rows, "stopped mid-way");
    let (csv, npy, width) = files.paired;
    let table = Table::read_csv(&part.join(csv)).expect("parseable CSV");
    let (rows, data) = npy_rows(&part.join(npy));
    assert_eq!(rows, table.rows.len());
    let width = if width == 0 { table.header.len() } else { width };
    assert_eq!(data, rows * width * 8);

    if let Some((text_from, text_to, key)) = files.changed {
        assert!(text.contains(text_from), "{name}: no `{text_from}` to change");
        let other = dir.join("other.toml");
        std::fs::write(&other, text.replacen(text_from, text_to, 1)).expect("scenario");
        let before: Vec<Vec<u8>> = files
            .compared
            .iter()
            .map(|f| std::fs::read(part.join(f)).expect("file"))
            .collect();
        let refused = Command::new(binary())
            .args(["run", "--quiet", "--resume"])
            .arg(&part)
            .arg(&other)
            .output()
            .expect("resume with another scenario");
        let err = String::from_utf8_lossy(&refused.stderr);
        assert!(!refused.status.success() && err.contains(key), "{name}: {err}");
        for (f, b) in files.compared.iter().zip(&before) {
            assert!(
                &std::fs::read(part.join(f)).expect("file") == b,
                "{name}: {f} touched by a refused resume"
            );
        }
        assert_eq!(summary(&part)["status"], "interrupted");
    }
    let status = Command::new(binary())
        .args(["run", "--quiet", "--resume"])
        .arg(&part)
        .arg(&file)
        .status()
        .expect("resume");
    assert!(status.success());
    assert_eq!(summary(&part)["status"], "ok");
    same_summary(name, &summary(&whole), &summary(&part));
    for f in files.compared {
        let a = std::fs::read(whole.join(f)).expect("whole");
        let b = std::fs::read(part.join(f)).expect("resumed");
        assert!(a == b, "{name}: {f} differs after resume");
    }
    // What a held rod or beam reports from its first and last rows and its
    // support, kept in the checkpoint across the interruption.
    let (s_whole, s_part) = (summary(&whole), summary(&part));
    for key in [
        "tip_displacement",
        "tip_rotation_vector",
        "deflection_max",
        "reaction_force",
        "reaction_moment",
    ] {
        assert_eq!(s_whole.get(key), s_part.get(key), "{name}: {key} differs after resume");
    }
    resume_of_a_completed_run_changes_nothing(name, &part, &file);
    std::fs::remove_dir_all(&dir).ok();
}

/// The summaries of a run done in one go (`whole`) and of the same run
/// interrupted and resumed (`part`) agree in every key but the wall time:
/// steps, time, and every counter (`iterations_mean`, the kinds' Newton
/// iterations, Jacobians, gradient evaluations, fallback steps).
fn same_summary(name: &str, whole: &serde_json::Value, part: &serde_json::Value) {
    let (Some(whole), Some(part)) = (whole.as_object(), part.as_object()) else {
        panic!("{name}: a summary is not an object");
    };
    let keys = |s: &serde_json::Map<String, serde_json::Value>| s.keys().cloned().collect::<Vec<_>>();
    assert_eq!(keys(whole), keys(part), "{name}: the summaries' keys differ");
    for (key, value) in whole {
        if key != "wall_seconds" {
            assert_eq!(&part[key], value, "{name}: `{key}` differs after resume");
        }
    }
}

/// `--resume` of the run in `dir`, which has completed, succeeds and
/// leaves every file as it was (the summary's counters included), with a
/// note that the run is complete.
fn resume_of_a_completed_run_changes_nothing(name: &str, dir: &Path, file: &Path) {
    let read_all = || -> Vec<(std::ffi::OsString, Vec<u8>)> {
        let mut files: Vec<_> = std::fs::read_dir(dir)
            .expect("dir")
            .map(|e| e.expect("entry"))
            .map(|e| (e.file_name(), std::fs::read(e.path()).expect("file")))
            .collect();
        files.sort();
        files
    };
    let before = read_all();
    let again = Command::new(binary())
        .args(["run", "--resume"])
        .arg(dir)
        .arg(file)
        .output()
        .expect("resume a completed run");
    let err = String::from_utf8_lossy(&again.stderr);
    assert!(again.status.success(), "{name}: {err}");
    assert!(err.contains("already complete"), "{name}: {err}");
    assert!(
        read_all() == before,
        "{name}: resuming the completed run changed its files"
    );
}

/// A mechanics run long enough to be interrupted (a few seconds).
const DOUBLE_PENDULUM: &str = r#"
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
"#;

#[test]
fn mechanics_run_survives_sigterm_and_resumes_bit_for_bit() {
    interrupt_and_resume(
        "mechanics",
        &format!("{DOUBLE_PENDULUM}checkpoint_every = 5000\n"),
        &TRAJECTORY,
    );
}

/// A run interrupted twice (by `--time-limit`) and resumed twice counts
/// every part: its summary is that of the run done in one go, counters
/// included (each checkpoint carries those of the parts before it).
#[test]
fn counters_add_up_over_two_interruptions() {
    let dir = Scratch::new("twice");
    let file = dir.join("scenario.toml");
    // Fifteen times the other tests' run (about 7 s here, few rows), so that
    // two parts of 0.5 s cannot finish it even on a much faster machine.
    let long = DOUBLE_PENDULUM
        .replace("steps = 400000", "steps = 6000000")
        .replace("every = 7", "every = 1000");
    std::fs::write(&file, format!("{long}checkpoint_every = 5000\n")).expect("scenario");
    let run = |args: &[&std::ffi::OsStr]| {
        Command::new(binary())
            .args(["run", "--quiet"])
            .args(args)
            .arg(&file)
            .status()
            .expect("run")
    };
    let (whole, part) = (dir.join("whole"), dir.join("part"));
    assert!(run(&["--out".as_ref(), whole.as_ref()]).success());
    let limit: [&std::ffi::OsStr; 2] = ["--time-limit".as_ref(), "0.5".as_ref()];
    assert!(!run(&[&limit[..], &["--out".as_ref(), part.as_ref()]].concat()).success());
    assert_eq!(summary(&part)["status"], "interrupted");
    assert!(!run(&[&limit[..], &["--resume".as_ref(), part.as_ref()]].concat()).success());
    assert_eq!(summary(&part)["status"], "interrupted", "the second part finished");
    assert!(run(&["--resume".as_ref(), part.as_ref()]).success());
    same_summary("twice", &summary(&whole), &summary(&part));
    std::fs::remove_dir_all(&dir).ok();
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
        &TRAJECTORY,
    );
}

const LATTICE: Files = Files {
    watch: "energy.csv",
    watch_bytes: 100_000,
    paired: ("snapshot_times.csv", "snapshots.npy", 64),
    compared: &["energy.csv", "snapshots.npy", "snapshot_times.csv", "energy_blocks.csv"],
    args: &[],
    changed: None,
};

#[test]
fn lattice_field_run_survives_sigterm_and_resumes_bit_for_bit() {
    // The fast path (sine-Gordon triangles, periodic, re-centred mod 2π).
    interrupt_and_resume(
        "lattice-fast",
        r#"
[model]
name = "sine-gordon"
[lattice]
nodes = 64
length = 16.0
boundary = "periodic"
courant = 0.25
[method]
scheme = "triangle"
[initial]
kind = "kink-antikink"
[time]
t_end = 30000.0
[output]
snapshot_every = 997
energy_every = 3
energy_block = 1000
plots = false
checkpoint_every = 20000
"#,
        &LATTICE,
    );
}

#[test]
fn generic_lattice_run_survives_sigterm_and_resumes_bit_for_bit() {
    // The generic path (symmetric rectangles, fixed ends: a whole-level Newton solve).
    interrupt_and_resume(
        "lattice-generic",
        r#"
[model]
name = "wave"
[lattice]
nodes = 64
length = 10.0
boundary = "dirichlet"
courant = 0.5
[method]
scheme = "symmetric-rectangle"
[initial]
kind = "dalembert"
amplitude = 0.5
mode = 1
[time]
t_end = 2000.0
[output]
snapshot_every = 101
energy_every = 1
energy_block = 250
plots = false
checkpoint_every = 3000
"#,
        &LATTICE,
    );
}

#[test]
fn cfk_lattice_run_survives_sigterm_and_resumes_bit_for_bit() {
    // The vertex-by-vertex Cauchy integrator on a periodic 2+1 CFK lattice.
    interrupt_and_resume(
        "cfk",
        r#"
[model]
name = "klein-gordon-complex"
[lattice]
kind = "cfk"
space_dimension = 2
nodes = [12, 12]
spacing = 0.5
courant = 0.4
[initial]
kind = "plane-wave"
amplitude = 0.5
[time]
t_end = 250.0
[output]
snapshot_every = 97
checkpoint_every = 100
plots = false
"#,
        &Files {
            watch: "momentum.csv",
            watch_bytes: 10_000,
            paired: ("snapshot_times.csv", "snapshots.npy", 12 * 12 * 2),
            compared: &["energy.csv", "momentum.csv", "snapshots.npy", "snapshot_times.csv"],
            args: &[],
            changed: Some(("amplitude = 0.5", "amplitude = 0.6", "initial.amplitude")),
        },
    );
}

#[test]
fn checkpoints_by_wall_time_resume_bit_for_bit() {
    // No `checkpoint_every`: only the clock writes checkpoints before the end.
    interrupt_and_resume(
        "clock",
        DOUBLE_PENDULUM,
        &Files {
            args: &["--checkpoint-seconds", "0.2"],
            changed: Some(("dt = 0.001", "dt = 0.002", "method.dt")),
            ..TRAJECTORY
        },
    );
}

#[test]
fn rod_run_survives_sigterm_and_resumes_bit_for_bit() {
    // The Cosserat rod: the Cauchy march on ℝ³ × SO(3) (checkpoint words by
    // the fibre's coordinates) and the observer's momentum balance sums.
    interrupt_and_resume(
        "rod",
        r#"
[model]
name = "cosserat-rod"
length = 1.0
nodes = 31
radius = 0.02
density = 1000.0
young = 1e5
poisson = 0.5
[loads]
gravity = [0.0, 0.0, -9.81]
damping = 0.1
end_force = [0.001, 0.0, 0.0]
ramp = 1.0
[initial]
shape = "bent"
curvature = 1.0
angular_velocity = [0.0, 0.5, 1.0]
[time]
t_end = 30.0
[output]
every = 10
checkpoint_every = 500
plots = false
"#,
        &Files {
            watch: "momentum.csv",
            watch_bytes: 20_000,
            paired: ("momentum.csv", "centerline.npy", 31 * 3),
            compared: &["momentum.csv", "energy.csv", "centerline.npy", "frames.npy"],
            args: &[],
            changed: Some(("young = 1e5", "young = 2e5", "model.young")),
        },
    );
}

#[test]
fn clamped_rod_run_resumes_its_tip_and_reaction_bit_for_bit() {
    // A damped cantilever under an end force: the support's impulse and the
    // first row of the centreline travel in the checkpoint.
    interrupt_and_resume(
        "rod-clamped",
        r#"
[model]
name = "cosserat-rod"
length = 1.0
nodes = 41
radius = 0.05
density = 1000.0
young = 1e5
poisson = 0.5
[ends]
start = "clamped"
[loads]
damping = 13.8
end_force = [0.0146, 0.0, 0.0]
ramp = 1.0
[time]
t_end = 60.0
[output]
every = 10
checkpoint_every = 500
plots = false
"#,
        &Files {
            watch: "momentum.csv",
            watch_bytes: 20_000,
            paired: ("momentum.csv", "centerline.npy", 41 * 3),
            compared: &["momentum.csv", "energy.csv", "centerline.npy", "frames.npy"],
            args: &[],
            changed: None,
        },
    );
}

#[test]
fn beam_run_survives_sigterm_and_resumes_bit_for_bit() {
    // Seed 000's time evolution on SE(3) with a clamped end (the rolling
    // three-level window rebuilt from the checkpoint).
    interrupt_and_resume(
        "beam",
        r#"
[model]
name = "beam"
length = 0.8
nodes = 21
width = 0.05
height = 0.05
density = 1000.0
young = 1e6
poisson = 0.3
[ends]
start = "clamped"
[initial]
shape = "bent"
curvature = 1.0
[time]
t_end = 1.0
[output]
every = 2
checkpoint_every = 50
plots = false
"#,
        &Files {
            watch: "momentum.csv",
            watch_bytes: 20_000,
            paired: ("momentum.csv", "frames.npy", 21 * 12),
            compared: &["momentum.csv", "energy.csv", "frames.npy", "centerline.npy"],
            args: &[],
            changed: None,
        },
    );
}

#[test]
fn run_time_dimension_run_survives_sigterm_and_resumes_bit_for_bit() {
    // A custom chain of 8 coordinates (beyond the fixed-size path): the kept
    // Jacobian of its simplified Newton iteration travels in the checkpoint.
    let names: Vec<String> = (0..8).map(|i| format!("x{i}")).collect();
    let kinetic: Vec<String> = names.iter().map(|x| format!("{x}_dot^2")).collect();
    let springs: Vec<String> = names
        .windows(2)
        .map(|w| format!("0.5*({1} - {0})^2 + 0.25*({1} - {0})^4", w[0], w[1]))
        .collect();
    let quoted: Vec<String> = names.iter().map(|x| format!("\"{x}\"")).collect();
    let q: Vec<String> = (0..8).map(|i| format!("{}", 0.3 * (i as f64).sin())).collect();
    let text = format!(
        "[model]\nname = \"custom\"\ncoordinates = [{}]\nlagrangian = \"0.5*({}) - ({})\"\n\
         [method]\nname = \"galerkin-gauss\"\nstages = 2\ndt = 0.01\n[time]\nsteps = 60000\n\
         [initial]\nq = [{}]\np = [0.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.1]\n\
         [output]\nevery = 7\nformats = [\"csv\", \"npy\"]\nplots = false\ncheckpoint_every = 2000\n",
        quoted.join(", "),
        kinetic.join(" + "),
        springs.join(" + "),
        q.join(", ")
    );
    interrupt_and_resume("run-time-dimension", &text, &TRAJECTORY);
}

/// Runs the scenario `text`, written to `dir/name.toml`, with `args`.
fn run_to(dir: &Scratch, name: &str, text: &str, args: &[&str]) -> std::process::Output {
    let file = dir.join(format!("{name}.toml"));
    std::fs::write(&file, text).expect("scenario");
    Command::new(binary())
        .args(["run", "--quiet"])
        .args(args)
        .arg(&file)
        .output()
        .expect("run")
}

/// A finished run is extended by a longer `t_end` that keeps its step: the
/// files then equal those of one run to the longer end. A `t_end` that
/// would land with another step (t_end/round(t_end/dt)) is refused naming
/// `time.t_end`, and the files stay as they were; so is a shorter one.
#[test]
fn a_finished_run_extends_with_its_own_step() {
    let dir = Scratch::new("extend");
    let run = |name: &str, t_end: &str, args: &[&str]| {
        run_to(
            &dir,
            name,
            &format!(
                "[model]\nname = \"kepler\"\n[method]\nname = \"midpoint\"\ndt = 0.01\n[time]\nt_end = {t_end}\n\
                 [output]\nformats = [\"csv\", \"npy\"]\nplots = false\n"
            ),
            args,
        )
    };
    let (whole, part) = (dir.join("whole"), dir.join("part"));
    let path = |p: &Path| p.to_str().expect("utf-8 path").to_owned();
    assert!(run("whole", "2.0", &["--out", &path(&whole)]).status.success());
    assert!(run("part", "1.0", &["--out", &path(&part)]).status.success());
    let files = ["trajectory.csv", "trajectory.npy"];
    let before: Vec<Vec<u8>> = files
        .iter()
        .map(|f| std::fs::read(part.join(f)).expect("file"))
        .collect();
    let refused = run("odd", "2.005", &["--resume", &path(&part)]);
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success() && err.contains("time.t_end") && err.contains("dt"),
        "{err}"
    );
    for (f, b) in files.iter().zip(&before) {
        assert!(
            &std::fs::read(part.join(f)).expect("file") == b,
            "{f} touched by a refused resume"
        );
    }
    assert!(run("longer", "2.0", &["--resume", &path(&part)]).status.success());
    let shorter = run("shorter", "0.5", &["--resume", &path(&part)]);
    let err = String::from_utf8_lossy(&shorter.stderr);
    assert!(
        !shorter.status.success() && err.contains("time.t_end") && err.contains("shorten"),
        "{err}"
    );
    assert_eq!(summary(&part)["t_final"], summary(&whole)["t_final"]);
    for f in files {
        let (a, b) = (
            std::fs::read(whole.join(f)).expect("whole"),
            std::fs::read(part.join(f)).expect("extended"),
        );
        assert!(a == b, "{f} differs after the extension");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A variable-step run (SEM), stopped by time, resumed: to a `t_end` before
/// the checkpoint's time it is refused naming `time.t_end`, with its files
/// untouched; to its own `t_end` (its last step may pass it) and to a later
/// one it is taken, and the extension gives the bytes of one run to the
/// later `t_end`.
#[test]
fn a_variable_step_run_cannot_be_resumed_to_an_earlier_end() {
    let dir = Scratch::new("variable-end");
    let run = |name: &str, t_end: &str, args: &[&str]| {
        run_to(
            &dir,
            name,
            &format!(
                "[model]\nname = \"kepler\"\nparams = {{ eccentricity = 0.5 }}\n[method]\nname = \"sem-averaged\"\n\
                 stages = 2\ndt = 0.01\n[time]\nt_end = {t_end}\n[output]\nformats = [\"csv\"]\nplots = false\n"
            ),
            args,
        )
    };
    let (whole, part) = (dir.join("whole"), dir.join("part"));
    let path = |p: &Path| p.to_str().expect("utf-8 path").to_owned();
    assert!(run("whole", "2.0", &["--out", &path(&whole)]).status.success());
    assert!(run("part", "1.0", &["--out", &path(&part)]).status.success());
    let before = std::fs::read(part.join("trajectory.csv")).expect("file");
    let shorter = run("shorter", "0.5", &["--resume", &path(&part)]);
    let err = String::from_utf8_lossy(&shorter.stderr);
    assert!(
        !shorter.status.success() && err.contains("time.t_end") && err.contains("shorten"),
        "{err}"
    );
    assert!(
        std::fs::read(part.join("trajectory.csv")).expect("file") == before,
        "trajectory.csv touched by a refused resume"
    );
    let same = run("same", "1.0", &["--resume", &path(&part)]);
    assert!(same.status.success(), "{}", String::from_utf8_lossy(&same.stderr));
    assert!(run("longer", "2.0", &["--resume", &path(&part)]).status.success());
    assert_eq!(summary(&part)["t_final"], summary(&whole)["t_final"]);
    assert!(
        std::fs::read(whole.join("trajectory.csv")).expect("whole")
            == std::fs::read(part.join("trajectory.csv")).expect("extended"),
        "trajectory.csv differs after the extension"
    );
    std::fs::remove_dir_all(&dir).ok();
}
