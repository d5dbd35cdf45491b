//! Mechanics runs: their outputs, forced runs' energy balance, fixed steps
//! landing on t_end, the Newton controls and output at chosen times.

use crate::common::{Scratch, run_scenario, scenario, succeeds, summary, veselov};
use crate::shared::{example_scenario, failing, relative_energy_error_is_stated};

#[test]
fn run_writes_npy_json_and_momentum_columns() {
    let dir = Scratch::new("kepler-npy");
    let file = example_scenario(&dir, "kepler", 100);
    let out = dir.join("out");
    run_scenario(&out, &file).success();
    let csv = std::fs::read_to_string(out.join("trajectory.csv")).expect("csv");
    assert_eq!(csv.lines().next(), Some("t,x,y,p_x,p_y,energy,J_angular"));
    let npy = std::fs::read(out.join("trajectory.npy")).expect("npy");
    assert_eq!(&npy[..6], b"\x93NUMPY");
    let rows = csv.lines().count() - 1;
    let header_len = 10 + u16::from_le_bytes([npy[8], npy[9]]) as usize;
    assert_eq!(npy.len() - header_len, rows * 7 * 8);
    let s = summary(&out);
    for key in [
        "status",
        "model",
        "method",
        "order",
        "dt",
        "steps",
        "t_final",
        "energy_initial",
        "energy_error_max",
        "momentum_error_max",
        "newton_iterations_mean",
        "wall_seconds",
    ] {
        assert!(s.get(key).is_some(), "summary lacks {key}: {s}");
    }
    assert_eq!(s["order"], 4);
    assert!(s["momentum_error_max"]["angular"].as_f64().expect("number") < 1e-13);
    relative_energy_error_is_stated(&s);
    assert!(out.join("orbit.svg").exists() && out.join("momentum_error.svg").exists());
    // `veselov plot` redraws from the CSV.
    std::fs::remove_file(out.join("orbit.svg")).expect("remove");
    veselov().arg("plot").arg(&out).assert().success();
    assert!(out.join("orbit.svg").exists());
}

/// A forced run's headline and plots show the energy balance, not the
/// dissipated energy as an "error"; a conservative run keeps its energy error.
#[test]
fn forced_runs_report_the_energy_balance() {
    let dir = Scratch::new("forced-headline");
    let file = example_scenario(&dir, "damped_kepler", 2000);
    let out = dir.join("out");
    let said = succeeds(veselov().args(["run", "--out"]).arg(&out).arg(&file));
    assert!(
        said.contains("max |E − E₀ − W| = ") && said.contains("energy balance"),
        "{said}"
    );
    assert!(!said.contains("max |E − E₀| ="), "{said}");
    for plot in ["energy_balance.svg", "energy_change.svg", "momentum_error.svg"] {
        assert!(out.join(plot).exists(), "{plot}");
    }
    assert!(!out.join("energy_error.svg").exists());
    let momentum = std::fs::read_to_string(out.join("momentum_error.svg")).expect("svg");
    assert!(momentum.contains("Momentum-map changes (forced system)"));
    let s = summary(&out);
    let balance = s["energy_balance_error_max"].as_f64().expect("number");
    assert!(
        balance < 1e-6 && s["work_of_forces"].as_f64().expect("number") < -1e-3,
        "{s}"
    );
    // Conservative: the energy error plot and headline as before.
    let file = example_scenario(&dir, "kepler", 200);
    let out = dir.join("conservative");
    let said = succeeds(veselov().args(["run", "--out"]).arg(&out).arg(&file));
    assert!(said.contains("max |E − E₀| = "), "{said}");
    assert!(out.join("energy_error.svg").exists() && !out.join("energy_balance.svg").exists());
}

/// One rule for the step count of a fixed-step run with `t_end`: round, and
/// adjust dt to land on t_end exactly, with a note. `t_end = 0.001` with
/// `dt = 0.01` is one step of 0.001 (it used to integrate to 0.01).
#[test]
fn fixed_step_runs_land_on_t_end() {
    let dir = Scratch::new("land-on-t-end");
    for (t_end, dt, steps) in [(0.001, 0.01, 1), (1.0, 0.3, 3), (1.0, 0.1, 10)] {
        let text = format!(
            "[model]\nname = \"pendulum\"\n[method]\nname = \"midpoint\"\ndt = {dt}\n[time]\nt_end = {t_end}\n\
             [initial]\nq = [1.0]\np = [0.0]\n"
        );
        let file = scenario(&dir, &text);
        let out = dir.join(format!("out-{steps}"));
        let said = succeeds(veselov().args(["run", "--out"]).arg(&out).arg(&file));
        let s = summary(&out);
        assert_eq!(s["steps"], steps, "{s}");
        let t_final = s["t_final"].as_f64().expect("number");
        assert!(
            (t_final - t_end).abs() <= 4.0 * f64::EPSILON * t_end,
            "{t_final} vs {t_end}"
        );
        let adjusted = (t_end / steps as f64 - dt).abs() > 1e-12 * dt;
        assert_eq!(said.contains("adjusted to"), adjusted, "{said}");
    }
}

/// `[method] newton_tolerance` and `newton_max_iterations` reach the Newton
/// iteration of a mechanics run: a looser tolerance takes fewer iterations, a
/// limit of one iteration fails the first step with a Newton failure (what
/// was computed is kept), and values out of range are refused naming the key.
#[test]
fn newton_controls_reach_the_iteration() {
    let dir = Scratch::new("newton-controls");
    let base = "[model]\nname = \"double-pendulum\"\n[method]\nname = \"galerkin-gauss\"\nstages = 2\ndt = 0.01\n";
    let rest = "[time]\nsteps = 100\n[initial]\nq = [0.5, -0.5]\np = [0.0, 0.0]\n";
    let run = |extra: &str, name: &str| {
        let file = scenario(&dir, &format!("{base}{extra}{rest}"));
        let out = dir.join(name);
        // A failing run exits non-zero but writes its summary.
        let _ = veselov()
            .args(["run", "--quiet", "--out"])
            .arg(&out)
            .arg(&file)
            .output();
        summary(&out)
    };
    let tight = run("", "default");
    let loose = run("newton_tolerance = 1e-6\n", "loose");
    assert_eq!(tight["status"], "ok");
    assert_eq!(loose["status"], "ok");
    let mean = |s: &serde_json::Value| s["newton_iterations_mean"].as_f64().expect("number");
    assert!(mean(&loose) < mean(&tight), "{} vs {}", mean(&loose), mean(&tight));
    let starved = run("newton_max_iterations = 1\n", "starved");
    assert_eq!(starved["status"], "error", "{starved}");
    assert_eq!(starved["failure"]["kind"], "newton_failure", "{starved}");
    for (bad, key) in [
        ("newton_tolerance = 0.5\n", "method.newton_tolerance"),
        ("newton_tolerance = 1e-20\n", "method.newton_tolerance"),
        ("newton_max_iterations = 0\n", "method.newton_max_iterations"),
    ] {
        let err = failing("newton-bad", &format!("{base}{bad}{rest}"));
        assert!(err.contains(key), "{bad}: {err}");
    }
}

/// A momentum conserved exactly (a free particle's translation momentum) is
/// drawn on a linear scale with a title that says so, not as an empty log plot.
#[test]
fn exactly_conserved_momentum_is_plotted_visibly() {
    let dir = Scratch::new("exact-momentum");
    let text = "[model]\nname = \"custom\"\ncoordinates = [\"x\"]\nlagrangian = \"0.5*x_dot^2\"\n\
                symmetries = { translation = [\"1\"] }\n[method]\nname = \"midpoint\"\ndt = 0.1\n[time]\nsteps = 20\n\
                [initial]\nq = [0.0]\np = [0.75]\n";
    let file = scenario(&dir, text);
    let out = dir.join("out");
    run_scenario(&out, &file).success();
    let svg = std::fs::read_to_string(out.join("momentum_error.svg")).expect("svg");
    assert!(svg.contains("exactly 0 at every row"), "title");
}

/// `[output] times` writes rows at the steps nearest the times asked for
/// (with a note off the grid) besides the first and last states; a time
/// outside the run, `times` with `every`, or `times` on a variable-step run
/// are refused naming the key, before any output directory is made.
#[test]
fn output_at_chosen_times() {
    let dir = Scratch::new("output-times");
    let base = "[model]\nname = \"pendulum\"\n[method]\nname = \"midpoint\"\ndt = 0.1\n[time]\nt_end = 1.0\n\
                [initial]\nq = [1.0]\np = [0.0]\n[output]\n";
    let file = scenario(&dir, &format!("{base}times = [0.5, 0.25, 0.7]\n"));
    let out = dir.join("out");
    let said = succeeds(veselov().args(["run", "--out"]).arg(&out).arg(&file));
    assert!(said.contains("0.25 written at the nearest step"), "{said}");
    let csv = std::fs::read_to_string(out.join("trajectory.csv")).expect("csv");
    let times: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().expect("t").parse().expect("number"))
        .collect();
    let want = [0.0, 0.3, 0.5, 0.7, 1.0];
    assert_eq!(times.len(), want.len(), "{csv}");
    assert!(times.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-12), "{times:?}");
    for (bad, name) in [("times = [1.5]\n", "late"), ("times = [0.5]\nevery = 2\n", "both")] {
        let err = failing(&format!("times-{name}"), &format!("{base}{bad}"));
        assert!(err.contains("output.times"), "{bad}: {err}");
    }
    let sem = base.replace("midpoint", "sem-midpoint");
    let err = failing("times-sem", &format!("{sem}times = [0.5]\n"));
    assert!(err.contains("output.times") && err.contains("variable-step"), "{err}");
}
