//! Array keys of every kind: an array of the wrong length or with an entry
//! of the wrong kind is refused, naming the key (and the entry), never read
//! in part. The 1+1 lattice kind has no array keys.

use crate::common::example;
use crate::shared::{failing, with_time_table};

/// `text` with `key = value` in `[table]`: the key's line replaced where
/// the table has it, else added below the table's header, else a new table.
fn put(text: &str, table: &str, key: &str, value: &str) -> String {
    let header = format!("[{table}]");
    let mut out = Vec::new();
    let (mut inside, mut done) = (false, false);
    for line in text.lines() {
        if line.starts_with('[') {
            if inside && !done {
                out.push(format!("{key} = {value}"));
                done = true;
            }
            inside = line.trim() == header;
        }
        if inside && !done && line.trim_start().starts_with(&format!("{key} =")) {
            out.push(format!("{key} = {value}"));
            done = true;
            continue;
        }
        out.push(line.to_string());
    }
    if inside && !done {
        out.push(format!("{key} = {value}"));
        done = true;
    }
    if !done {
        out.push(format!("{header}\n{key} = {value}"));
    }
    out.join("\n") + "\n"
}

#[test]
fn over_long_or_malformed_arrays_are_refused_naming_the_key() {
    // Every base is cut short, so that an array read in part would end in
    // a quick run (and a failed assertion), not a long one.
    let rod = with_time_table(&example("rod_free_tumbling.toml"), "t_end = 0.01\n");
    let clamped = with_time_table(&example("rod_cantilever_damped.toml"), "t_end = 0.01\n");
    let driven = put(
        &put(&rod, "ends", "start", "\"driven\""),
        "ends.start_motion",
        "rotation",
        "[\"0\", \"0\", \"0\"]",
    );
    let curve = put(&rod, "initial", "shape", "\"curve\"").replace("curvature = 1.5", "");
    let beam = with_time_table(&example("beam_cantilever_damped.toml"), "t_end = 1e-3\n");
    let kepler = with_time_table(&example("kepler.toml"), "steps = 5\n");
    let kepler = put(
        &put(&kepler, "initial", "q", "[0.5, 0.0]"),
        "initial",
        "p",
        "[0.0, 1.7]",
    );
    let top = with_time_table(&example("heavy_top.toml"), "steps = 5\n");
    let se3 = with_time_table(&example("rigid_body_se3.toml"), "steps = 5\n");
    let cfk = with_time_table(&example("sine_gordon_2d.toml"), "t_end = 0.1\n");
    let junk = "9, \"text\", true]";
    let three = format!("[0, 0, 1, {junk}");
    let cases: Vec<(&str, String, &str, &str)> = vec![
        // (what, scenario, key named, message)
        (
            "rod velocity",
            put(&rod, "initial", "velocity", &three),
            "`initial.velocity`",
            "expected 3 numbers, got 6",
        ),
        (
            "rod spin",
            put(&rod, "initial", "angular_velocity", &three),
            "`initial.angular_velocity`",
            "expected 3 numbers, got 6",
        ),
        (
            "rod gravity",
            put(&rod, "loads", "gravity", &three),
            "`loads.gravity`",
            "expected 3 numbers, got 6",
        ),
        (
            "rod end force",
            put(&clamped, "loads", "end_force", &three),
            "`loads.end_force`",
            "expected 3 numbers, got 6",
        ),
        (
            "rod end torque",
            put(&clamped, "loads", "end_torque", &three),
            "`loads.end_torque`",
            "expected 3 numbers, got 6",
        ),
        (
            "rod short",
            put(&rod, "loads", "gravity", "[0, 0]"),
            "`loads.gravity`",
            "expected 3 numbers, got 2",
        ),
        (
            "rod entry",
            put(&rod, "loads", "gravity", "[0, \"down\", 0]"),
            "`loads.gravity[1]`",
            "expected a number, got the string \"down\"",
        ),
        (
            "rod not finite",
            put(&rod, "initial", "velocity", "[0, inf, 0]"),
            "`initial.velocity[1]`",
            "expected a finite number, got inf",
        ),
        (
            "rod curve",
            put(&curve, "initial", "position", "[\"0\", \"0\", \"s\", \"s\"]"),
            "`initial.position`",
            "expected 3 strings, got 4",
        ),
        (
            "rod motion",
            put(&driven, "ends.start_motion", "rotation", "[\"0\", \"0\", \"0\", 1]"),
            "`ends.start_motion.rotation`",
            "expected 3 strings, got 4",
        ),
        (
            "beam gravity",
            put(&beam, "loads", "gravity", &three),
            "`loads.gravity`",
            "expected 3 numbers, got 6",
        ),
        (
            "beam damping",
            put(&beam, "loads", "damping", &format!("[0, 0, 0, 0, 0, 0, {junk}")),
            "`loads.damping`",
            "expected 6 numbers, got 9",
        ),
        (
            "kepler q",
            put(&kepler, "initial", "q", &format!("[0.5, 0.0, {junk}")),
            "`initial.q`",
            "expected 2 numbers",
        ),
        (
            "kepler p",
            put(&kepler, "initial", "p", &format!("[0.0, 1.7, {junk}")),
            "`initial.p`",
            "expected 2 numbers",
        ),
        (
            "kepler entry",
            put(&kepler, "initial", "q", "[0.5, true]"),
            "`initial.q[1]`",
            "expected a number, got the boolean true",
        ),
        (
            "inertia",
            put(&top, "model", "inertia", &format!("[1, 1, 0.5, {junk}")),
            "`model.inertia`",
            "expected 3 or 9 numbers",
        ),
        (
            "centre of mass",
            put(&top, "model", "centre_of_mass", &three),
            "`model.centre_of_mass`",
            "expected 3 numbers, got 6",
        ),
        (
            "rigid spin",
            put(&top, "initial", "angular_velocity", &three),
            "`initial.angular_velocity`",
            "expected 3 numbers, got 6",
        ),
        (
            "quaternion",
            put(&top, "initial", "quaternion", &format!("[1, 0, 0, 0, {junk}"))
                .replace("rotation_vector = [0.3, 0.0, 0.0]", ""),
            "`initial.quaternion`",
            "expected 4 numbers, got 7",
        ),
        (
            "se3 velocity",
            put(&se3, "initial", "velocity", &three),
            "`initial.velocity`",
            "expected 3 numbers, got 6",
        ),
        (
            "se3 position",
            put(&se3, "initial", "position", &three),
            "`initial.position`",
            "expected 3 numbers, got 6",
        ),
        (
            "cfk nodes",
            put(&cfk, "lattice", "nodes", "[48, 48, 48]"),
            "`lattice.nodes`",
            "expected 2 integers, got 3",
        ),
        (
            "cfk mode",
            put(&cfk, "initial", "mode", &format!("[1, 1, {junk}")),
            "`initial.mode`",
            "expected 2 integers, got 5",
        ),
    ];
    for (what, text, key, message) in cases {
        let err = failing(&format!("vector-{}", what.replace(' ', "-")), &text);
        assert!(
            err.contains(key) && err.contains(message),
            "{what}: expected {key}: {message}, got:\n{err}"
        );
        assert_eq!(
            err.lines().filter(|l| l.starts_with("error:")).count(),
            1,
            "{what}: {err}"
        );
    }
    // The same keys well formed still run (the bases are valid).
    for (what, text) in [
        ("rod", &rod),
        ("beam", &beam),
        ("kepler", &kepler),
        ("top", &top),
        ("cfk", &cfk),
    ] {
        let (ok, err, _) = crate::common::run(&format!("vector-valid-{what}"), text);
        assert!(ok, "{what}: {err}");
    }
}
