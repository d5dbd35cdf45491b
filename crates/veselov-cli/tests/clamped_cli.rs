//! Rods and beams held at one end: the tip's displacement and rotation, the
//! largest deflection and the support's reaction in `summary.json`, read
//! against the files the run wrote (`centerline.npy`, `frames.npy`) and
//! against the statics of a settled cantilever.

mod common;
use common::{example, npy_data, npy_shape, run, set, summary};

/// `s[key]` as three numbers.
fn vector(s: &serde_json::Value, key: &str) -> [f64; 3] {
    let v = s[key]
        .as_array()
        .unwrap_or_else(|| panic!("{key} is not an array: {s}"));
    assert_eq!(v.len(), 3, "{key}");
    std::array::from_fn(|i| v[i].as_f64().expect("a number"))
}

fn number(s: &serde_json::Value, key: &str) -> f64 {
    s[key].as_f64().unwrap_or_else(|| panic!("{key} is not a number: {s}"))
}

fn norm(v: [f64; 3]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Point `k` of row `row` of a centreline (rows × nodes × 3).
fn point(data: &[f64], nodes: usize, row: usize, k: usize) -> [f64; 3] {
    std::array::from_fn(|a| data[(row * nodes + k) * 3 + a])
}

/// The summary's tip and deflection against `centerline.npy`: the tip
/// displacement is its last point minus its first (to 1e-12), its
/// magnitude the norm, and the largest deflection the largest distance of
/// a node from its first-row place, at that node's material coordinate.
fn tip_agrees_with_the_centreline(s: &serde_json::Value, out: &std::path::Path, length: f64) {
    let shape = npy_shape(&out.join("centerline.npy"));
    let (rows, nodes) = (shape[0], shape[1]);
    assert_eq!(shape[2], 3);
    let data = npy_data(&out.join("centerline.npy"));
    let (first, last) = (
        point(&data, nodes, 0, nodes - 1),
        point(&data, nodes, rows - 1, nodes - 1),
    );
    let u = vector(s, "tip_displacement");
    for a in 0..3 {
        assert!(
            (u[a] - (last[a] - first[a])).abs() <= 1e-12,
            "tip_displacement {u:?}: {s}"
        );
    }
    assert!((number(s, "tip_displacement_magnitude") - norm(u)).abs() <= 1e-15);
    assert_eq!(s["tip_end"], "end");
    assert_eq!(number(s, "tip_s"), length);
    let (mut largest, mut at) = (0.0_f64, 0);
    for k in 0..nodes {
        let (a, b) = (point(&data, nodes, 0, k), point(&data, nodes, rows - 1, k));
        let d = norm([b[0] - a[0], b[1] - a[1], b[2] - a[2]]);
        if d > largest {
            (largest, at) = (d, k);
        }
    }
    assert!((number(s, "deflection_max") - largest).abs() <= 1e-15, "{s}");
    let s_at = length * at as f64 / (nodes - 1) as f64;
    assert!((number(s, "deflection_max_s") - s_at).abs() <= 1e-12 * length, "{s}");
    // The rotation vector's norm is the angle.
    let theta = vector(s, "tip_rotation_vector");
    assert!((number(s, "tip_rotation_angle") - norm(theta)).abs() <= 1e-15);
}

/// The damped cantilever of `examples/rod_cantilever_damped.toml` (21
/// material points, to keep the test short), clamped at s = 0 under the end
/// force F = (0.0146, 0, 0) N, settles by t = 20 s: its slowest mode decays
/// as e^{−ω₁t}, ω₁ ≈ 0.88 rad/s, from the end of the 1 s ramp, so the
/// momentum still changing and the damping forces are a few 1e-8 of the
/// load (e^{−0.88·19} ≈ 5e-8). The reaction from the momentum balance is then
/// −F to 1e-6 of |F|, and its moment about the clamp −(r_tip − r_s) × F to
/// 1e-6 of |r_tip − r_s||F|, r_tip and r_s from `centerline.npy`; with the
/// force doubled, so is the reaction (the balance is not a constant). The
/// tip and deflection keys agree with the centreline file.
#[test]
fn a_settled_cantilever_rod_reports_its_tip_and_the_reaction_of_its_clamp() {
    let text = set(&example("rod_cantilever_damped.toml"), "nodes", "21");
    for scale in [1.0, 2.0] {
        let force = [0.0146 * scale, 0.0, 0.0];
        let text = set(&text, "end_force", &format!("[{}, 0.0, 0.0]", force[0]));
        let (ok, err, out) = run(&format!("rod-clamp-{scale}"), &text);
        assert!(ok, "{err}");
        let s = summary(&out);
        assert_eq!(s["status"], "ok");
        tip_agrees_with_the_centreline(&s, &out, 1.0);
        assert_eq!(s["reaction_end"], "start");
        let f = vector(&s, "reaction_force");
        let error = norm([f[0] + force[0], f[1] + force[1], f[2] + force[2]]);
        println!("reaction {f:?} against −{force:?}: error {error:e} N");
        assert!(error <= 1e-6 * norm(force), "reaction {f:?} against −{force:?}");
        let shape = npy_shape(&out.join("centerline.npy"));
        let (rows, nodes) = (shape[0], shape[1]);
        let data = npy_data(&out.join("centerline.npy"));
        let (r_s, r_tip) = (
            point(&data, nodes, rows - 1, 0),
            point(&data, nodes, rows - 1, nodes - 1),
        );
        let arm = [r_tip[0] - r_s[0], r_tip[1] - r_s[1], r_tip[2] - r_s[2]];
        let expected = cross(arm, force).map(|x| -x);
        let m = vector(&s, "reaction_moment");
        let error = norm([m[0] - expected[0], m[1] - expected[1], m[2] - expected[2]]);
        println!("moment {m:?} against {expected:?}: error {error:e} N·m");
        assert!(
            error <= 1e-6 * norm(arm) * norm(force),
            "moment {m:?} against {expected:?}"
        );
        // The tip moved along the force and turned about y.
        assert!(vector(&s, "tip_displacement")[0] > 0.0 && vector(&s, "tip_rotation_vector")[1] > 0.0);
    }
}

/// A free rod has no support: the tip, deflection and reaction keys are
/// null; a rod clamped at both ends has no tip and no single reaction, but
/// a deflection.
#[test]
fn free_and_doubly_held_rods_report_only_what_is_defined() {
    let free = set(&example("rod_free_tumbling.toml"), "t_end", "0.05");
    let (ok, err, out) = run("rod-free", &free);
    assert!(ok, "{err}");
    let s = summary(&out);
    for key in [
        "tip_end",
        "tip_displacement",
        "deflection_max",
        "reaction_force",
        "reaction_moment",
    ] {
        assert!(s[key].is_null(), "{key}: {s}");
    }
    let both = "[model]\nname = \"cosserat-rod\"\nlength = 1.0\nnodes = 11\nradius = 0.05\ndensity = 1000.0\n\
                young = 1e5\npoisson = 0.5\n[ends]\nstart = \"clamped\"\nend = \"clamped\"\n[loads]\n\
                gravity = [9.81, 0.0, 0.0]\n[time]\nt_end = 0.2\n";
    let (ok, err, out) = run("rod-both", both);
    assert!(ok, "{err}");
    let s = summary(&out);
    assert!(s["tip_end"].is_null() && s["reaction_force"].is_null(), "{s}");
    // Sagging under gravity along x, most away from the clamps.
    assert!(number(&s, "deflection_max") > 0.0);
    let at = number(&s, "deflection_max_s");
    assert!(at > 0.0 && at < 1.0, "{s}");
}

/// The damped beam cantilever of `examples/beam_cantilever_damped.toml`
/// writes `centerline.npy` (rows × nodes × 3, the positions of
/// `frames.npy`), its summary has the tip keys agreeing with that file, and,
/// settled under gravity (critically damped, e^{−ω₁t} ≈ 4e-12 at 1.5 s), the
/// clamp carries the beam's weight: F = −ρAL𝐠 to 1e-6, and its moment about
/// the clamp is −Σ_k w_k (r_k − r_s) × ρAΔs𝐠 with the trapezoidal weights
/// w_k (½ at the ends: the potential is averaged over each cell's space
/// edge), to 1e-6 of its size.
#[test]
fn a_settled_beam_cantilever_writes_its_centreline_and_carries_its_weight() {
    let (ok, err, out) = run("beam-clamp", &example("beam_cantilever_damped.toml"));
    assert!(ok, "{err}");
    let s = summary(&out);
    assert_eq!(s["status"], "ok");
    let shape = npy_shape(&out.join("centerline.npy"));
    let frames = npy_data(&out.join("frames.npy"));
    let line = npy_data(&out.join("centerline.npy"));
    assert_eq!(npy_shape(&out.join("frames.npy"))[..2], shape[..2]);
    let (rows, nodes) = (shape[0], shape[1]);
    for i in 0..rows * nodes {
        assert_eq!(line[3 * i..3 * i + 3], frames[12 * i + 9..12 * i + 12], "point {i}");
    }
    tip_agrees_with_the_centreline(&s, &out, 1.0);
    // The example: a 0.05 m square section, ρ = 1000, L = 1, g = (0, −9.81, 0).
    let (rho_a, length, g) = (1000.0 * 0.05 * 0.05, 1.0, [0.0, -9.81, 0.0]);
    let weight = g.map(|x| rho_a * length * x);
    let f = vector(&s, "reaction_force");
    let error = norm([f[0] + weight[0], f[1] + weight[1], f[2] + weight[2]]);
    println!("beam reaction {f:?} against the weight {weight:?}: error {error:e} N");
    assert!(error <= 1e-6 * norm(weight), "reaction {f:?}");
    let ds = length / (nodes - 1) as f64;
    let r_s = point(&line, nodes, rows - 1, 0);
    let mut expected = [0.0; 3];
    for k in 0..nodes {
        let w = if k == 0 || k == nodes - 1 { 0.5 } else { 1.0 };
        let r = point(&line, nodes, rows - 1, k);
        let torque = cross(
            [r[0] - r_s[0], r[1] - r_s[1], r[2] - r_s[2]],
            g.map(|x| w * rho_a * ds * x),
        );
        for a in 0..3 {
            expected[a] -= torque[a];
        }
    }
    let m = vector(&s, "reaction_moment");
    let error = norm([m[0] - expected[0], m[1] - expected[1], m[2] - expected[2]]);
    println!("beam moment {m:?} against {expected:?}: error {error:e} N·m");
    assert!(error <= 1e-6 * norm(expected), "moment {m:?} against {expected:?}");
}
