//! Custom models from a Lagrangian: against the built-in Kepler, declared
//! symmetries, column names, and models beyond six coordinates.

use crate::common::{Scratch, assert_mentions, csv, run, run_scenario, scenario, summary, veselov};
use crate::shared::failing;

#[test]
fn custom_kepler_matches_built_in_kepler() {
    let dir = Scratch::new("custom-vs-builtin");
    let shared_tables = "[method]\nname = \"galerkin-gauss\"\nstages = 3\ndt = 0.02\n[time]\nsteps = 300\n\
                  [initial]\nq = [0.4, 0.0]\np = [0.0, 1.8708286933869707]\n";
    let builtin = scenario(
        &dir,
        &format!("[model]\nname = \"kepler\"\nparams = {{ eccentricity = 0.6 }}\n{shared_tables}"),
    );
    run_scenario(dir.join("a"), &builtin).success();
    let custom = scenario(
        &dir,
        &format!(
            "[model]\nname = \"custom\"\ncoordinates = [\"x\", \"y\"]\nlagrangian = \"0.5*(x_dot^2 + y_dot^2) + 1/sqrt(x^2 + y^2)\"\n\
             symmetries = {{ angular = [\"-y\", \"x\"] }}\n{shared_tables}"
        ),
    );
    run_scenario(dir.join("b"), &custom).success();
    let read = |d: &str| std::fs::read_to_string(dir.join(d).join("trajectory.csv")).expect("csv");
    let (a, b) = (read("a"), read("b"));
    assert_eq!(a.lines().next(), b.lines().next());
    let mut worst = 0.0_f64;
    for (la, lb) in a.lines().skip(1).zip(b.lines().skip(1)) {
        for (x, y) in la.split(',').zip(lb.split(',')) {
            let (x, y): (f64, f64) = (x.parse().expect("number"), y.parse().expect("number"));
            worst = worst.max((x - y).abs());
        }
    }
    // Fixed-point (built-in) and Newton (custom) solve the same equations to
    // round-off; over 300 steps through pericentre the difference stays tiny.
    assert!(worst < 1e-11, "trajectories differ by {worst:e}");
    // ∇V evaluations are counted on the separable path only: s = 3 per sweep.
    let (sa, sb) = (summary(&dir.join("a")), summary(&dir.join("b")));
    let evaluations = sa["force_evaluations_mean"]
        .as_f64()
        .expect("counted on the fixed-point path");
    let sweeps = sa["newton_iterations_mean"].as_f64().expect("number");
    assert!(
        (evaluations - 3.0 * sweeps).abs() < 1e-12 && (3.0..20.0).contains(&evaluations),
        "{sa}"
    );
    assert!(sb["force_evaluations_mean"].is_null(), "{sb}");
}

/// A declared symmetry is checked: the rotation of a charge in a magnetic
/// field (symmetric gauge) is accepted and its momentum conserved; the
/// translation, which leaves L invariant only up to a total derivative, is
/// refused naming the key, before any step.
#[test]
fn declared_symmetries_are_checked() {
    let model = |generator: &str| {
        format!(
            "[model]\nname = \"custom\"\ncoordinates = [\"x\", \"y\"]\n\
             lagrangian = \"0.5*(x_dot^2 + y_dot^2) + 0.5*b*(x*y_dot - y*x_dot)\"\n\
             symmetries = {{ s = {generator} }}\nconstants = {{ b = 1.5 }}\n\
             [method]\nname = \"midpoint\"\ndt = 0.01\n[time]\nsteps = 200\n[initial]\nq = [1.0, 0.0]\nv = [0.0, 1.0]\n"
        )
    };
    let dir = Scratch::new("symmetry-check");
    let file = scenario(&dir, &model("[\"-y\", \"x\"]"));
    let out = dir.join("out");
    run_scenario(&out, &file).success();
    let s = summary(&out);
    let drift = s["momentum_error_max"]["s"].as_f64().expect("number");
    assert!(drift < 1e-12, "{s}");
    let err = failing("symmetry-translation", &model("[\"1\", \"0\"]"));
    assert!(
        err.contains("model.symmetries.s") && err.contains("not invariant"),
        "{err}"
    );
}

#[test]
fn trajectory_columns_carry_the_coordinate_names_unless_they_clash() {
    let header = |coordinates: &str, lagrangian: &str| {
        let text = format!(
            "[model]\nname = \"custom\"\ncoordinates = {coordinates}\nlagrangian = \"{lagrangian}\"\n\
             [method]\nname = \"midpoint\"\ndt = 0.1\n[time]\nsteps = 3\n[initial]\nq = [1.0, 0.5]\np = [0.0, 0.1]\n"
        );
        let (ok, stderr, out) = run(&format!("columns-{}", coordinates.len()), &text);
        assert!(ok, "{stderr}");
        let (header, rows) = csv(&out.join("trajectory.csv"));
        assert_eq!(rows.len(), 4);
        assert!(out.join("phase.svg").exists() && out.join("orbit.svg").exists());
        header
    };
    assert_eq!(
        header(
            "[\"theta1\", \"theta2\"]",
            "0.5*(theta1_dot^2 + theta2_dot^2) + cos(theta1) + cos(theta2)"
        ),
        ["t", "theta1", "theta2", "p_theta1", "p_theta2", "energy"]
    );
    // `x` and `p_x` would give two columns `p_x`: positional names instead.
    assert_eq!(
        header("[\"x\", \"p_x\"]", "0.5*(x_dot^2 + p_x_dot^2) - 0.5*x^2"),
        ["t", "q0", "q1", "p0", "p1", "energy"]
    );
}

/// A custom model of `n` coordinates `a, b1..b(n−1)`: an anharmonic
/// oscillator `a` decoupled from a free chain `b` (nearest-neighbour
/// quartic springs), whose Lagrangian is invariant under a shift of every `b`.
fn oscillator_and_chain(n: usize, extra: &str) -> String {
    let b: Vec<String> = (1..n).map(|i| format!("b{i}")).collect();
    let kinetic: Vec<String> = b.iter().map(|x| format!("{x}_dot^2")).collect();
    let springs: Vec<String> = b
        .windows(2)
        .map(|w| format!("0.5*({1} - {0})^2 + 0.25*({1} - {0})^4", w[0], w[1]))
        .collect();
    let coordinates: Vec<String> = std::iter::once("\"a\"".to_string())
        .chain(b.iter().map(|x| format!("\"{x}\"")))
        .collect();
    let shift: Vec<&str> = std::iter::once("\"0\"").chain(b.iter().map(|_| "\"1\"")).collect();
    let q: Vec<String> = (0..n).map(|i| format!("{}", 1.0 - 0.3 * i as f64)).collect();
    let p: Vec<String> = (0..n).map(|i| format!("{}", 0.3 + 0.1 * (i as f64).sin())).collect();
    format!(
        "[model]\nname = \"custom\"\ncoordinates = [{}]\n\
         lagrangian = \"0.5*a_dot^2 - 0.5*a^2 - 0.1*a^4 + 0.5*({}) - ({})\"\n\
         symmetries = {{ shift = [{}] }}\n\
         [method]\nname = \"galerkin-gauss\"\nstages = 2\ndt = 0.05\n[time]\nsteps = 200\n\
         [initial]\nq = [{}]\np = [{}]\n{extra}",
        coordinates.join(", "),
        kinetic.join(" + "),
        springs.join(" + "),
        shift.join(", "),
        q.join(", "),
        p.join(", ")
    )
}

#[test]
fn custom_models_beyond_six_coordinates_run_on_the_run_time_dimension_integrator() {
    // The oscillator alone, on the fixed-size path.
    let alone = "[model]\nname = \"custom\"\ncoordinates = [\"a\"]\n\
                 lagrangian = \"0.5*a_dot^2 - 0.5*a^2 - 0.1*a^4\"\n\
                 [method]\nname = \"galerkin-gauss\"\nstages = 2\ndt = 0.05\n[time]\nsteps = 200\n\
                 [initial]\nq = [1.0]\np = [0.3]\n";
    let (ok, stderr, out_alone) = run("dyn-alone", alone);
    assert!(ok, "{stderr}");
    let (h1, rows1) = csv(&out_alone.join("trajectory.csv"));
    assert_eq!(h1[..3], ["t", "a", "p_a"]);
    for n in [8, 12] {
        let (ok, stderr, out) = run(&format!("dyn-{n}"), &oscillator_and_chain(n, ""));
        assert!(ok, "{n}: {stderr}");
        let (header, rows) = csv(&out.join("trajectory.csv"));
        assert_eq!(header.len(), 1 + 2 * n + 2, "{header:?}");
        assert_eq!((header[1].as_str(), header[n + 1].as_str()), ("a", "p_a"));
        assert_eq!(header.last().map(String::as_str), Some("J_shift"));
        assert_eq!(rows.len(), 201);
        // The decoupled oscillator follows the one-coordinate run (the other
        // path through the code) to the Newton tolerance.
        let worst = rows
            .iter()
            .zip(&rows1)
            .map(|(r, r1)| (r[1] - r1[1]).abs().max((r[n + 1] - r1[2]).abs()))
            .fold(0.0, f64::max);
        assert!(worst < 1e-12, "{n}: the oscillator differs by {worst:e}");
        let s = summary(&out);
        assert_eq!(s["status"], "ok");
        assert_eq!(s["coordinates"], n);
        // The shift momentum is conserved to round-off, the energy of an
        // order-4 method with h = 0.05 to its truncation error.
        let shift = s["momentum_error_max"]["shift"].as_f64().expect("number");
        assert!(shift < 1e-12, "{n}: shift momentum drifts by {shift:e}");
        let energy = s["energy_error_max"].as_f64().expect("number");
        assert!(energy < 1e-4, "{n}: energy error {energy:e}");
        // The factored Jacobian is kept across steps: fewer than one per step
        // (full Newton evaluates one per iteration, 3 to 4 per step here).
        let jacobians = s["jacobians_mean"].as_f64().expect("number");
        assert!(jacobians < 0.5, "{n}: {jacobians} Jacobians per step");
        assert!(out.join("phase.svg").exists() && out.join("energy_error.svg").exists());
    }
}

#[test]
fn custom_models_beyond_six_coordinates_refuse_what_they_cannot_do() {
    let refuse = |name: &str, text: String, needles: &[&str]| {
        let (ok, stderr, _) = run(name, &text);
        assert!(!ok, "{name} ran");
        assert_mentions(&stderr, needles, name);
    };
    let base = oscillator_and_chain(8, "");
    let forced = base.replace(
        "symmetries =",
        "force = [\"0\", \"0\", \"0\", \"0\", \"0\", \"0\", \"0\", \"-b7_dot\"]\nsymmetries =",
    );
    refuse("dyn-force", forced, &["model.force", "at most 6"]);
    let sem = base.replace("name = \"galerkin-gauss\"\nstages = 2", "name = \"sem-midpoint\"");
    refuse("dyn-sem", sem, &["method.name", "sem-midpoint"]);
    let wrong = base.replace("shift = [\"0\"", "shift = [\"1\"");
    refuse("dyn-symmetry", wrong, &["model.symmetries.shift", "not invariant"]);
    refuse(
        "dyn-65",
        oscillator_and_chain(65, ""),
        &["model.coordinates", "between 1 and 64"],
    );
    let dir = Scratch::new("dyn-verify");
    let file = scenario(&dir, &base);
    let o = veselov()
        .args(["verify", "--quiet", "--dt", "0.1,0.05"])
        .arg(&file)
        .output()
        .expect("verify");
    assert!(!o.status.success());
    assert_mentions(
        &String::from_utf8_lossy(&o.stderr),
        &["model.coordinates", "at most 6"],
        "verify",
    );
}
