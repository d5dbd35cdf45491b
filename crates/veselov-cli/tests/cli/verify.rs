//! `veselov verify`: the fitted order, its warnings, and the shipped
//! mechanics examples verified as written.

use crate::common::{Scratch, scenario, succeeds, summary, verify_command, veselov, workspace_root};

#[test]
fn verify_measures_the_order() {
    let dir = Scratch::new("verify");
    let text = "[model]\nname = \"pendulum\"\n[method]\nname = \"galerkin-gauss\"\nstages = 2\ndt = 0.1\n[time]\nt_end = 2.0\n";
    let file = scenario(&dir, text);
    let out = dir.join("v");
    verify_command("0.2,0.1,0.05,0.025", &out, &file).assert().success();
    let s = summary(&out);
    let p = s["order_fitted"].as_f64().expect("fitted order");
    assert!((p - 4.0).abs() < 0.2, "{s}");
    assert_eq!(s["reference"], "exact solution");
    assert!(out.join("convergence.csv").exists() && out.join("convergence.svg").exists());
    // A step that does not divide the horizon is adjusted to land on t_end,
    // and says so; a step that is not positive, or asks for more steps than a
    // run may take (it would not end), is refused at once, naming the flag.
    let stdout = succeeds(
        veselov()
            .args(["verify", "--dt", "0.3", "--out"])
            .arg(dir.join("w"))
            .arg(&file),
    );
    assert!(stdout.contains("adjusted to 0.2857142857142857"), "{stdout}");
    assert!(stdout.contains("outputs in"), "{stdout}");
    for bad in ["0", "-0.1", "1e-300,1e-301", "nan"] {
        let res = verify_command(bad, dir.join("x"), &file)
            .timeout(std::time::Duration::from_secs(20))
            .assert()
            .failure();
        let stderr = String::from_utf8_lossy(&res.get_output().stderr).to_string();
        assert!(stderr.contains("--dt"), "{bad}: {stderr}");
    }
}

/// The flagship example verifies as the README documents it, its steps
/// adjusted to land on t_end, with the order reached and the range printed.
#[test]
fn verify_runs_the_kepler_example_as_documented() {
    let dir = Scratch::new("verify-kepler");
    let out = dir.join("v");
    let stdout = succeeds(
        veselov()
            .args(["verify", "--dt", "0.1,0.05,0.025", "--out"])
            .arg(&out)
            .arg(workspace_root().join("examples/kepler.toml")),
    );
    assert!(
        stdout.contains("fitted order") && stdout.contains("dt from"),
        "{stdout}"
    );
    assert!(!stdout.contains("warning"), "{stdout}");
    let s = summary(&out);
    assert_eq!(s["order_reached"], true, "{s}");
    let p = s["order_fitted"].as_f64().expect("fitted order");
    assert!((p - 4.0).abs() < 0.1, "{s}");
    assert_eq!(s["local_rates"].as_array().map(Vec::len), Some(2), "{s}");
}

/// A study whose steps are not in the asymptotic range says so instead of
/// reporting a wrong order silently: the heavy top's coarsest steps (the
/// error grows from 0.01 to 0.005) and Kepler e = 0.7 at 25 and 31 steps per
/// orbit (a local rate near 6 for a fourth-order method).
#[test]
fn verify_warns_when_the_steps_are_not_asymptotic() {
    let dir = Scratch::new("verify-coarse");
    let out = dir.join("top");
    let stdout = succeeds(
        veselov()
            .args(["verify", "--dt", "0.01,0.005", "--out"])
            .arg(&out)
            .arg(workspace_root().join("examples/heavy_top.toml")),
    );
    assert_eq!(summary(&out)["order_reached"], false, "{stdout}");
    assert!(
        stdout.contains("warning: the claimed order 2 is not reached"),
        "{stdout}"
    );
    let text = "[model]\nname = \"kepler\"\nparams = { eccentricity = 0.7 }\n[method]\nname = \"galerkin-gauss\"\n\
                stages = 2\ndt = 0.1\n[time]\nt_end = 6.283185307179586\n";
    let file = scenario(&dir, text);
    let out = dir.join("kepler");
    let stdout = succeeds(
        veselov()
            .args(["verify", "--dt", "0.25,0.2", "--out"])
            .arg(&out)
            .arg(&file),
    );
    assert!(
        stdout.contains("warning: the fitted order is above the claimed 4"),
        "{stdout}"
    );
}

#[test]
fn verify_measures_the_order_of_the_lie_group_integrator() {
    let dir = Scratch::new("rigid-verify");
    let path = scenario(
        &dir,
        "[model]\nname = \"heavy-top\"\n[method]\nretraction = \"exp\"\ndt = 0.01\n\
         [initial]\nrotation_vector = [0.3, 0.1, 0.0]\nangular_velocity = [0.5, -0.3, 2.0]\n[time]\nt_end = 1.0\n",
    );
    let out = dir.join("verify");
    verify_command("0.02,0.01,0.005,0.0025", &out, &path).assert().success();
    let s = summary(&out);
    let order = s["order_fitted"].as_f64().expect("fitted order");
    assert!((order - 2.0).abs() <= 0.2, "order {order}");
    assert!(out.join("convergence.csv").exists());
}

/// `verify` runs on every shipped mechanics and rigid-body example as
/// written (fixed and variable steps), at its own step and half of it, with
/// finite errors; where the horizon is not chaotic the fitted order is the
/// claimed one.
#[test]
fn verify_works_on_every_shipped_mechanics_example() {
    let mut count = 0;
    for entry in std::fs::read_dir(workspace_root().join("examples")).expect("examples dir") {
        let path = entry.expect("entry").path();
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        let value: toml::Value = match toml::from_str(&text) {
            Ok(v) if path.extension().and_then(|e| e.to_str()) == Some("toml") => v,
            _ => continue,
        };
        let model = value.get("model").and_then(|m| m.get("name")).and_then(|n| n.as_str());
        if value.get("lattice").is_some() || matches!(model, Some("beam" | "cosserat-rod")) {
            continue;
        }
        let dt = value
            .get("method")
            .and_then(|m| m.get("dt"))
            .and_then(|d| d.as_float())
            .unwrap_or(0.01);
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("example")
            .to_string();
        let out = Scratch::new(&format!("verify-all-{name}")).at("v");
        succeeds(&mut verify_command(&format!("{dt},{}", dt / 2.0), &out, &path));
        let s = summary(&out);
        let errors = s["errors"].as_array().expect("errors");
        assert!(
            errors
                .iter()
                .all(|e| e.as_f64().is_some_and(|e| e.is_finite() && e > 0.0)),
            "{name}: {s}"
        );
        if name != "double_pendulum" {
            assert_eq!(s["order_reached"], true, "{name}: {s}");
        }
        count += 1;
    }
    assert!(count >= 14, "only {count} examples verified");
}
