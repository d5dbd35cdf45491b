//! Bad inputs and output directories: one clear message per fault, short
//! even for huge inputs, partial results kept, and what `--force` removes.

use std::path::Path;

use crate::common::{self, Scratch, run, run_scenario, scenario, succeeds, summary, verify_command, veselov};
use crate::shared::failing;

const KEPLER: &str = "[model]\nname = \"kepler\"\n[method]\nname = \"midpoint\"\ndt = 0.01\n[time]\nsteps = 10\n";

#[test]
fn bad_input_gives_one_clear_message() {
    let cases: &[(&str, String, &[&str])] = &[
        ("unknown-key", format!("{KEPLER}[output]\ncolour = \"red\"\n"), &["scenario.toml", "colour"]),
        ("unknown-model", KEPLER.replace("\"kepler\"", "\"kepplr\""), &["model.name", "kepplr", "expected one of", "cosserat-rod"]),
        // Named before the missing tables of the kind it looks like.
        ("near-model-name", "[model]\nname = \"Cosserat_Rod\"\nlength = 1.0\n".into(), &["model.name", "did you mean `cosserat-rod`"]),
        ("unknown-method", KEPLER.replace("\"midpoint\"", "\"rk4\""), &["method.name", "rk4"]),
        ("unknown-param", KEPLER.replace("name = \"kepler\"", "name = \"kepler\"\nparams = { ecc = 0.2 }"), &["model.params.ecc", "eccentricity"]),
        ("wrong-type", KEPLER.replace("dt = 0.01", "dt = \"small\""), &["dt", "scenario.toml"]),
        ("missing-key", KEPLER.replace("dt = 0.01\n", ""), &["dt"]),
        ("dt-zero", KEPLER.replace("dt = 0.01", "dt = 0.0"), &["method.dt", "> 0"]),
        ("dt-negative", KEPLER.replace("dt = 0.01", "dt = -1.0"), &["method.dt"]),
        ("dt-nan", KEPLER.replace("dt = 0.01", "dt = nan"), &["method.dt"]),
        ("dimension", format!("{KEPLER}[initial]\nq = [1.0, 0.0, 0.0]\np = [0.0, 1.0]\n"), &["initial.q", "expected 2 numbers"]),
        ("non-finite-initial", format!("{KEPLER}[initial]\nq = [1.0, inf]\np = [0.0, 1.0]\n"), &["initial.q[1]", "finite"]),
        ("bad-eccentricity", KEPLER.replace("name = \"kepler\"", "name = \"kepler\"\nparams = { eccentricity = 1.5 }"), &["eccentricity", "[0, 1)"]),
        ("overflowing-inertia", KEPLER.replace("name = \"kepler\"", "name = \"pendulum\"\nparams = { length = 1e300 }").replace("[time]", "[initial]\nq = [1.0]\np = [0.0]\n[time]"), &["model.params", "mass·length²"]),
        ("stages-on-midpoint", KEPLER.replace("dt = 0.01", "dt = 0.01\nstages = 3"), &["method.stages"]),
        ("too-many-stages", KEPLER.replace("\"midpoint\"", "\"galerkin-gauss\"\nstages = 99"), &["method.stages"]),
        (
            "parse-error",
            "[model]\nname = \"custom\"\ncoordinates = [\"x\"]\nlagrangian = \"0.5*x_dot^2 - (x^2\"\n[method]\nname = \"midpoint\"\ndt = 0.1\n[time]\nsteps = 5\n[initial]\nq = [1.0]\np = [0.0]\n".into(),
            &["model.lagrangian", "column", "^"],
        ),
        (
            "unknown-variable",
            "[model]\nname = \"custom\"\ncoordinates = [\"x\"]\nlagrangian = \"0.5*y_dot^2\"\n[method]\nname = \"midpoint\"\ndt = 0.1\n[time]\nsteps = 5\n[initial]\nq = [1.0]\np = [0.0]\n".into(),
            &["model.lagrangian", "y_dot"],
        ),
        (
            "degenerate-lagrangian",
            "[model]\nname = \"custom\"\ncoordinates = [\"x\"]\nlagrangian = \"x*x_dot - 0.5*x^2\"\n[method]\nname = \"midpoint\"\ndt = 0.1\n[time]\nsteps = 5\n[initial]\nq = [1.0]\np = [0.0]\n".into(),
            &["model.lagrangian", "not finite"],
        ),
    ];
    for (name, text, needles) in cases {
        let err = failing(name, text);
        assert_eq!(
            err.lines().filter(|l| l.starts_with("error:")).count(),
            1,
            "{name}: {err}"
        );
        for n in *needles {
            assert!(err.contains(n), "{name}: message lacks `{n}`:\n{err}");
        }
    }
}

/// A huge input is not echoed back: a TOML syntax error on a 3 MB line and an
/// expression error in a 8 MB Lagrangian both give messages of a few hundred
/// bytes that still say where the fault is.
#[test]
fn errors_about_huge_inputs_stay_short() {
    let unquoted = format!(
        "[model]\nname = \"custom\"\ncoordinates = [\"x\"]\nlagrangian = {}\n",
        "x".repeat(3_000_000)
    );
    let err = failing("huge-toml", &unquoted);
    assert!(err.len() < 2000 && err.contains("line 4"), "{} bytes", err.len());
    let bad_expression = format!(
        "[model]\nname = \"custom\"\ncoordinates = [\"x\"]\nlagrangian = \"{}foo(x)\"\n[method]\nname = \"midpoint\"\n\
         dt = 0.1\n[time]\nsteps = 1\n[initial]\nq = [0.0]\np = [0.0]\n",
        "x + ".repeat(2_000_000)
    );
    let err = failing("huge-expression", &bad_expression);
    assert!(
        err.len() < 2000 && err.contains("model.lagrangian") && err.contains("unknown function `foo`"),
        "{} bytes",
        err.len()
    );
}

#[test]
fn unwritable_or_non_empty_output_directory_is_refused() {
    let dir = Scratch::new("outdir");
    let file = scenario(&dir, KEPLER);
    // A path below a regular file cannot be created.
    std::fs::write(dir.join("blocker"), "x").expect("write");
    let out = run_scenario(dir.join("blocker/out"), &file).failure();
    assert!(String::from_utf8_lossy(&out.get_output().stderr).contains("blocker"));
    // First run succeeds; a second into the same directory is refused; --force overwrites.
    run_scenario(dir.join("o"), &file).success();
    let out = run_scenario(dir.join("o"), &file).failure();
    assert!(String::from_utf8_lossy(&out.get_output().stderr).contains("not empty"));
    veselov()
        .args(["run", "--quiet", "--force", "--out"])
        .arg(dir.join("o"))
        .arg(&file)
        .assert()
        .success();
}

/// The file names in `dir` (not subdirectories), sorted.
fn file_names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("output directory")
        .map(|e| e.expect("entry"))
        .filter(|e| e.file_type().expect("file type").is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Every kind of run writes only files `--force` knows as run outputs
/// (`output::is_run_output`, by which a directory of an earlier version is
/// cleaned), in both plot formats, and lists every one of them in its
/// `outputs.json` (by which `--force` cleans a directory now): a file a run
/// writes missing from either would survive a `--force` rerun of another
/// kind.
#[test]
fn every_file_a_run_writes_is_a_known_output() {
    let short = |file: &str, key: &str, value: &str| common::set(&common::example(file), key, value);
    let runs = [
        ("harmonic", short("harmonic.toml", "steps", "50")),
        ("damped", short("damped_oscillator.toml", "t_end", "1.0")),
        ("rigid", short("rigid_body.toml", "t_end", "1.0")),
        ("kepler", short("kepler.toml", "t_end", "1.0")),
        ("sine-gordon", short("sine_gordon.toml", "t_end", "1.0")),
        ("sine-gordon-2d", short("sine_gordon_2d.toml", "t_end", "0.5")),
        ("beam", short("beam_cantilever.toml", "t_end", "0.02")),
        ("rod", short("rod_free_tumbling.toml", "t_end", "0.05")),
    ];
    let mut seen = 0;
    for (name, text) in runs {
        for format in ["svg", "png"] {
            assert!(text.contains("[output]\n") && !text.contains("plot_format"), "{name}");
            let text = text.replacen("[output]\n", &format!("[output]\nplot_format = \"{format}\"\n"), 1);
            let (ok, stderr, out) = run(&format!("known-{name}-{format}"), &text);
            assert!(ok, "{name} ({format}): {stderr}");
            known_and_recorded(&format!("{name} ({format})"), &out);
            seen += file_names(&out).len();
        }
    }
    let dir = Scratch::new("known-verify");
    let file = scenario(&dir, &short("harmonic.toml", "steps", "50"));
    let out = dir.join("verify");
    succeeds(&mut verify_command("0.1,0.05", &out, &file));
    known_and_recorded("verify", &out);
    seen += file_names(&out).len();
    assert!(seen > 100, "{seen} files");
}

/// Every file of the run `name` in `out` but its record is a known output
/// and is listed in the record.
fn known_and_recorded(name: &str, out: &Path) {
    let recorded = veselov_cli::pipeline::manifest::recorded(out)
        .expect("a readable outputs.json")
        .expect("an outputs.json");
    for file in file_names(out) {
        if file == veselov_cli::pipeline::manifest::FILE {
            continue;
        }
        assert!(veselov_cli::output::is_run_output(&file), "{name} wrote {file}");
        assert!(recorded.contains(&file), "{name}: {file} is not in outputs.json");
    }
}

/// `--force` into the directory of an earlier run of another kind leaves
/// exactly the new run's outputs beside the user's own files: nothing of the
/// earlier run (a rod's centreline, frames, animation) is left to be taken
/// for the new run's.
#[test]
fn force_removes_the_outputs_of_an_earlier_run() {
    let dir = Scratch::new("force-kinds");
    let rod = scenario(
        &dir,
        &common::set(&common::example("rod_free_tumbling.toml"), "t_end", "0.05"),
    );
    let out = dir.join("out");
    succeeds(veselov().args(["run", "--quiet", "--out"]).arg(&out).arg(&rod));
    assert!(out.join("centerline.gif").exists() && out.join("frames.npy").exists());
    std::fs::write(out.join("notes.txt"), "mine").expect("write");
    std::fs::create_dir(out.join("keep")).expect("subdirectory");
    let harmonic = dir.join("harmonic.toml");
    std::fs::write(&harmonic, common::set(&common::example("harmonic.toml"), "steps", "50")).expect("write");
    succeeds(
        veselov()
            .args(["run", "--quiet", "--force", "--out"])
            .arg(&out)
            .arg(&harmonic),
    );
    let fresh = dir.join("fresh");
    succeeds(veselov().args(["run", "--quiet", "--out"]).arg(&fresh).arg(&harmonic));
    let mut expected = file_names(&fresh);
    expected.push("notes.txt".into());
    expected.sort();
    assert_eq!(file_names(&out), expected);
    assert!(out.join("keep").is_dir());
    assert_eq!(std::fs::read_to_string(out.join("notes.txt")).expect("kept"), "mine");
}

#[test]
fn failure_mid_run_keeps_partial_results() {
    // L = ½ẋ² + √(1 − x²): leaves the domain |x| < 1 after a few steps.
    let text = "[model]\nname = \"custom\"\ncoordinates = [\"x\"]\nlagrangian = \"0.5*x_dot^2 + sqrt(1 - x^2)\"\n\
                [method]\nname = \"midpoint\"\ndt = 0.1\n[time]\nsteps = 200\n[initial]\nq = [0.0]\np = [2.0]\n";
    let dir = Scratch::new("midway");
    let file = scenario(&dir, text);
    let out = dir.join("out");
    let res = run_scenario(&out, &file).failure();
    let err = String::from_utf8_lossy(&res.get_output().stderr).into_owned();
    assert!(err.contains("step"), "{err}");
    let s = summary(&out);
    assert_eq!(s["status"], "error");
    assert!(s["error"].as_str().expect("message").contains("step"));
    let steps = s["steps"].as_u64().expect("steps");
    assert!(steps > 0 && steps < 200, "{s}");
    let rows = std::fs::read_to_string(out.join("trajectory.csv"))
        .expect("csv")
        .lines()
        .count()
        - 1;
    assert_eq!(rows as u64, steps + 1);
}
