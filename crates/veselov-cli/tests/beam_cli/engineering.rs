//! The beam as an engineering model: an end force and torque with a ramp,
//! driven ends, velocity fields and motions r(s, t), θ(s, t) as initial
//! data, rows from t = 0, and the errors naming the key.

use crate::common::{csv, example, npy_data, npy_shape, run, set, summary};

/// The damped cantilever of `examples/beam_end_force.toml` settles to
/// Timoshenko's tip deflection FL³/(3EI) + FL/(kGA) (F = 5 N: 0.027171 m)
/// within the discretisation error of its 10 cells (2.4e-3 relative, the
/// library's convergence test) plus the geometric nonlinearity (δ/L)² ≈
/// 7e-4: measured 0.99674 of it. The support balances the load: F_R = −F to
/// the settling tolerance, M_R = F times the deflected arm 1 − w_z.
#[test]
fn a_cantilever_under_an_end_force_settles_to_timoshenko() {
    let (ok, err, out) = run("end-force", &example("beam_end_force.toml"));
    assert!(ok, "{err}");
    let s = summary(&out);
    let (e, nu, side, length, force) = (1.18e8_f64, 0.3, 0.05_f64, 1.0_f64, 5.0);
    let (area, inertia) = (side * side, side.powi(4) / 12.0);
    let kappa = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu);
    let shear = e / (2.0 * (1.0 + nu));
    let timoshenko = force * length.powi(3) / (3.0 * e * inertia) + force * length / (kappa * shear * area);
    let tip = &s["tip_displacement"];
    let ratio = -tip[1].as_f64().expect("tip") / timoshenko;
    assert!((ratio - 1.0).abs() < 4e-3, "tip / Timoshenko = {ratio}");
    let reaction: Vec<f64> = (0..3).map(|i| s["reaction_force"][i].as_f64().expect("F")).collect();
    assert!((reaction[1] - force).abs() < 1e-6 * force, "{reaction:?}");
    let arm = length + tip[2].as_f64().expect("tip z");
    let moment = s["reaction_moment"][0].as_f64().expect("M");
    assert!(
        (moment + force * arm).abs() < 1e-6 * force,
        "M = {moment}, F·arm = {}",
        force * arm
    );
    assert_eq!(s["end_force"][1], -5.0);
    // A loaded run conserves no energy: it is not judged.
    assert!(s["warnings"].as_array().expect("warnings").is_empty(), "{s}");
}

/// Rows start at t = 0 with the initial shape itself (the bent arc of
/// curvature κ: node a at ((1 − cos κs)/κ about E1 … ) and end at t_end.
#[test]
fn rows_start_at_t_zero_with_the_initial_shape() {
    let text = set(&example("beam_free_free.toml"), "t_end", "0.02");
    let (ok, err, out) = run("from-zero", &text);
    assert!(ok, "{err}");
    let (_, m) = csv(&out.join("momentum.csv"));
    assert_eq!(m[0][0], 0.0);
    assert_eq!(m[0][1], 0.0);
    assert!((m[m.len() - 1][1] - 0.02).abs() < 1e-15);
    let shape = npy_shape(&out.join("frames.npy"));
    assert_eq!(shape, [m.len(), 21, 12]);
    let frames = npy_data(&out.join("frames.npy"));
    // The Cayley arc of curvature 1 about E1: its nodes lie on the circle
    // y² + (z … ) of radius 1 through the origin, tangent to E3 there:
    // (y + 1)² + z² = 1 in the y–z plane (bending about E1 turns E3 towards −E2).
    for a in 0..21 {
        let p = &frames[a * 12 + 9..a * 12 + 12];
        assert!(p[0].abs() < 1e-15, "node {a}: {p:?}");
        let radius = ((p[1] + 1.0).powi(2) + p[2] * p[2]).sqrt();
        assert!((radius - 1.0).abs() < 1e-12, "node {a} at {p:?}: radius {radius}");
    }
    let s = summary(&out);
    assert_eq!(s["steps"], s["levels"]);
    assert_eq!(s["kinetic_quadrature"], "trapezoid");
}

/// A free beam given a uniform velocity translates rigidly: every node
/// moves by v·t to round-off, its linear momentum is ρA·L·v, and a motion
/// r(s, t) = (0.1t, 0, s) sampled at t = −Δt and 0 starts the same run.
#[test]
fn velocity_fields_and_motions_start_the_same_rigid_translation() {
    let base = set(&example("beam_free_free.toml"), "t_end", "0.02");
    let shape = "shape = \"bent\"\ncurvature = 1.0          # 1/m, about E1";
    let by_velocity = base.replace(shape, "shape = \"straight\"\nvelocity = [0.1, \"0\", 0]");
    let by_motion = base.replace(shape, "position = [\"0.1*t\", \"0\", \"s\"]");
    assert_ne!(by_velocity, base);
    let (ok, err, out) = run("velocity", &by_velocity);
    assert!(ok, "{err}");
    let frames = npy_data(&out.join("frames.npy"));
    let (_, m) = csv(&out.join("momentum.csv"));
    let rows = m.len();
    for (row, line) in m.iter().enumerate() {
        let t = line[1];
        for a in 0..21 {
            let p = &frames[(row * 21 + a) * 12 + 9..(row * 21 + a) * 12 + 12];
            let expected = [0.1 * t, 0.0, a as f64 * 0.04];
            for k in 0..3 {
                assert!(
                    (p[k] - expected[k]).abs() < 1e-14,
                    "row {row}, node {a}: {p:?} against {expected:?}"
                );
            }
        }
        // J_v = ρA L v (ρA = 1000 · 0.05²).
        assert!((line[5] - 2.5 * 0.8 * 0.1).abs() < 1e-14, "{line:?}");
    }
    let (ok, err, by_motion_out) = run("motion", &by_motion);
    assert!(ok, "{err}");
    let other = npy_data(&by_motion_out.join("frames.npy"));
    assert_eq!(other.len(), rows * 21 * 12);
    let worst = frames
        .iter()
        .zip(&other)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-14, "velocity and motion starts differ by {worst:e}");
}

/// A driven start follows its prescribed motion at every row.
#[test]
fn a_driven_end_follows_its_motion() {
    let base = set(&example("beam_cantilever.toml"), "t_end", "0.05");
    let text = base.replace("start = \"clamped\"", "start = \"driven\"").replace(
        "end = \"free\"",
        "end = \"free\"\n[ends.start_motion]\ndisplacement = [\"0\", \"0.001*sin(40*t)\", \"0\"]\nrotation = [\"0.01*sin(20*t)\", \"0\", \"0\"]",
    );
    let text = text.replace("[initial]\nshape = \"bent\"", "[initial]\nshape = \"straight\"");
    assert!(text.contains("[ends.start_motion]") && text.contains("shape = \"straight\""));
    let (ok, err, out) = run("driven", &text);
    assert!(ok, "{err}");
    let frames = npy_data(&out.join("frames.npy"));
    let (_, m) = csv(&out.join("momentum.csv"));
    for (row, line) in m.iter().enumerate() {
        let t = line[1];
        let node = &frames[row * 21 * 12..row * 21 * 12 + 12];
        assert!(
            (node[10] - 0.001 * (40.0 * t).sin()).abs() < 1e-15,
            "row {row}: {node:?}"
        );
        // R = exp(θ e₁): R[1][1] = cos θ.
        assert!(
            (node[4] - (0.01 * (20.0 * t).sin()).cos()).abs() < 1e-15,
            "row {row}: {node:?}"
        );
    }
    let s = summary(&out);
    assert_eq!(s["ends"][0], "driven");
}

#[test]
fn bad_engineering_input_names_the_key() {
    let cantilever = example("beam_cantilever.toml");
    let free = example("beam_free_free.toml");
    let cases = [
        (
            cantilever.replace("end = \"free\"", "end = \"clamped\"\n[loads]\nend_force = [0, 1, 0]"),
            "loads.end_force",
        ),
        (
            cantilever.replace("start = \"clamped\"", "start = \"driven\""),
            "ends.start_motion",
        ),
        (
            cantilever.replace(
                "end = \"free\"",
                "end = \"free\"\n[ends.end_motion]\ndisplacement = [\"t\", \"0\", \"0\"]",
            ),
            "ends.end_motion",
        ),
        (
            cantilever.replace("start = \"clamped\"", "start = \"driven\"").replace(
                "end = \"free\"",
                "end = \"free\"\n[ends.start_motion]\ndisplacement = [\"1 + t\", \"0\", \"0\"]",
            ),
            "ends.start_motion.displacement",
        ),
        (
            free.replace(
                "curvature = 1.0          # 1/m, about E1",
                "curvature = 1.0\nposition = [\"0\", \"0\", \"s\"]",
            ),
            "initial.shape",
        ),
        (
            free.replace(
                "shape = \"bent\"",
                "rotation_vector = [\"0\", \"0\", \"s\"]\nshape = \"bent\"",
            ),
            "initial.shape",
        ),
        (
            free.replace(
                "curvature = 1.0          # 1/m, about E1",
                "velocity = [\"0\", \"wobble*s\", \"0\"]",
            ),
            "initial.velocity[1]",
        ),
        (
            free.replace(
                "curvature = 1.0          # 1/m, about E1",
                "angular_velocity = [\"1/(s - 0.4)\", \"0\", \"0\"]",
            ),
            "initial.angular_velocity[0]",
        ),
        (
            free.replace(
                "shape = \"bent\"\ncurvature = 1.0          # 1/m, about E1",
                "position = [\"0\", \"q\", \"s\"]",
            ),
            "initial.position[1]",
        ),
        (
            free.replace("[time]", "[loads]\nend_force = [0, 1, 0]\nramp = -1\n[time]"),
            "loads.ramp",
        ),
    ];
    for (i, (text, key)) in cases.iter().enumerate() {
        assert_ne!(text, &cantilever, "case {i} changed nothing");
        let (ok, err, _) = run(&format!("bad-{i}"), text);
        assert!(
            !ok && err.contains(key) && !err.contains("panicked"),
            "case {i} ({key}): {err}"
        );
    }
    let (ok, err, _) = run(
        "space-load",
        &example("beam_paper_space_well_posed.toml").replace("[initial]", "[loads]\nend_force = [0, 1, 0]\n[initial]"),
    );
    assert!(!ok && err.contains("loads.end_force"), "{err}");
}

/// Under an end torque M about E1 alone the bending moment is M along the
/// whole beam: the settled beam is an arc of curvature M/EI, its tip turned
/// by ML/EI (0.2 rad here) for any size of M. The Cayley increment and its
/// pulled-back moments err at second order in κΔs = 0.02 (each cell turns
/// by 2 atan(κΔs/2), and the moment balance carries dcay⁻¹, 1 + O((κΔs)²)):
/// measured 1.3e-4 relative, within (κΔs)²/2 = 2e-4. The clamp's reaction
/// moment is −M and its force zero.
#[test]
fn a_cantilever_under_an_end_torque_settles_to_a_circular_arc() {
    let ei = 1.18e8 * 0.05_f64.powi(4) / 12.0;
    let torque = 0.2 * ei;
    let text = example("beam_end_force.toml")
        .replace("end_force = [0.0, -5.0, 0.0]", "end_force = [0.0, 0.0, 0.0]")
        .replace(
            "end_torque = [0.0, 0.0, 0.0]",
            &format!("end_torque = [{torque:?}, 0.0, 0.0]"),
        );
    assert!(text.contains(&format!("{torque:?}")));
    let (ok, err, out) = run("end-torque", &text);
    assert!(ok, "{err}");
    let s = summary(&out);
    let angle = s["tip_rotation_vector"][0].as_f64().expect("angle");
    let kappa_ds = 0.2 / 10.0;
    assert!(
        (angle / 0.2 - 1.0).abs() < 0.5 * kappa_ds * kappa_ds,
        "tip rotation {angle} against ML/EI = 0.2"
    );
    let moment = s["reaction_moment"][0].as_f64().expect("M");
    assert!(
        (moment + torque).abs() < 1e-6 * torque,
        "M_R = {moment} against −{torque}"
    );
    let force = (0..3)
        .map(|i| s["reaction_force"][i].as_f64().expect("F").abs())
        .fold(0.0, f64::max);
    assert!(force < 1e-6 * torque, "F_R = {force:e}");
}
