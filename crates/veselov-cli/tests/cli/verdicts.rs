//! Run verdicts: a run that ends "ok" but strays from what its scheme
//! conserves carries a warning in `summary.json` and on the terminal, and
//! input that cannot give a right answer is refused naming its key.

use crate::common::{example, run, set, summary};
use crate::shared::with_time_table;

/// The warnings of a summary: (code, message) pairs.
fn warnings(s: &serde_json::Value) -> Vec<(String, String)> {
    s["warnings"]
        .as_array()
        .unwrap_or_else(|| panic!("`warnings` is a list: {s}"))
        .iter()
        .map(|w| {
            (
                w["code"].as_str().unwrap_or_default().to_string(),
                w["message"].as_str().unwrap_or_default().to_string(),
            )
        })
        .collect()
}

/// A run that succeeds, with its summary's warnings and its standard error.
fn warned(name: &str, text: &str) -> (Vec<(String, String)>, String, serde_json::Value) {
    let (ok, stderr, out) = run(name, text);
    assert!(ok, "{stderr}");
    let s = summary(&out);
    assert_eq!(s["status"], "ok", "{s}");
    (warnings(&s), stderr, s)
}

/// The code of the only warning, which the terminal shows too.
fn only_warning(name: &str, text: &str) -> (String, String) {
    let (w, stderr, _) = warned(name, text);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(stderr.contains(&format!("warning: {}", w[0].1)), "{stderr}");
    w[0].clone()
}

#[test]
fn an_eccentric_orbit_at_a_coarse_step_ends_ok_with_an_energy_warning() {
    let text = "[model]\nname = \"custom\"\ncoordinates = [\"x\", \"y\"]\n\
                lagrangian = \"0.5*(x_dot^2 + y_dot^2) + 1/sqrt(x^2 + y^2)\"\n\
                [method]\nname = \"galerkin-gauss\"\nstages = 2\ndt = 0.01\n\
                [time]\nt_end = 20\n[initial]\nq = [0.5, 0]\np = [0, 0.5]\n[output]\nplots = false\n";
    let (code, message) = only_warning("verdict-eccentric", text);
    assert_eq!(code, "energy_error");
    assert!(message.contains("try method.dt ≤"), "{message}");
    // At a step the advice allows, the same orbit is within the threshold.
    let dt = message
        .rsplit("method.dt ≤ ")
        .next()
        .and_then(|s| s.split([' ', ';']).next())
        .and_then(|s| s.parse::<f64>().ok())
        .expect("a suggested step");
    assert!(dt < 0.01, "{message}");
    let finer = set(text, "dt", &format!("{dt}"));
    let (w, _, s) = warned("verdict-eccentric-fine", &finer);
    assert!(w.is_empty(), "{w:?}: {s}");
    let measured = s["checks"]["energy_error"]["measured"].as_f64().expect("measured");
    assert!(measured <= 0.01, "{s}");
}

#[test]
fn a_nearly_parabolic_kepler_orbit_and_a_heavy_top_at_a_huge_step_carry_warnings() {
    let kepler = "[model]\nname = \"kepler\"\nparams = { eccentricity = 0.999999999 }\n\
                  [method]\nname = \"galerkin-gauss\"\nstages = 2\ndt = 0.01\n[time]\nt_end = 10\n\
                  [output]\nplots = false\n";
    assert_eq!(only_warning("verdict-parabolic", kepler).0, "energy_error");
    let top = with_time_table(&set(&example("heavy_top.toml"), "dt", "100.0"), "t_end = 400.0\n");
    let top = set(&top, "plots", "false");
    assert_eq!(only_warning("verdict-top", &top).0, "energy_error");
}

#[test]
fn the_threshold_is_set_per_scenario_and_an_accurate_run_has_an_empty_list() {
    let kepler = example("kepler.toml").replace("t_end = 314.1592653589793", "t_end = 20.0");
    let kepler = set(&kepler, "plots", "false");
    let (w, _, s) = warned("verdict-kepler", &kepler);
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(s["checks"]["energy_error"]["limit"], 0.01);
    // Kepler at dt = 0.01 keeps its energy to ~3e-9: a threshold of 1e-12 flags it.
    let strict = format!("{kepler}\n[checks]\nenergy_error = 1e-12\n");
    let (w, _, s) = warned("verdict-kepler-strict", &strict);
    assert_eq!(w.len(), 1, "{s}");
    assert_eq!(s["checks"]["energy_error"]["limit"], 1e-12);
    let (ok, stderr, _) = run(
        "verdict-bad-threshold",
        &format!("{kepler}\n[checks]\nenergy_error = -1\n"),
    );
    assert!(!ok && stderr.contains("`checks.energy_error`"), "{stderr}");
}

#[test]
fn a_forced_run_is_judged_on_its_energy_balance() {
    let text = set(&example("damped_oscillator.toml"), "plots", "false");
    let (w, _, s) = warned("verdict-damped", &text);
    // The energy falls by design; the balance E − E₀ − W holds to round-off.
    assert!(w.is_empty(), "{w:?}: {s}");
    assert!(
        s["checks"]["energy_error"]["measured"].as_f64().expect("measured") < 1e-10,
        "{s}"
    );
}

#[test]
fn a_one_plus_one_lattice_beyond_its_stability_limit_is_refused_naming_the_key() {
    let wave = set(&example("wave.toml"), "courant", "1e300");
    let (ok, stderr, _) = run("verdict-courant", &wave);
    assert!(!ok, "{stderr}");
    assert!(
        stderr.contains("`lattice.courant`") && stderr.contains("stability limit 1"),
        "{stderr}"
    );
    assert!(!stderr.contains("000000000000"), "numbers in shortest form: {stderr}");
    // An implicit scheme has no limit, but a step longer than the run is refused.
    let rectangle = wave.replace("scheme = \"triangle\"", "scheme = \"rectangle\"");
    let (ok, stderr, _) = run("verdict-courant-rect", &rectangle);
    assert!(
        !ok && stderr.contains("`lattice.courant`") && stderr.contains("longer than the run"),
        "{stderr}"
    );
    // Allowed on request, with a warning recorded.
    let short = with_time_table(&set(&example("wave.toml"), "courant", "1.1"), "t_end = 1.0\n");
    let allowed = short.replace("scheme = \"triangle\"", "scheme = \"triangle\"\nallow_unstable = true");
    let (w, _, _) = warned("verdict-courant-allowed", &set(&allowed, "plots", "false"));
    assert!(w.iter().any(|(c, _)| c == "beyond_stability_limit"), "{w:?}");
}

#[test]
fn an_inertia_no_body_has_is_refused_naming_the_key() {
    for inertia in ["[1.0, 2.0, 3.1]", "[1.0, 2.0, 3e14]"] {
        let text = set(&example("rigid_body.toml"), "inertia", inertia);
        let (ok, stderr, _) = run("verdict-inertia", &text);
        assert!(!ok, "{inertia}: {stderr}");
        assert!(
            stderr.contains("`model.inertia`") && stderr.contains("triangle inequality"),
            "{stderr}"
        );
    }
    // A flat body (I₃ = I₁ + I₂) is a body.
    let (ok, stderr, _) = run(
        "verdict-inertia-flat",
        &set(
            &set(&example("rigid_body.toml"), "inertia", "[1.0, 2.0, 3.0]"),
            "plots",
            "false",
        ),
    );
    assert!(ok, "{stderr}");
}

#[test]
fn a_symmetry_generator_that_is_not_finite_is_refused_at_parse() {
    for generator in ["1/0", "sqrt(-1)"] {
        let text = format!(
            "[model]\nname = \"custom\"\ncoordinates = [\"x\"]\nlagrangian = \"0.5*x_dot^2\"\n\
             symmetries = {{ bad = [\"{generator}\"] }}\n[method]\nname = \"midpoint\"\ndt = 0.1\n\
             [time]\nsteps = 3\n[initial]\nq = [1.0]\np = [0.5]\n"
        );
        let (ok, stderr, _) = run("verdict-generator", &text);
        assert!(!ok, "{generator}: {stderr}");
        assert!(
            stderr.contains("`model.symmetries.bad`") && stderr.contains("not finite"),
            "{stderr}"
        );
    }
}

#[test]
fn messages_speak_the_users_words() {
    let kepler = set(&example("kepler.toml"), "plots", "false");
    // No Rust type names.
    let (ok, stderr, _) = run("words-every", &set(&kepler, "every", "-1"));
    assert!(!ok && stderr.contains("expected a whole number ≥ 0"), "{stderr}");
    assert!(!stderr.contains("u64"), "{stderr}");
    // Numbers in shortest form with an exponent, never hundreds of digits.
    let (ok, stderr, _) = run("words-dt", &set(&kepler, "dt", "-1e308"));
    assert!(!ok && stderr.contains("-1e308"), "{stderr}");
    // One step is a step.
    let one = with_time_table(&kepler, "steps = 1\n");
    let (o, _dir) = crate::common::run_loud("words-one-step", &one);
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(said.contains(": 1 step to t = 0.01"), "{said}");
}

#[test]
fn a_failed_run_prints_no_success_line_before_its_error() {
    // exp(x²) pulls the particle out faster than a step of 0.1 can follow:
    // Newton fails at the fourth step.
    let text = "[model]\nname = \"custom\"\ncoordinates = [\"x\"]\nlagrangian = \"0.5*x_dot^2 + exp(x^2)\"\n\
                [method]\nname = \"midpoint\"\ndt = 0.1\n[time]\nsteps = 100\n[initial]\nq = [1.0]\np = [0.0]\n\
                [output]\nplots = false\n";
    let (o, dir) = crate::common::run_loud("words-failed", text);
    let (said, stderr) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(!o.status.success() && stderr.contains("error: run failed"), "{stderr}");
    assert!(
        !said.contains("outputs in"),
        "a success-style line before the error: {said}"
    );
    assert_eq!(summary(&dir.join("out"))["status"], "error");
}

/// A `sem-leftpoint` Kepler scenario of eccentricity `e` and first step
/// `dt`, over `t_end`, with `initial` (a TOML table, or empty for the
/// pericentre start).
fn left_point(e: f64, dt: f64, t_end: f64, initial: &str) -> String {
    format!(
        "[model]\nname = \"kepler\"\nparams = {{ eccentricity = {e} }}\n[method]\nname = \"sem-leftpoint\"\n\
         dt = {dt}\n[time]\nt_end = {t_end}\n{initial}[output]\nplots = false\n"
    )
}

#[test]
fn a_left_point_run_from_a_turning_point_warns_of_its_start_and_its_runaway() {
    for dt in [0.02, 0.005] {
        let (w, stderr, s) = warned("verdict-left-point", &left_point(0.1, dt, std::f64::consts::TAU, ""));
        let codes: Vec<&str> = w.iter().map(|(c, _)| c.as_str()).collect();
        assert_eq!(codes, ["degenerate_start", "step_runaway"], "dt = {dt}: {stderr}");
        assert!(w[0].1.contains("sem-midpoint or sem-averaged"), "{}", w[0].1);
        // The energy's advice (a smaller dt) would not help: not given.
        assert!(s.get("checks").is_none(), "{s}");
        let growth = s["h_max"].as_f64().expect("h_max") / dt;
        assert!(
            w[1].1.contains(&format!("{}×", veselov_cli::output::approx(growth))),
            "{}",
            w[1].1
        );
    }
}

#[test]
fn a_left_point_run_away_from_turning_points_or_on_a_circle_is_not_warned_about() {
    // The e = 0.1 orbit at t = 1 (Kepler's equation), 1.5 before its apocentre.
    let initial = "[initial]\nq = [0.3637281822405811, 0.8815365059178706]\n\
                   p = [-0.9290606863040317, 0.4838407759124423]\n";
    let (w, stderr, s) = warned("verdict-left-point-regular", &left_point(0.1, 0.005, 1.5, initial));
    assert!(w.is_empty(), "{w:?}: {stderr}");
    assert!(s["checks"]["energy_error"]["measured"].as_f64().is_some(), "{s}");
    let (w, stderr, _) = warned(
        "verdict-left-point-circle",
        &left_point(0.0, 0.02, std::f64::consts::TAU, ""),
    );
    assert!(w.is_empty(), "{w:?}: {stderr}");
}

#[test]
fn a_symmetric_rule_from_pericentre_is_not_warned_about() {
    let text = example("kepler_sem.toml");
    let (w, stderr, _) = warned(
        "verdict-sem-averaged",
        &with_time_table(&text, "t_end = 6.283185307179586\n"),
    );
    assert!(w.is_empty(), "{w:?}: {stderr}");
}

#[test]
fn verify_of_a_left_point_run_from_a_turning_point_says_why_no_order_is_reached() {
    let dir = crate::common::Scratch::new("verdict-left-point-verify");
    let file = crate::common::scenario(&dir, &left_point(0.1, 0.01, std::f64::consts::TAU, ""));
    let stdout = crate::common::succeeds(
        crate::common::veselov()
            .args(["verify", "--dt", "0.02,0.01,0.005", "--out"])
            .arg(dir.join("v"))
            .arg(&file),
    );
    assert!(
        stdout.contains("the claimed order 1 is not reached: the start is on or near a turning point"),
        "{stdout}"
    );
    let s = summary(&dir.join("v"));
    let order = s["order_fitted"].as_f64().expect("a fitted order");
    assert!(order.abs() < 0.1, "{s}");
    assert!(s["caveat"].as_str().is_some_and(|c| c.contains("sem-midpoint")), "{s}");
}
