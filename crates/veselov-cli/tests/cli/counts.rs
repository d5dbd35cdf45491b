//! One vocabulary of counts: the preflight line, the final line and
//! `summary.json` count the same time steps, whatever the number of
//! lattice levels a time step computes, and messages print numbers short.

use crate::common::{example, run_loud, summary};
use crate::shared::with_time_table;

/// Runs `text` (not quiet) in a fresh directory `name`; returns the
/// preflight count, the final line (standard output) and the summary.
fn counted(name: &str, text: &str) -> (u64, String, serde_json::Value) {
    let (o, dir) = run_loud(name, text);
    let out = dir.at("out");
    let (stdout, stderr) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "{stderr}");
    let preflight = stderr
        .lines()
        .find_map(|l| l.strip_prefix("preflight: "))
        .and_then(|l| l.split(' ').next())
        .and_then(|n| n.parse::<u64>().ok())
        .unwrap_or_else(|| panic!("a preflight count: {stderr}"));
    (preflight, stdout.trim().to_string(), summary(&out))
}

/// `key` of `s` as an integer.
fn int(s: &serde_json::Value, key: &str) -> u64 {
    s[key].as_u64().unwrap_or_else(|| panic!("`{key}` is an integer: {s}"))
}

/// `key` of `s` as a number.
fn num(s: &serde_json::Value, key: &str) -> f64 {
    s[key].as_f64().unwrap_or_else(|| panic!("`{key}` is a number: {s}"))
}

/// The steps agree everywhere a user reads them, make up `t_final` at the
/// run's step, and the iterations per time step are the per-vertex ones
/// times the vertex solves of a time step.
fn agree(name: &str, text: &str, levels_per_step: u64, vertices_per_level: Option<u64>) -> String {
    let (preflight, line, s) = counted(name, text);
    let steps = int(&s, "steps");
    assert_eq!(preflight, steps, "preflight against summary: {s}");
    assert!(line.contains(&format!(": {steps} time steps ")), "{line}");
    let dt = num(&s, "dt");
    assert!((steps as f64 * dt - num(&s, "t_final")).abs() < 1e-9, "{s}");
    if levels_per_step > 1 {
        assert_eq!(int(&s, "time_steps"), steps, "{s}");
    }
    assert_eq!(int(&s, "levels"), levels_per_step * steps, "{s}");
    if let Some(v) = vertices_per_level {
        let per_vertex = num(&s, "newton_iterations_per_vertex");
        let per_step = num(&s, "iterations_mean");
        let expected = per_vertex * (levels_per_step * v) as f64;
        assert!(
            (per_step - expected).abs() <= 1e-9 * expected,
            "{per_step} against {expected}: {s}"
        );
    }
    line
}

#[test]
fn a_rod_counts_time_steps_of_two_levels_each() {
    let text = with_time_table(&example("rod_cantilever_damped.toml"), "t_end = 0.05\n");
    // 81 nodes: a level solves every other one.
    let line = agree("counts-rod", &text, 2, Some(41));
    // Numbers in the report are short: no padded exponents.
    assert!(!line.contains("e0") && !line.contains(".0000"), "{line}");
}

#[test]
fn a_cfk_field_counts_time_steps_of_three_levels_each() {
    let text = with_time_table(&example("sine_gordon_2d.toml"), "t_end = 0.5\n");
    let nodes = 48 * 48;
    agree("counts-cfk", &text, 3, Some(nodes));
}

#[test]
fn a_beam_counts_its_time_steps_from_the_first_level() {
    let text = with_time_table(&example("beam_cantilever.toml"), "t_end = 0.02\n");
    let line = agree("counts-beam", &text, 1, None);
    assert!(!line.contains("levels"), "{line}");
}

#[test]
fn a_one_plus_one_field_counts_its_levels_as_time_steps() {
    let text = with_time_table(&example("wave.toml"), "t_end = 5\n");
    agree("counts-lattice", &text, 1, None);
}
