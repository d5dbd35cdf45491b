//! Helpers several modules share: examples cut to a few steps, a run that
//! must fail, and the relative energy error a summary states.

use std::path::{Path, PathBuf};

use crate::common::{Scratch, run_scenario, scenario, workspace_root};

/// The example `examples/<name>.toml` cut to `steps` steps, written into `dir`.
pub(crate) fn example_scenario(dir: &Path, name: &str, steps: usize) -> PathBuf {
    let text = std::fs::read_to_string(workspace_root().join(format!("examples/{name}.toml"))).expect("example");
    scenario(dir, &shorten(&text, steps))
}

/// Replace the `[time]` table of an example with a short horizon.
pub(crate) fn shorten(text: &str, steps: usize) -> String {
    with_time_table(text, &format!("steps = {steps}\n"))
}

/// `text` with its `[time]` table's keys replaced by `keys` (lines ending in
/// a newline).
pub(crate) fn with_time_table(text: &str, keys: &str) -> String {
    let mut out = String::new();
    let mut skip = false;
    for line in text.lines() {
        if line.starts_with('[') {
            skip = line.trim() == "[time]";
            if skip {
                out.push_str("[time]\n");
                out.push_str(keys);
                continue;
            }
        }
        if !skip {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// Run a scenario that must fail, returning stderr.
pub(crate) fn failing(name: &str, text: &str) -> String {
    let dir = Scratch::new(name);
    let file = scenario(&dir, text);
    let out = run_scenario(dir.join("out"), &file).failure();
    String::from_utf8_lossy(&out.get_output().stderr).into_owned()
}

/// `energy_error_max_relative` is `energy_error_max / |energy_initial|` (to
/// a few ulps: serde_json's default float parser may miss the nearest
/// double by one ulp).
pub(crate) fn relative_energy_error_is_stated(s: &serde_json::Value) {
    let error = s["energy_error_max"].as_f64().expect("energy error");
    let initial = s["energy_initial"].as_f64().expect("initial energy");
    let relative = s["energy_error_max_relative"].as_f64().expect("relative energy error");
    assert!(initial != 0.0, "{s}");
    let expected = error / initial.abs();
    assert!(
        (relative - expected).abs() <= 4.0 * f64::EPSILON * expected,
        "{relative:e} against {expected:e}: {s}"
    );
}
