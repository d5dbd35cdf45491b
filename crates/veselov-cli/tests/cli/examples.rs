//! The shipped examples and benchmark scenarios: each runs, writes to its own
//! directory, and accepts either spelling of the method key.

use std::path::{Path, PathBuf};

use crate::common::{self, Scratch, run_scenario, scenario, summary, workspace_root};
use crate::shared::{shorten, with_time_table};

/// Runs the example `name` as rewritten to `text` into `dir/out`, which
/// must succeed with status ok; the output directory and the summary.
fn run_ok(name: &str, text: &str, dir: &Path) -> (PathBuf, serde_json::Value) {
    let file = scenario(dir, text);
    let out = dir.join("out");
    run_scenario(&out, &file).success();
    let s = summary(&out);
    assert_eq!(s["status"], "ok", "{name}: {s}");
    (out, s)
}

/// A lattice-field example, run to t = 1: its outputs exist and agree with
/// one another.
fn check_field_example(name: &str, original: &str, dir: &Path) {
    let text = with_time_table(original, "t_end = 1.0\n");
    let (out, s) = run_ok(name, &text, dir);
    assert!(s["t_final"].as_f64().expect("t_final") >= 1.0, "{name}");
    let csv = std::fs::read_to_string(out.join("energy.csv")).expect("energy.csv");
    assert!(csv.starts_with("t,energy"), "{name}");
    let npy = std::fs::read(out.join("snapshots.npy")).expect("snapshots.npy");
    assert!(npy.starts_with(b"\x93NUMPY"), "{name}");
    let plots: &[&str] = if text.contains("kind = \"cfk\"") {
        let momentum = std::fs::read_to_string(out.join("momentum.csv")).expect("momentum.csv");
        assert!(momentum.starts_with("t,p_x,p_y"), "{name}");
        &["field_0.png", "energy_error.svg"]
    } else {
        &["spacetime.png", "final_waveform.svg", "energy_error.svg"]
    };
    for plot in plots {
        assert!(out.join(plot).exists(), "{name}: no {plot}");
    }
}

/// A beam example: time evolution for 10 levels, space evolution as
/// shipped. The literal seed 000 §5 data stop at a vertex-solve failure,
/// which must be reported cleanly with the columns computed kept.
fn check_beam_example(name: &str, original: &str, dir: &Path) {
    let text = original.replace("t_end = 0.4 ", "t_end = 0.0125 ");
    let file = scenario(dir, &text);
    let out = dir.join("out");
    let run = run_scenario(&out, &file);
    let s = summary(&out);
    if original.contains("shape = \"paper\"") {
        run.failure();
        assert_eq!(s["status"], "error", "{name}: {s}");
    } else {
        run.success();
        assert_eq!(s["status"], "ok", "{name}: {s}");
    }
    for file in ["frames.npy", "momentum.csv", "energy.csv"] {
        assert!(out.join(file).exists(), "{name}: no {file}");
    }
}

/// A rod example, run to t = 0.004 in steps of 0.2 ms (within every
/// example's step limit): 20 steps from t = 0, or 19 from t = Δt for an
/// initial motion given by expressions in s and t (whose clock starts at
/// the lattice's first level, Δt before the first cut); status ok and every
/// output present.
fn check_rod_example(name: &str, original: &str, dir: &Path) {
    let text = with_time_table(original, "t_end = 0.004\ndt = 0.0002\n");
    let (out, s) = run_ok(name, &text, dir);
    let by_expressions = original.contains("\nrotation_vector = ");
    let t_start = s["t_start"].as_f64().expect("t_start");
    assert!(
        (t_start - if by_expressions { 0.0002 } else { 0.0 }).abs() < 1e-18,
        "{name}: {s}"
    );
    assert_eq!(s["time_steps"], if by_expressions { 19 } else { 20 }, "{name}");
    for file in [
        "centerline.npy",
        "frames.npy",
        "momentum.csv",
        "energy.csv",
        "momentum.svg",
    ] {
        assert!(out.join(file).exists(), "{name}: no {file}");
    }
}

#[test]
fn every_example_runs() {
    let examples = std::fs::read_dir(workspace_root().join("examples")).expect("examples dir");
    let mut count = 0;
    for entry in examples {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("example")
            .to_string();
        let dir = Scratch::new(&format!("example-{name}"));
        let original = std::fs::read_to_string(&path).expect("read example");
        if original.contains("[lattice]") {
            check_field_example(&name, &original, &dir);
            count += 1;
            continue;
        }
        if original.contains("name = \"beam\"") {
            check_beam_example(&name, &original, &dir);
            count += 1;
            continue;
        }
        if original.contains("\"cosserat-rod\"") {
            check_rod_example(&name, &original, &dir);
            count += 1;
            continue;
        }
        let text = shorten(&original, 40);
        let file = scenario(&dir, &text);
        let out = dir.join("out");
        run_scenario(&out, &file).success();
        let s = summary(&out);
        assert_eq!(s["status"], "ok", "{name}: {s}");
        assert_eq!(s["steps"], 40, "{name}");
        let csv = std::fs::read_to_string(out.join("trajectory.csv")).expect("trajectory.csv");
        let rigid = csv.starts_with("t,R00,");
        let header: Vec<&str> = csv.lines().next().unwrap_or_default().split(',').collect();
        // The first coordinate's momentum column is `p_<name>`.
        assert!(
            header.len() > 2 && header.contains(&format!("p_{}", header[1]).as_str()) || rigid,
            "{name}: {}",
            csv.lines().next().unwrap_or_default()
        );
        // Forced runs (a `work` column) plot the energy balance instead.
        let energy_plot = if csv.lines().next().is_some_and(|h| h.ends_with(",work")) {
            "energy_balance.svg"
        } else {
            "energy_error.svg"
        };
        assert!(out.join(energy_plot).exists(), "{name}: no {energy_plot}");
        if rigid {
            assert!(out.join("body_momentum.svg").exists(), "{name}: no body momentum plot");
        } else {
            assert!(out.join("phase.svg").exists(), "{name}: no phase plot");
        }
        count += 1;
    }
    assert!(count >= 5, "only {count} examples found");
}

#[test]
fn every_example_writes_to_its_own_directory() {
    let mut seen = std::collections::BTreeMap::new();
    for entry in std::fs::read_dir(workspace_root().join("examples")).expect("examples dir") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("read");
        let value: toml::Value = toml::from_str(&text).expect("valid TOML");
        // `[output] dir`, or by default `out/<file stem>`.
        let dir = value
            .get("output")
            .and_then(|o| o.get("dir"))
            .and_then(|d| d.as_str())
            .map(PathBuf::from)
            .unwrap_or_else(|| Path::new("out").join(path.file_stem().expect("stem")));
        if let Some(other) = seen.insert(dir.clone(), path.clone()) {
            panic!(
                "{} and {} both write to {}",
                other.display(),
                path.display(),
                dir.display()
            );
        }
    }
    assert!(seen.len() >= 20, "only {} examples", seen.len());
}

#[test]
fn method_key_is_spelled_name_or_scheme_in_every_kind() {
    // Mechanics with `scheme`, a lattice with `name`: the same runs as the
    // shipped spellings.
    let cases = [
        (
            "kepler.toml",
            "name = \"galerkin-gauss\"",
            "scheme = \"galerkin-gauss\"",
        ),
        ("wave.toml", "scheme = ", "name = "),
    ];
    for (file, from, to) in cases {
        let original = std::fs::read_to_string(workspace_root().join("examples").join(file)).expect("example");
        assert!(original.contains(from), "{file} spells {from}");
        let dir = Scratch::new(&format!("spelling-{file}"));
        let text = original.replacen(from, to, 1);
        let text = if original.contains("[lattice]") {
            text.replace("t_end = ", "t_end = 1.0 #")
        } else {
            shorten(&text, 20)
        };
        let out = dir.join("out");
        run_scenario(&out, scenario(&dir, &text)).success();
        assert_eq!(summary(&out)["status"], "ok", "{file}");
    }
}

/// The scenarios that repeat the mechanics benchmarks as whole `veselov run`
/// processes (`crates/veselov/benches/scenarios/`, see the README) are valid
/// and take the path their benchmark measures: shortened to 2000 steps, each
/// completes, and ∇V evaluations are counted exactly on the built-in
/// separable models.
#[test]
fn benchmark_scenarios_run() {
    let dir = workspace_root().join("crates/veselov/benches/scenarios");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("scenarios")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 10, "{files:?}");
    for file in files {
        let text = std::fs::read_to_string(&file).expect("read");
        let dt: f64 = text
            .lines()
            .find_map(|l| l.strip_prefix("dt = "))
            .and_then(|v| v.trim().parse().ok())
            .expect("dt");
        let short = common::set(&text, "t_end", &format!("{}", 2000.0 * dt));
        let name = file.file_stem().expect("stem").to_string_lossy().to_string();
        let (ok, stderr, run_dir) = common::run(&format!("bench-{name}"), &short);
        assert!(ok, "{name}: {stderr}");
        let s = summary(&run_dir);
        assert_eq!(s["status"], "ok", "{name}: {s}");
        assert_eq!(s["steps"], 2000, "{name}: {s}");
        let counted = !s["force_evaluations_mean"].is_null();
        let separable = !text.contains("name = \"custom\"") && !text.contains("double-pendulum");
        assert_eq!(counted, separable, "{name}: {s}");
    }
}
