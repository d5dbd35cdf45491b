//! The listing commands (`models`, `methods`, `expressions`): what they say,
//! and a reader that closes the pipe early.

use crate::common::{Scratch, assert_mentions, run_scenario, scenario, succeeds, veselov};
use crate::shared::failing;

#[test]
fn listing_commands_describe_models_and_methods() {
    let text = succeeds(veselov().arg("models"));
    assert_mentions(
        &text,
        &[
            "kepler",
            "eccentricity = 0.5",
            "pendulum",
            "henon-heiles",
            "double-pendulum",
            "custom",
        ],
        "models output",
    );
    let text = succeeds(veselov().arg("methods"));
    assert_mentions(
        &text,
        &[
            "midpoint",
            "galerkin-gauss",
            "order 2s",
            "galerkin-lobatto",
            "order 2s − 2",
        ],
        "methods output",
    );
}

/// `veselov models` lists the structures (beam, rod) with the other
/// models, and a listing whose reader closes the pipe early
/// (`veselov models | head -3`) ends quietly, without a panic.
#[test]
fn listings_name_every_model_and_survive_a_closed_pipe() {
    let listing = veselov().arg("models").output().expect("models");
    let text = String::from_utf8_lossy(&listing.stdout);
    for name in ["kepler", "rigid-body", "sine-gordon", "beam", "cosserat-rod"] {
        assert!(text.lines().any(|l| l == name), "`veselov models` lacks {name}");
    }
    for command in ["models", "methods", "expressions"] {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_veselov"))
            .arg(command)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("spawn");
        // The reading end closed before the listing is written.
        drop(child.stdout.take());
        let out = child.wait_with_output().expect("wait");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{command}: {err}");
        assert!(out.status.success(), "{command}: {:?} {err}", out.status);
    }
}

/// `veselov expressions` documents every name and function the parser knows,
/// `pi` and `e` work in a custom model, and an unknown function's error lists
/// the functions there are.
#[test]
fn expression_language_is_documented_and_helpful() {
    let text = succeeds(veselov().arg("expressions"));
    assert_mentions(
        &text,
        &[
            "<name>_dot",
            "t ",
            "pi",
            "e = 2.718281828459045",
            "pow(a, b)",
            "atan2(y, x)",
            "1 to 64",
        ],
        "`veselov expressions`",
    );
    for f in veselov::expr::FUNCTIONS {
        assert!(text.contains(f), "lacks {f}");
    }
    // A custom model that uses the built-in constants runs.
    let ok = "[model]\nname = \"custom\"\ncoordinates = [\"x\"]\n\
              lagrangian = \"0.5*x_dot^2 + cos(x) - 0*pi*e\"\n[method]\nname = \"midpoint\"\ndt = 0.01\n\
              [time]\nsteps = 10\n[initial]\nq = [1.0]\np = [0.0]\n";
    let dir = Scratch::new("expressions");
    let file = scenario(&dir, ok);
    run_scenario(dir.join("out"), &file).success();
    let bad = ok.replace("cos(x)", "cosine(x)");
    let err = failing("expressions-bad", &bad);
    assert!(
        err.contains("unknown function `cosine`") && err.contains("sinh") && err.contains("atan2"),
        "{err}"
    );
}
