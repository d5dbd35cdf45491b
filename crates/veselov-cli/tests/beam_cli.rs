//! The beam kind of `veselov run` (`[model] name = "beam"`, seed 000): time
//! and space evolution from the command line, outputs, the momentum maps read
//! back, the step limit and errors naming the key.

use std::path::{Path, PathBuf};

use assert_cmd::Command;

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("veselov-beam-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn example(name: &str) -> String {
    std::fs::read_to_string(workspace_root().join("examples").join(name)).expect("example")
}

/// Replace the first line starting with `key =`.
fn set(text: &str, key: &str, value: &str) -> String {
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

fn run(name: &str, text: &str) -> (bool, String, PathBuf) {
    let dir = temp_dir(name);
    let file = dir.join("scenario.toml");
    std::fs::write(&file, text).expect("write");
    let out = dir.join("out");
    let o = Command::cargo_bin("veselov")
        .expect("binary")
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(&file)
        .output()
        .expect("run");
    (o.status.success(), String::from_utf8_lossy(&o.stderr).into_owned(), out)
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).expect("summary")).expect("json")
}

fn rows(path: &Path) -> (String, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).expect("csv");
    let mut lines = text.lines();
    let header = lines.next().expect("header").to_string();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.trim().parse::<f64>().expect("number")).collect())
        .collect();
    (header, rows)
}

fn npy_shape(path: &Path) -> Vec<usize> {
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

#[test]
fn free_free_time_evolution_keeps_its_momentum_map() {
    let text = set(&example("beam_free_free.toml"), "t_end", "0.05");
    let (ok, err, out) = run("free", &text);
    assert!(ok, "{err}");
    let s = summary(&out);
    assert_eq!(s["status"], "ok");
    let (header, m) = rows(&out.join("momentum.csv"));
    assert_eq!(header, "level,t,J_wx,J_wy,J_wz,J_vx,J_vy,J_vz");
    assert_eq!(npy_shape(&out.join("frames.npy")), [m.len(), 21, 12]);
    let last = &m[m.len() - 1];
    assert!((last[1] - 0.05).abs() < 1e-12, "ends at t_end: {}", last[1]);
    // Relative to the size of the momentum terms Σ|J^k| (the map itself is
    // zero for a beam released at rest).
    assert!(s["momentum_map_drift"].as_f64().expect("drift") <= 1e-10, "{s}");
    let (eh, e) = rows(&out.join("energy.csv"));
    assert_eq!(eh, "level,t,energy");
    assert!(e.iter().all(|r| r[2].is_finite() && r[2] > 0.0));
    for plot in ["centerline_xz.svg", "centerline_yz.svg", "momentum.svg", "energy.svg"] {
        assert!(out.join(plot).exists(), "no {plot}");
    }
}

#[test]
fn paper_space_evolution_well_posed_reaches_the_end_and_literal_stops_cleanly() {
    let (ok, err, out) = run("well-posed", &example("beam_paper_space_well_posed.toml"));
    assert!(ok, "{err}");
    let s = summary(&out);
    assert_eq!(s["levels"], 40);
    assert!(s["momentum_map_drift"].as_f64().expect("drift") <= 1e-10, "{s}");
    let (header, m) = rows(&out.join("momentum.csv"));
    assert!(header.starts_with("level,s,"));
    assert!((m[m.len() - 1][1] - 0.8).abs() < 1e-12);
    assert_eq!(npy_shape(&out.join("frames.npy")), [m.len(), 52, 12]);
    let (ok, err, out) = run("literal", &example("beam_paper_space.toml"));
    assert!(!ok && err.starts_with("error: ") && err.contains("(j, a)"), "{err}");
    assert!(!err.contains("panicked"));
    assert_eq!(summary(&out)["status"], "error");
    assert!(
        !rows(&out.join("momentum.csv")).1.is_empty(),
        "the columns computed are kept"
    );
}

#[test]
fn step_limit_is_enforced_unless_overridden() {
    let text = set(&example("beam_free_free.toml"), "t_end", "0.05\ndt = 0.01");
    let (ok, err, _) = run("fast", &text);
    assert!(
        !ok && err.contains("time.dt") && err.contains("allow_unstable"),
        "{err}"
    );
    let forced = text.replace("[method]", "[method]\nallow_unstable = true");
    let (_, err, out) = run("forced", &forced);
    assert!(err.starts_with("warning"), "{err}");
    assert!(!err.contains("panicked"));
    let (_, m) = rows(&out.join("momentum.csv"));
    assert!(m.iter().flatten().all(|x| x.is_finite()));
}

#[test]
fn bad_beam_input_names_the_key() {
    let base = example("beam_free_free.toml");
    let space = example("beam_paper_space_well_posed.toml");
    let cases = [
        (set(&base, "young", "-1.0"), "model.young"),
        (set(&base, "nodes", "2"), "model.nodes"),
        (base.replace("[time]", "[time]\nsteps = 3"), "steps"),
        (set(&base, "evolution", "\"diagonal\""), "method.evolution"),
        (set(&base, "retraction", "\"quaternion\""), "method.retraction"),
        (set(&base, "shape", "\"paper\""), "initial.shape"),
        (set(&space, "nodes", "21"), "model.nodes"),
        (
            space.replace("[initial]", "[ends]\nstart = \"clamped\"\n\n[initial]"),
            "ends.start",
        ),
        (
            base.replace("[initial]", "[loads]\ndamping = [0, 0, 0, -1, 0, 0]\n\n[initial]"),
            "loads.damping[3]",
        ),
    ];
    for (text, key) in cases {
        let (ok, err, _) = run("bad", &text);
        assert!(!ok && err.contains(key), "expected an error naming {key}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}
