//! The beam kind of `veselov run` (`[model] name = "beam"`, seed 000): time
//! and space evolution from the command line, outputs, the momentum maps read
//! back, the step limit and errors naming the key.

mod common;
use common::{csv, example, npy_shape, run, set, summary};

#[test]
fn free_free_time_evolution_keeps_its_momentum_map() {
    let text = set(&example("beam_free_free.toml"), "t_end", "0.05");
    let (ok, err, out) = run("free", &text);
    assert!(ok, "{err}");
    let s = summary(&out);
    assert_eq!(s["status"], "ok");
    let (header, m) = csv(&out.join("momentum.csv"));
    assert_eq!(header.join(","), "level,t,J_wx,J_wy,J_wz,J_vx,J_vy,J_vz");
    assert_eq!(npy_shape(&out.join("frames.npy")), [m.len(), 21, 12]);
    let last = &m[m.len() - 1];
    assert!((last[1] - 0.05).abs() < 1e-12, "ends at t_end: {}", last[1]);
    // Relative to the size of the momentum terms Σ|J^k| (the map itself is
    // zero for a beam released at rest).
    assert!(s["momentum_map_drift"].as_f64().expect("drift") <= 1e-10, "{s}");
    let (eh, e) = csv(&out.join("energy.csv"));
    assert_eq!(eh.join(","), "level,t,energy");
    assert!(e.iter().all(|r| r[2].is_finite() && r[2] > 0.0));
    for plot in ["centerline_xz.svg", "centerline_yz.svg", "momentum.svg", "energy.svg"] {
        assert!(out.join(plot).exists(), "no {plot}");
    }
}

#[test]
fn paper_space_evolution_well_posed_reaches_the_end_and_literal_stops_cleanly() {
    let (ok, err, out) = run("well-posed", &example("beam_paper_space_well_posed.toml"));
    assert!(ok, "{err}");
    let s = summary(&out);
    assert_eq!(s["levels"], 40);
    assert!(s["momentum_map_drift"].as_f64().expect("drift") <= 1e-10, "{s}");
    let (header, m) = csv(&out.join("momentum.csv"));
    assert!(header.join(",").starts_with("level,s,"));
    assert!((m[m.len() - 1][1] - 0.8).abs() < 1e-12);
    assert_eq!(npy_shape(&out.join("frames.npy")), [m.len(), 52, 12]);
    let (ok, err, out) = run("literal", &example("beam_paper_space.toml"));
    assert!(!ok && err.starts_with("error: ") && err.contains("(j, a)"), "{err}");
    assert!(!err.contains("panicked"));
    assert_eq!(summary(&out)["status"], "error");
    assert!(
        !csv(&out.join("momentum.csv")).1.is_empty(),
        "the columns computed are kept"
    );
}

#[test]
fn step_limit_is_enforced_unless_overridden() {
    let text = set(&example("beam_free_free.toml"), "t_end", "0.05\ndt = 0.01");
    let (ok, err, _) = run("fast", &text);
    assert!(
        !ok && err.contains("time.dt") && err.contains("allow_unstable"),
        "{err}"
    );
    let forced = text.replace("[method]", "[method]\nallow_unstable = true");
    let (_, err, out) = run("forced", &forced);
    assert!(err.starts_with("warning"), "{err}");
    assert!(!err.contains("panicked"));
    let (_, m) = csv(&out.join("momentum.csv"));
    assert!(m.iter().flatten().all(|x| x.is_finite()));
}

#[test]
fn bad_beam_input_names_the_key() {
    let base = example("beam_free_free.toml");
    let space = example("beam_paper_space_well_posed.toml");
    let cases = [
        (set(&base, "young", "-1.0"), "model.young"),
        (set(&base, "nodes", "2"), "model.nodes"),
        (base.replace("[time]", "[time]\nsteps = 3"), "steps"),
        (set(&base, "evolution", "\"diagonal\""), "method.evolution"),
        (set(&base, "retraction", "\"quaternion\""), "method.retraction"),
        (set(&base, "shape", "\"paper\""), "initial.shape"),
        (set(&space, "nodes", "21"), "model.nodes"),
        (
            space.replace("[initial]", "[ends]\nstart = \"clamped\"\n\n[initial]"),
            "ends.start",
        ),
        (
            base.replace("[initial]", "[loads]\ndamping = [0, 0, 0, -1, 0, 0]\n\n[initial]"),
            "loads.damping[3]",
        ),
    ];
    for (text, key) in cases {
        let (ok, err, _) = run("bad", &text);
        assert!(!ok && err.contains(key), "expected an error naming {key}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}
