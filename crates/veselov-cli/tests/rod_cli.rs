//! The Cosserat-rod kind of `veselov run` (`[model] name = "cosserat-rod"`):
//! outputs, momentum balances read back from the files, the step limit and
//! errors naming the key.

mod common;
#[path = "rod_cli/initial_state.rs"]
mod initial_state;
use common::{csv, example, npy_data, npy_shape, run, set, summary};

#[test]
fn free_rod_writes_its_outputs_and_keeps_its_momenta() {
    let text = set(&example("rod_free_tumbling.toml"), "t_end", "0.5");
    let (ok, err, out) = run("free", &text);
    assert!(ok, "{err}");
    let s = summary(&out);
    assert_eq!(s["status"], "ok");
    let (header, rows) = csv(&out.join("momentum.csv"));
    assert_eq!(header, ["t", "P_x", "P_y", "P_z", "L_x", "L_y", "L_z"]);
    let n = rows.len();
    let nodes = s["nodes"].as_u64().expect("a node count") as usize;
    assert_eq!(nodes, 151, "the example's node count");
    assert_eq!(npy_shape(&out.join("centerline.npy")), [n, nodes, 3]);
    assert_eq!(npy_shape(&out.join("frames.npy")), [n, nodes, 9]);
    assert_eq!(rows[0][0], 0.0);
    assert!((rows[n - 1][0] - 0.5).abs() < 1e-12, "ends at t_end");
    // Conserved to round-off (the rod moves: |P| ≈ 0.1 M).
    for (range, bound) in [(1..4, 1e-12), (4..7, 1e-10)] {
        let scale = rows
            .iter()
            .flat_map(|r| r[range.clone()].to_vec())
            .fold(0.0_f64, |m, x| m.max(x.abs()));
        let drift = rows
            .iter()
            .flat_map(|r| range.clone().map(|i| (r[i] - rows[0][i]).abs()).collect::<Vec<_>>())
            .fold(0.0_f64, f64::max);
        assert!(
            scale > 1e-3 && drift <= bound * scale,
            "{range:?}: {drift:e} of {scale:e}"
        );
    }
    assert!(s["linear_momentum_balance_error"].as_f64().expect("number") <= 1e-12);
    // The vertex equations are the discrete Euler–Lagrange equations, solved
    // to the default tolerance 1e-14 (or accepted at round-off).
    let el = s["el_residual_max"].as_f64().expect("number");
    println!("el_residual_max {el:e}");
    assert!(el > 0.0 && el <= 1e-12, "EL residual {el:e}");
    let (eh, energy) = csv(&out.join("energy.csv"));
    assert_eq!(eh, ["t", "energy"]);
    assert_eq!(energy.len(), n);
    for plot in ["centerline_xz.svg", "centerline_yz.svg", "momentum.svg", "energy.svg"] {
        assert!(out.join(plot).exists(), "no {plot}");
    }
}

#[test]
fn falling_rod_gains_the_momentum_of_its_weight() {
    let text = set(&example("rod_gravity.toml"), "t_end", "0.3");
    let (ok, err, out) = run("gravity", &text);
    assert!(ok, "{err}");
    let (_, rows) = csv(&out.join("momentum.csv"));
    // M = ρAL; P_z(t) − P_z(0) = −M g t exactly in the discrete balance.
    let mass = 1000.0 * std::f64::consts::PI * 0.02_f64.powi(2) * 1.0;
    let mut worst = 0.0_f64;
    for r in &rows {
        let expected = -mass * 9.81 * r[0];
        worst = worst.max((r[3] - rows[0][3] - expected).abs() / (mass * 9.81 * 0.3));
        assert!((r[1] - rows[0][1]).abs() < 1e-12 && (r[2] - rows[0][2]).abs() < 1e-12);
    }
    assert!(worst < 1e-12, "{worst:e}");
    assert!(
        summary(&out)["angular_momentum_balance_error"]
            .as_f64()
            .expect("number")
            <= 1e-12
    );
}

/// Material points far apart against the rod's bending length are warned
/// about (shear locking, `models::rod::resolution`: the lattice bends as if
/// stiffer by 0.245Λ, Λ = κGAδ²/EI), with the node count that brings it to
/// 1 %; summary.json gives Λ and the estimate either way. The example's
/// own lattice is resolved and not warned about.
#[test]
fn coarse_bending_resolution_is_warned_about() {
    let base = set(&example("rod_cantilever_damped.toml"), "t_end", "0.05");
    // κGA/EI = κ(G/E)(A/I) = 0.9 · (1/3) · 4/r² = 1.2/r² (ν = 0.5, r = 0.05).
    let locking = |delta: f64| 1.2 * (delta / 0.05_f64).powi(2);
    let (ok, err, out) = run("resolved", &base);
    assert!(ok, "{err}");
    assert!(!err.contains("coarsely resolved"), "{err}");
    let s = summary(&out);
    let number = s["bending_locking_number"].as_f64().expect("a number");
    assert!((number / locking(1.0 / 80.0) - 1.0).abs() < 1e-12, "{s}");
    let (ok, err, out) = run("coarse", &set(&base, "nodes", "21"));
    assert!(ok, "{err}");
    let warning = err
        .lines()
        .find(|l| l.contains("coarsely resolved"))
        .unwrap_or_default();
    // Λ = 1.2 at δ = r: 29 % stiffer, deflections 23 % short; 1 % needs
    // δ ≤ r·√(0.01/(0.245 · 1.2)) = 0.00922 m, 110 nodes.
    assert!(
        warning.starts_with("warning:")
            && warning.contains("1.200")
            && warning.contains("about 29 % stiffer")
            && warning.contains("about 23 % short")
            && warning.contains("nodes = 110 or more"),
        "{err}"
    );
    let s = summary(&out);
    let stiffening = s["bending_stiffening_estimate"].as_f64().expect("a number");
    assert!((stiffening / (0.245 * locking(0.05)) - 1.0).abs() < 1e-12, "{s}");
}

/// `[method] shear_frame = "centred"` removes the locking: the coarse
/// cantilever above runs without the warning, its summary says which frame
/// and gives no stiffening estimate, and it settles within 0.1 % of
/// Timoshenko's tip deflection FL³/3EI + FL/κGA on 21 nodes, where Prop.
/// 6.5's frame falls 23 % short. Bad values name the key.
#[test]
fn the_centred_shear_frame_is_not_warned_about_and_does_not_lock() {
    let base = set(&example("rod_cantilever_damped.toml"), "nodes", "21")
        .replace("[output]", "[method]\nshear_frame = \"centred\"\n\n[output]");
    let (ok, err, out) = run("centred", &base);
    assert!(ok, "{err}");
    assert!(!err.contains("coarsely resolved"), "{err}");
    let s = summary(&out);
    assert_eq!(s["shear_frame"], "centred", "{s}");
    assert!(s["bending_stiffening_estimate"].is_null(), "{s}");
    // E = 1e5, ν = 0.5, r = 0.05, κ = 0.9, F = 0.0146, L = 1.
    let (r, e, force) = (0.05_f64, 1e5, 0.0146);
    let (area, inertia) = (std::f64::consts::PI * r * r, std::f64::consts::PI * r.powi(4) / 4.0);
    let exact = force / (3.0 * e * inertia) + force / (0.9 * e / 3.0 * area);
    let (shape, data) = (
        npy_shape(&out.join("centerline.npy")),
        npy_data(&out.join("centerline.npy")),
    );
    let tip = data[(shape[0] - 1) * shape[1] * 3 + (shape[1] - 1) * 3];
    assert!(
        (tip / exact - 1.0).abs() < 1e-3,
        "tip {tip:e} against Timoshenko {exact:e}"
    );
    let (ok, err, _) = run("bad", &set(&base, "shear_frame", "\"middle\""));
    assert!(
        !ok && err.contains("method.shear_frame") && err.contains("vertex | centred"),
        "{err}"
    );
    let (ok, err, _) = run("bad", &base.replace("[method]", "[method]\nquadrature = \"symmetric\""));
    assert!(!ok && err.contains("method.shear_frame"), "{err}");
}

#[test]
fn damped_cantilever_comes_to_rest_with_a_clamped_end() {
    let text = set(&example("rod_cantilever_damped.toml"), "nodes", "21");
    let (ok, err, out) = run("cantilever", &text);
    assert!(ok, "{err}");
    let s = summary(&out);
    assert!(
        s["linear_momentum_balance_error"].is_null(),
        "no balance with a support"
    );
    let (_, rows) = csv(&out.join("momentum.csv"));
    let last = &rows[rows.len() - 1];
    let peak = rows.iter().map(|r| r[1].abs()).fold(0.0_f64, f64::max);
    assert!(last[1].abs() < 1e-6 * peak, "still moving: {} of {peak}", last[1]);
}

#[test]
fn above_the_step_limit_the_run_is_refused_or_fails_cleanly() {
    let base = example("rod_free_tumbling.toml");
    let fast = set(&base, "t_end", "0.5\ndt = 0.02");
    let (ok, err, _) = run("unstable", &fast);
    assert!(
        !ok && err.contains("time.dt") && err.contains("allow_unstable"),
        "{err}"
    );
    // A dt changed to land on t_end is refused with the value asked for
    // beside the one the march would take (10 s asked, one step of 0.5 s).
    let (ok, err, _) = run("adjusted", &set(&base, "t_end", "0.5\ndt = 10.0"));
    assert!(
        !ok && err.contains("dt = 0.5 (the 10 asked for, adjusted to land on t_end = 0.5)"),
        "{err}"
    );
    let forced = fast.replace("[output]", "[method]\nallow_unstable = true\n\n[output]");
    let (ok, err, out) = run("forced", &forced);
    assert!(!ok && err.starts_with("warning") && err.contains("error: "), "{err}");
    assert!(!err.contains("panicked"));
    let s = summary(&out);
    assert_eq!(s["status"], "error", "{s}");
    // A solver failure, placed at the step the run was taking.
    assert_eq!(s["failure"]["kind"], "vertex_solve_failure", "{s}");
    assert_eq!(s["failure"]["step"], s["steps"], "{s}");
    assert_eq!(s["failure"]["time"], s["t_final"], "{s}");
    let (_, rows) = csv(&out.join("momentum.csv"));
    assert!(rows.iter().flatten().all(|x| x.is_finite()));
}

/// A rod so long that the terms of its first vertex equation overflow
/// (Δs = 5e298) stops at that vertex with a NaN residual, not the zero the
/// solve starts from, and keeps the levels it was given.
#[test]
fn an_overflowing_vertex_equation_reports_a_nan_residual() {
    let long = "[model]\nname = \"cosserat-rod\"\nnodes = 21\nlength = 1e300\nradius = 0.01\n\
                density = 1000.0\nyoung = 1e5\npoisson = 0.5\n\n[time]\nt_end = 0.05\n";
    let (ok, err, out) = run("overflow", long);
    assert!(!ok && !err.contains("panicked"), "{err}");
    let s = summary(&out);
    assert_eq!(s["failure"]["kind"], "vertex_solve_failure", "{s}");
    let message = s["failure"]["message"].as_str().expect("message");
    assert!(
        message.contains("residual NaN") && message.contains("non-finite"),
        "{message}"
    );
}

#[test]
fn bad_rod_input_names_the_key() {
    let base = example("rod_free_tumbling.toml");
    let cases = [
        (set(&base, "density", "-1.0"), "model.density"),
        (set(&base, "nodes", "2"), "model.nodes"),
        (base.replace("[time]", "[time]\nsteps = 3"), "steps"),
        (
            set(&base, "shape", "\"helix\"").replace("curvature = 1.5", "helix_radius = 0.0"),
            "initial.helix_radius",
        ),
        (set(&base, "shape", "\"spiral\""), "initial.shape"),
        (
            base.replace(
                "[initial]",
                "[ends]\nend = \"clamped\"\n\n[loads]\nend_force = [1.0, 0.0, 0.0]\n\n[initial]",
            ),
            "loads.end_force",
        ),
        (
            base.replace("[initial]", "[ends]\nstart = \"pinned\"\n\n[initial]"),
            "ends.start",
        ),
        (set(&base, "curvature", "10.0"), "initial.curvature"),
        // Subnormal, as the library's parameter checks refuse them.
        (set(&base, "length", "1e-310"), "model.length"),
    ];
    for (text, key) in cases {
        let (ok, err, _) = run("bad", &text);
        assert!(!ok && err.contains(key), "expected an error naming {key}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    // The subnormal value is printed in exponent form, not as 300 digits.
    let (_, err, _) = run("bad", &set(&base, "length", "1e-310"));
    assert!(err.contains("subnormal 1e-310"), "{err}");
}

/// A straight rod, free at s = L, whose start is driven sideways,
/// `Δr = (0, 0.01 sin 20t, 0)`, and twisted: the start point follows the
/// prescribed motion (the centreline output holds it at the cut's level, or at
/// the midpoint of its values half a step before and after, which differ
/// from the motion by at most A ω² Δt²/8), the wave it sends travels into
/// the rod, and the run reports the end as driven.
#[test]
fn a_driven_end_follows_its_prescribed_motion() {
    let text = "[model]\nname = \"cosserat-rod\"\nlength = 1.0\nnodes = 21\nradius = 0.02\ndensity = 1000.0\n\
                young = 1e5\npoisson = 0.5\n[ends]\nstart = \"driven\"\n[ends.start_motion]\n\
                displacement = [\"0\", \"0.01*sin(20*t)\", \"0\"]\nrotation = [\"0\", \"0\", \"0.2*sin(10*t)\"]\n\
                [time]\nt_end = 0.3\n[output]\nevery = 5\n";
    let (ok, err, out) = run("driven", text);
    assert!(ok, "{err}");
    let s = summary(&out);
    assert_eq!(s["ends"][0], "driven", "{s}");
    let dt = s["dt"].as_f64().expect("dt");
    let (_, energy) = csv(&out.join("energy.csv"));
    let shape = npy_shape(&out.join("centerline.npy"));
    let nodes = shape[1];
    let data = npy_data(&out.join("centerline.npy"));
    let bound = 0.01 * 400.0 * dt * dt / 8.0 + 1e-14;
    let mut far = 0.0_f64;
    for (row, e) in energy.iter().enumerate() {
        let t = e[0];
        let y0 = data[row * nodes * 3 + 1];
        assert!(
            (y0 - 0.01 * (20.0 * t).sin()).abs() <= bound,
            "t = {t}: start at y = {y0}, prescribed {}",
            0.01 * (20.0 * t).sin()
        );
        far = far.max(data[(row * nodes + nodes / 2) * 3 + 1].abs());
    }
    assert!(far > 1e-4, "the motion did not reach the middle of the rod ({far:e})");
}

#[test]
fn bad_driven_ends_name_the_key() {
    let base = "[model]\nname = \"cosserat-rod\"\nlength = 1.0\nnodes = 11\nradius = 0.02\ndensity = 1000.0\n\
                young = 1e5\npoisson = 0.5\n[time]\nt_end = 0.01\n";
    for (ends, needles) in [
        (
            "[ends]\nstart = \"driven\"\n[ends.start_motion]\ndisplacement = [\"0\", \"1 + t\", \"0\"]\n",
            &["ends.start_motion.displacement", "vanish at t = 0"][..],
        ),
        (
            "[ends]\nstart = \"driven\"\n[ends.start_motion]\nrotation = [\"0\", \"sin(q)\", \"0\"]\n",
            &["ends.start_motion.rotation[1]"][..],
        ),
        ("[ends]\nend = \"driven\"\n", &["ends.end_motion", "displacement"][..]),
        (
            "[ends]\nstart = \"clamped\"\n[ends.start_motion]\ndisplacement = [\"0\", \"0\", \"0\"]\n",
            &["ends.start_motion", "not \"driven\""][..],
        ),
    ] {
        let (ok, err, _) = run("driven-bad", &format!("{base}{ends}"));
        assert!(!ok, "{ends} ran");
        for n in needles {
            assert!(err.contains(n), "{ends}: {err} lacks {n}");
        }
    }
}

/// The centreline of a rod as expressions in s: the arc of
/// `rod_free_tumbling.toml` written out, `r(s) = ((1 − cos κs)/κ, 0, sin κs/κ)`,
/// framed along its tangent, runs as the built-in bent shape does (the two
/// paths agree to round-off); and bad curves are refused naming the key.
#[test]
fn an_initial_centreline_given_by_expressions_in_s() {
    let built_in = set(&example("rod_free_tumbling.toml"), "t_end", "0.1");
    let curve = built_in.replace(
        "shape = \"bent\"\ncurvature = 1.5          # 1/m",
        "shape = \"curve\"\nposition = [\"(1 - cos(1.5*s))/1.5\", \"0\", \"sin(1.5*s)/1.5\"]",
    );
    assert_ne!(curve, built_in, "the example's shape lines changed");
    let read = |text: &str, name: &str| {
        let (ok, err, out) = run(name, text);
        assert!(ok, "{name}: {err}");
        npy_data(&out.join("centerline.npy"))
    };
    let (a, b) = (read(&built_in, "bent"), read(&curve, "curve"));
    assert_eq!(a.len(), b.len());
    let worst = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-12, "the curve differs from the bent shape by {worst:e}");
    for (text, needle) in [
        (
            curve.replace("\"(1 - cos(1.5*s))/1.5\"", "\"log(s)\""),
            "initial.position",
        ),
        (
            curve
                .replace("\"sin(1.5*s)/1.5\"", "\"0\"")
                .replace("\"(1 - cos(1.5*s))/1.5\"", "\"0\""),
            "non-zero tangent",
        ),
        (
            curve.replace("shape = \"curve\"", "shape = \"straight\""),
            "not \"curve\"",
        ),
        (
            built_in.replace("shape = \"bent\"", "shape = \"curve\""),
            "three expressions in s",
        ),
    ] {
        let (ok, err, _) = run("curve-bad", &text);
        assert!(!ok && err.contains(needle), "{needle}: {err}");
    }
}

/// `[method] quadrature = "symmetric"`: the rod through the core's Q_sym
/// discretisation of the same density (6-D Newton per vertex). It keeps the
/// momenta of a free rod to round-off and solves its Euler–Lagrange
/// equations to the tolerance; it and Prop. 6.5's Q_{v₀} march converge to
/// each other as Δs and Δt are halved together (measured largest centreline
/// gap at t = 0.1: 1.07e-4 at 31 nodes, 4.3e-5 at 61, 1.9e-5 at 121: about
/// first order). Damping and end loads, discrete forces of Q_{v₀}, are
/// refused naming the key.
#[test]
fn symmetric_quadrature_keeps_the_momenta_and_meets_the_vertex_rule() {
    let base = set(&example("rod_free_tumbling.toml"), "t_end", "0.1\ndt = 0.001");
    let with = |text: &str, nodes: &str, dt: &str, quadrature: &str| {
        let text = set(&set(text, "nodes", nodes), "dt", dt);
        text.replace(
            "[output]",
            &format!("[method]\nquadrature = \"{quadrature}\"\n\n[output]"),
        )
    };
    let gap = |nodes: &str, dt: &str| {
        let mut last = Vec::new();
        for q in ["vertex", "symmetric"] {
            let (ok, err, out) = run(&format!("quadrature_{q}_{nodes}"), &with(&base, nodes, dt, q));
            assert!(ok, "{q}: {err}");
            let s = summary(&out);
            assert_eq!(s["quadrature"], q);
            for key in [
                "linear_momentum_balance_error",
                "angular_momentum_balance_error",
                "el_residual_max",
            ] {
                let v = s[key].as_f64().expect("number");
                assert!(v <= 1e-12, "{q}: {key} = {v:e}");
            }
            let data = npy_data(&out.join("centerline.npy"));
            let n: usize = nodes.parse().expect("nodes");
            last.push(data[data.len() - 3 * n..].to_vec());
        }
        last[0]
            .iter()
            .zip(&last[1])
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let (coarse, fine) = (gap("31", "0.001"), gap("61", "0.0005"));
    println!("centreline gap between the quadratures: {coarse:e} (31 nodes), {fine:e} (61 nodes)");
    assert!(coarse > 0.0 && coarse < 1e-3, "{coarse:e}");
    assert!(fine < 0.6 * coarse, "{fine:e} vs {coarse:e}");
    let damped = with(&base, "31", "0.001", "symmetric").replace("[initial]", "[loads]\ndamping = 0.1\n\n[initial]");
    let (ok, err, _) = run("quadrature_damped", &damped);
    assert!(
        !ok && err.contains("`loads.damping`") && err.contains("symmetric"),
        "{err}"
    );
    let (ok, err, _) = run("quadrature_unknown", &with(&base, "31", "0.001", "simpson"));
    assert!(
        !ok && err.contains("`method.quadrature`") && err.contains("simpson"),
        "{err}"
    );
}

/// Material and section varying along the rod (`radius`, `width`,
/// `height`, `density`, `young` as expressions in s): a constant expression
/// reproduces the uniform run bit for bit (the profile path is the uniform
/// one when nothing varies), a tapered free rod keeps its momenta to
/// round-off and moves differently; bad profiles are refused naming the key
/// and the point. (The tapered cantilever's convergence to the tapered
/// Timoshenko deflection is tested in the library, `rod_ends`.)
#[test]
fn material_varying_along_the_rod() {
    let base = set(&example("rod_free_tumbling.toml"), "t_end", "0.2");
    let last_row = |text: &str, name: &str| {
        let (ok, err, out) = run(name, text);
        assert!(ok, "{name}: {err}");
        let s = summary(&out);
        assert!(
            s["linear_momentum_balance_error"].as_f64().expect("number") <= 1e-12,
            "{name}"
        );
        assert!(
            s["angular_momentum_balance_error"].as_f64().expect("number") <= 1e-10,
            "{name}"
        );
        let data = npy_data(&out.join("centerline.npy"));
        data[data.len() - 31 * 3..].to_vec()
    };
    let uniform = last_row(&base, "profile_uniform");
    let constant = last_row(&set(&base, "radius", "\"0.02 + 0*s\""), "profile_constant");
    assert_eq!(uniform, constant);
    let tapered = last_row(
        &set(
            &set(&base, "radius", "\"0.02*(1 - 0.4*s)\""),
            "density",
            "\"1000 + 500*s\"",
        ),
        "profile_tapered",
    );
    let moved = uniform
        .iter()
        .zip(&tapered)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(moved > 1e-6, "the profile is felt: {moved:e}");
    for (key, value, needle) in [
        ("density", "\"1000*(1 - 2*s)\"", "at s = 0.5"),
        ("young", "\"1e5*sqrt(s - 0.5)\"", "at s = 0"),
        ("radius", "\"0.02*(1 +\"", "model.radius"),
    ] {
        let (ok, err, _) = run(&format!("profile_bad_{key}"), &set(&base, key, value));
        assert!(
            !ok && err.contains(&format!("`model.{key}`")) && err.contains(needle),
            "{key}: {err}"
        );
    }
    let (ok, err, _) = run("profile_bad_type", &set(&base, "radius", "true"));
    assert!(
        !ok && err.contains("line") && err.contains("expected a number, or an expression in s"),
        "{err}"
    );
    let symmetric = set(&base, "radius", "\"0.02*(1 - 0.4*s)\"")
        .replace("[output]", "[method]\nquadrature = \"symmetric\"\n\n[output]");
    let (ok, err, _) = run("profile_symmetric", &symmetric);
    assert!(
        !ok && err.contains("`method.quadrature`") && err.contains("uniform"),
        "{err}"
    );
}

/// Initial data whose energy overflows (a velocity of 1e200 m/s) fail the
/// run at its first state: `summary.json` reports the failure at step 0
/// and t = 0, where the run stood (not at the lattice level the march
/// starts from). A rod stiff enough for a step number of 151 digits, run
/// anyway, is warned about with that number in exponent form.
#[test]
fn an_overflowing_start_fails_at_step_zero() {
    let base = example("rod_free_tumbling.toml");
    let text = set(&set(&base, "velocity", "[1e200, 0.0, 0.0]"), "t_end", "0.01");
    let (ok, err, out) = run("overflowing-start", &text);
    assert!(!ok && err.contains("energy"), "{err}");
    let s = summary(&out);
    assert_eq!(s["failure"]["kind"], "non_finite_state", "{s}");
    assert_eq!(s["failure"]["step"], 0, "{s}");
    assert_eq!(s["failure"]["time"], 0.0, "{s}");
    let stiff = set(
        &set(&base, "young", "1e306"),
        "t_end",
        "0.01\ndt = 0.001\n[method]\nallow_unstable = true",
    );
    let (_, err, _) = run("stiff-unstable", &stiff);
    let warning = err.lines().find(|l| l.starts_with("warning:")).unwrap_or_default();
    assert!(
        warning.contains("step number 2.525") && warning.contains("e150"),
        "{err}"
    );
}

/// `[time] step_number` sets the step as a fraction of the stability limit:
/// the fewest steps whose step number is at most the one given (0.5 without
/// `dt` or `step_number`), with a warning above 0.9, and errors naming the
/// key for a value that is not positive, for both keys at once, and above 1.
#[test]
fn step_number_sets_the_step_as_a_fraction_of_the_limit() {
    let base = set(&example("rod_free_tumbling.toml"), "t_end", "0.5");
    let (ok, err, out) = run("step-number-default", &base);
    assert!(ok, "{err}");
    let default = summary(&out);
    let limit = default["dt_stability_limit"].as_f64().expect("number");
    for (name, number) in [
        ("step-number-0.9", 0.9),
        ("step-number-0.25", 0.25),
        ("step-number-0.92", 0.92),
    ] {
        let text = set(&base, "t_end", &format!("0.5\nstep_number = {number}"));
        let (ok, err, out) = run(name, &text);
        assert!(ok, "{err}");
        // Above 0.9 (and at most 1) a warning: long runs can still grow.
        assert_eq!(err.contains("warning: step number"), number > 0.9, "{name}: {err}");
        let s = summary(&out);
        let (dt, taken) = (
            s["dt"].as_f64().expect("dt"),
            s["step_number"].as_f64().expect("number"),
        );
        let steps = (0.5 / dt).round();
        // dt = 0.5/steps with steps = ⌈0.5/(number·limit)⌉.
        assert_eq!(steps, (0.5 / (number * limit)).ceil(), "{s}");
        assert!(
            taken <= number * (1.0 + 1e-12) && taken > number * (steps - 1.0) / steps,
            "{s}"
        );
        assert!(
            (taken / (dt / limit) - 1.0).abs() < 1e-12,
            "step number = dt / limit: {s}"
        );
    }
    let d = default["step_number"].as_f64().expect("number");
    assert!(d <= 0.5 * (1.0 + 1e-12) && d > 0.45, "default {d}");
    for (name, value, expected) in [
        ("step-number-zero", "0.0", "time.step_number"),
        ("step-number-negative", "-0.5", "time.step_number"),
        ("step-number-nan", "nan", "time.step_number"),
        ("step-number-and-dt", "0.9\ndt = 0.001", "not both"),
        ("step-number-unstable", "1.5", "allow_unstable"),
    ] {
        let text = set(&base, "t_end", &format!("0.5\nstep_number = {value}"));
        let (ok, err, _) = run(name, &text);
        assert!(
            !ok && err.contains("time.step_number") && err.contains(expected),
            "{name}: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
}
