//! A rod from any initial state and from raw material data: `[model]`
//! `mass_per_length`, `inertia_density`, `shear_stiffness`,
//! `bending_stiffness`, and `[initial]` `position`, `rotation_vector` as
//! expressions in s and t, sampled on the lattice's first four levels at
//! their own times wΔt/2 (seed 003 (6.2), (6.4)).

use crate::common::{csv, npy_data, run, run_loud, set, summary};

/// The seed-003 §6 reference: a uniform rod given by its raw data, started
/// from a motion in s and t, free ends, no loads.
const SECTION_6: &str = r#"[model]
name = "cosserat-rod"
length = 1.0
nodes = 21
mass_per_length = 1.0
inertia_density = [0.1, 0.1, 0.2]
shear_stiffness = [1.0, 1.0, 10.0]
bending_stiffness = [1.0, 1.0, 0.5]

[initial]
position = ["0.05*sin(3*s) + 0.2*t", "0.1*t*cos(2*s)", "s + 0.01*t"]
rotation_vector = ["0.3*s", "0.5*t", "0.2*s^2 + 0.4*t"]

[time]
t_end = 0.4025
dt = 0.005

[method]
shear_frame = "vertex"

[output]
every = 1
plots = false
"#;

/// The reference's centreline r(s, t), written out here independently of
/// the scenario's expressions.
fn reference_position(s: f64, t: f64) -> [f64; 3] {
    [
        0.05 * (3.0 * s).sin() + 0.2 * t,
        0.1 * t * (2.0 * s).cos(),
        s + 0.01 * t,
    ]
}

/// The final momenta of an independent implementation of Prop. 6.5's march
/// (Newton to a residual of 1e-14) from the same data, sampled at the same
/// times: linear, then angular about the origin.
const PROTOTYPE: [f64; 6] = [
    0.200427242086534,
    0.0448994415466,
    0.010470853044042,
    -0.010241443704355,
    0.141408132575811,
    0.080355900419697,
];

#[test]
fn section_6_reference_run_meets_the_independent_momenta_and_keeps_them() {
    let (ok, err, out) = run("section6", SECTION_6);
    assert!(ok, "{err}");
    let s = summary(&out);
    assert_eq!(s["status"], "ok", "{s}");
    // t_end = 0.4025 is 161 half steps of the dt asked for: dt is kept, and
    // the run's clock is the expressions', its first cut (level 2) at
    // t = Δt, so it marches 159 levels.
    let dt = s["dt"].as_f64().expect("dt");
    assert!((dt - 0.005).abs() <= 1e-17, "dt {dt:e}");
    assert_eq!(s["levels"], 159, "{s}");
    assert!((s["t_final"].as_f64().expect("t_final") - 0.4025).abs() < 1e-15, "{s}");
    let (header, rows) = csv(&out.join("momentum.csv"));
    assert_eq!(header, ["t", "P_x", "P_y", "P_z", "L_x", "L_y", "L_z"]);
    let (first, last) = (&rows[0], &rows[rows.len() - 1]);
    assert!((first[0] - dt).abs() < 1e-15, "first row at t = Δt: {first:?}");
    assert!((last[0] - 0.4025).abs() < 1e-15, "last row at t_end: {last:?}");
    let off = (0..6).map(|i| (last[i + 1] - PROTOTYPE[i]).abs()).fold(0.0, f64::max);
    // Conserved through the run: every row against the first.
    let drift = rows
        .iter()
        .flat_map(|r| (1..7).map(|i| (r[i] - first[i]).abs()).collect::<Vec<_>>())
        .fold(0.0, f64::max);
    println!("§6 reference: final momenta off the prototype's by {off:.1e}; largest drift {drift:.1e}");
    assert!(off <= 1e-9, "final momenta {last:?} against {PROTOTYPE:?}: {off:e}");
    assert!(drift <= 1e-12, "momentum drift {drift:e}");
    assert!(s["linear_momentum_balance_error"].as_f64().expect("number") <= 1e-12);

    // The sampling times, read back from the first centreline row (the cut
    // at level 2): the even material points lie on level 2 at t = Δt, the
    // odd ones are the midpoint of their values at t = Δt/2 (level 1) and
    // t = 3Δt/2 (level 3).
    let line = npy_data(&out.join("centerline.npy"));
    let mut worst = 0.0_f64;
    for p in 0..21 {
        let s = p as f64 * 0.05;
        let expected: Vec<f64> = if p % 2 == 0 {
            reference_position(s, dt).to_vec()
        } else {
            let (a, b) = (reference_position(s, 0.5 * dt), reference_position(s, 1.5 * dt));
            (0..3).map(|k| 0.5 * (a[k] + b[k])).collect()
        };
        for k in 0..3 {
            worst = worst.max((line[3 * p + k] - expected[k]).abs());
        }
    }
    assert!(worst < 1e-15, "first row off the lattice's sampling times by {worst:e}");
}

#[test]
fn a_motion_sampled_half_a_step_later_changes_the_momenta() {
    // The momenta depend on when the first levels are sampled: the same
    // motion shifted by Δt/2 gives momenta off the reference by far more
    // than the test's tolerance, so the reference test pins the times.
    let shifted = SECTION_6
        .replace(
            "0.2*t\", \"0.1*t*cos(2*s)\", \"s + 0.01*t\"",
            "0.2*(t + 0.0025)\", \"0.1*(t + 0.0025)*cos(2*s)\", \"s + 0.01*(t + 0.0025)\"",
        )
        .replace(
            "\"0.5*t\", \"0.2*s^2 + 0.4*t\"",
            "\"0.5*(t + 0.0025)\", \"0.2*s^2 + 0.4*(t + 0.0025)\"",
        )
        .replace("t_end = 0.4025", "t_end = 0.02");
    assert!(
        shifted.contains("t + 0.0025") && !shifted.contains("0.4*t\""),
        "{shifted}"
    );
    let (ok, err, out) = run("section6-shifted", &shifted);
    assert!(ok, "{err}");
    let (_, rows) = csv(&out.join("momentum.csv"));
    let last = &rows[rows.len() - 1];
    let off = (0..6).map(|i| (last[i + 1] - PROTOTYPE[i]).abs()).fold(0.0, f64::max);
    assert!(off > 1e-6, "shifted sampling still meets the reference ({off:e})");
}

/// The §6 rod given as a circular section (radius a, density ρ₀, E, G, κ)
/// and as the raw data of the same section: ρA, J = ρ₀(I, I, 2I),
/// C₁ = (κGA, κGA, EA), C₂ = (EI, EI, 2GI) with A = πa², I = πa⁴/4. The two
/// runs agree to round-off; the tensor given in full (9 entries) is the
/// same rod to the bit.
#[test]
fn raw_rod_data_are_the_parameters_of_a_section() {
    let (a, rho, e, g, kappa): (f64, f64, f64, f64, f64) = (0.02, 1000.0, 1e5, 4e4, 0.9);
    let (area, i) = (std::f64::consts::PI * a * a, std::f64::consts::PI * a.powi(4) / 4.0);
    let section = "radius = 0.02\ndensity = 1000.0\nyoung = 1e5\nshear_modulus = 4e4\nshear_coefficient = 0.9";
    let raw = format!(
        "mass_per_length = {:e}\ninertia_density = [{:e}, {:e}, {:e}]\nshear_stiffness = [{:e}, {:e}, {:e}]\n\
         bending_stiffness = [{:e}, {:e}, {:e}]",
        rho * area,
        rho * i,
        rho * i,
        rho * 2.0 * i,
        kappa * g * area,
        kappa * g * area,
        e * area,
        e * i,
        e * i,
        g * 2.0 * i
    );
    let full = raw.replace(
        &format!("[{:e}, {:e}, {:e}]", rho * i, rho * i, rho * 2.0 * i),
        &format!("[{:e}, 0, 0, 0, {:e}, 0, 0, 0, {:e}]", rho * i, rho * i, rho * 2.0 * i),
    );
    assert_ne!(full, raw);
    let scenario = |model: &str| {
        format!(
            "[model]\nname = \"cosserat-rod\"\nlength = 1.0\nnodes = 21\n{model}\n\n[initial]\nshape = \"bent\"\n\
             curvature = 1.0\nvelocity = [0.01, 0.0, 0.02]\nangular_velocity = [0.0, 0.3, 0.1]\n\n[time]\n\
             t_end = 0.05\n\n[output]\nplots = false\n"
        )
    };
    let read = |model: &str, name: &str| {
        let (ok, err, out) = run(name, &scenario(model));
        assert!(ok, "{name}: {err}");
        (csv(&out.join("momentum.csv")).1, npy_data(&out.join("centerline.npy")))
    };
    let (m_section, c_section) = read(section, "section");
    let (m_raw, c_raw) = read(&raw, "raw");
    let (m_full, c_full) = read(&full, "full");
    assert_eq!(
        (&m_raw, &c_raw),
        (&m_full, &c_full),
        "diagonal tensor in 3 or 9 entries"
    );
    assert_eq!(m_section.len(), m_raw.len());
    let scale = m_section.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
    let gap = m_section
        .iter()
        .flatten()
        .zip(m_raw.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    let line_gap = c_section
        .iter()
        .zip(&c_raw)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(
        scale > 1e-4 && gap <= 1e-12 * scale,
        "momenta differ by {gap:e} of {scale:e}"
    );
    assert!(line_gap <= 1e-12, "centrelines differ by {line_gap:e}");
    // An off-diagonal inertia is used: the rod moves differently.
    let tilted = raw.replace(
        &format!("[{:e}, {:e}, {:e}]", rho * i, rho * i, rho * 2.0 * i),
        &format!(
            "[{:e}, {:e}, 0, {:e}, {:e}, 0, 0, 0, {:e}]",
            rho * i,
            0.5 * rho * i,
            0.5 * rho * i,
            rho * i,
            rho * 2.0 * i
        ),
    );
    let (m_tilted, _) = read(&tilted, "tilted");
    assert_ne!(m_tilted, m_raw);
}

#[test]
fn bad_raw_data_and_initial_expressions_name_the_key() {
    let cases: Vec<(String, &str, &str)> = vec![
        (
            SECTION_6.replace("mass_per_length = 1.0", "mass_per_length = 1.0\nradius = 0.1"),
            "model.mass_per_length",
            "model.radius",
        ),
        (
            SECTION_6.replace("shear_stiffness = [1.0, 1.0, 10.0]\n", ""),
            "model.shear_stiffness",
            "all four",
        ),
        (set(SECTION_6, "mass_per_length", "0.0"), "model.mass_per_length", "> 0"),
        (
            set(SECTION_6, "inertia_density", "[0.1, 0.1, 0.2, 0.3]"),
            "model.inertia_density",
            "3 or 9 numbers",
        ),
        (
            set(
                SECTION_6,
                "inertia_density",
                "[0.1, 0.0, 0.0, 0.0, 0.1, 0.01, 0.0, 0.02, 0.2]",
            ),
            "model.inertia_density[7]",
            "symmetric",
        ),
        (
            set(
                SECTION_6,
                "inertia_density",
                "[0.1, 0.2, 0.0, 0.2, 0.1, 0.0, 0.0, 0.0, 0.2]",
            ),
            "model.inertia_density",
            "positive definite",
        ),
        (
            set(
                SECTION_6,
                "inertia_density",
                "[0.1, 0.0, 0.0, 0.0, -0.1, 0.0, 0.0, 0.0, 0.2]",
            ),
            "model.inertia_density[4]",
            "positive",
        ),
        (
            set(SECTION_6, "inertia_density", "[0.1, -0.1, 0.2]"),
            "model.inertia_density[1]",
            "> 0",
        ),
        (
            set(SECTION_6, "shear_stiffness", "[1.0, 1.0, nan]"),
            "model.shear_stiffness[2]",
            "finite",
        ),
        (
            set(SECTION_6, "bending_stiffness", "[1.0, 0.0, 0.5]"),
            "model.bending_stiffness[1]",
            "> 0",
        ),
        (
            SECTION_6.replace("\"0.1*t*cos(2*s)\"", "\"0.1*u*cos(2*s)\""),
            "initial.position[1]",
            "u",
        ),
        (
            SECTION_6.replace("\"0.3*s\", ", ""),
            "initial.rotation_vector",
            "expected 3 strings, got 2",
        ),
        (
            SECTION_6.replace("\"0.5*t\"", "\"1/(t - 0.0025)\""),
            "initial.rotation_vector[1]",
            "t = 0.0025",
        ),
        (
            SECTION_6.replace("\"0.3*s\"", "\"sqrt(0.5 - s)\""),
            "initial.rotation_vector[0]",
            "must be finite",
        ),
        (
            SECTION_6.replace("[initial]", "[initial]\nshape = \"straight\""),
            "initial.shape",
            "not both",
        ),
        (
            SECTION_6.replace("[initial]", "[initial]\nvelocity = [1.0, 0.0, 0.0]"),
            "initial.velocity",
            "not both",
        ),
        (
            SECTION_6.replace("[initial]", "[initial]\nangular_velocity = [1.0, 0.0, 0.0]"),
            "initial.angular_velocity",
            "not both",
        ),
        (
            SECTION_6.replace("rotation_vector = [\"0.3*s\", \"0.5*t\", \"0.2*s^2 + 0.4*t\"]\n", ""),
            "initial.rotation_vector",
            "missing",
        ),
        (
            SECTION_6
                .replace("mass_per_length = 1.0\n", "")
                .replace("inertia_density = [0.1, 0.1, 0.2]\n", "")
                .replace("shear_stiffness = [1.0, 1.0, 10.0]\n", "")
                .replace(
                    "bending_stiffness = [1.0, 1.0, 0.5]\n",
                    "radius = 0.1\nyoung = 1.0\npoisson = 0.3\n",
                ),
            "model.density",
            "missing",
        ),
    ];
    for (text, key, detail) in cases {
        assert_ne!(text, SECTION_6, "{key}: the case changed nothing");
        let (ok, err, _) = run("bad-initial", &text);
        assert!(
            !ok && err.contains(&format!("`{key}`")) && err.contains(detail),
            "expected an error naming `{key}` ({detail}): {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn a_whole_number_of_half_steps_keeps_the_step_and_ends_there() {
    // A shape at rest (the run's t = 0 at the first cut) to t_end = 80.5 Δt:
    // 161 levels of the Δt asked for; 80.3 Δt is rounded to 161 half steps.
    let shape = SECTION_6
        .replace(
            "position = [\"0.05*sin(3*s) + 0.2*t\", \"0.1*t*cos(2*s)\", \"s + 0.01*t\"]",
            "shape = \"bent\"",
        )
        .replace(
            "rotation_vector = [\"0.3*s\", \"0.5*t\", \"0.2*s^2 + 0.4*t\"]",
            "velocity = [0.2, 0.0, 0.0]",
        );
    for (t_end, dt) in [(0.4025, 0.005), (0.4015, 0.4015 / 80.5)] {
        let text = set(&shape, "t_end", &t_end.to_string());
        let (o, dir) = run_loud("half-steps", &text);
        let (err, out) = (String::from_utf8_lossy(&o.stderr), dir.join("out"));
        assert!(o.status.success(), "{err}");
        let s = summary(&out);
        assert_eq!(s["levels"], 161, "{s}");
        assert!((s["dt"].as_f64().expect("dt") - dt).abs() < 1e-17, "{s}");
        let (_, rows) = csv(&out.join("momentum.csv"));
        assert_eq!(rows[0][0], 0.0);
        assert!((rows[rows.len() - 1][0] - t_end).abs() < 1e-15);
        assert_eq!(err.contains("adjusted to"), t_end != 0.4025, "{err}");
    }
}

#[test]
fn a_clamped_start_holds_the_pose_of_the_motion_at_t_0() {
    // The motion moves the start point, r(0, t) = (0.2t, 0.1t, 0.01t); a
    // clamped start holds it at r(0, 0) = 0 (the band's first level, the
    // run's t = 0), in every row, through the run.
    let text = SECTION_6
        .replace("[time]", "[ends]\nstart = \"clamped\"\n\n[time]")
        .replace("t_end = 0.4025", "t_end = 0.05");
    let (ok, err, out) = run("section6-clamped", &text);
    assert!(ok, "{err}");
    let s = summary(&out);
    assert_eq!(s["ends"][0], "clamped", "{s}");
    let line = npy_data(&out.join("centerline.npy"));
    let rows = line.len() / (21 * 3);
    assert!(rows >= 10, "{rows} rows");
    let worst = (0..rows)
        .flat_map(|row| (0..3).map(move |k| row * 63 + k))
        .map(|i| line[i].abs())
        .fold(0.0, f64::max);
    assert_eq!(worst, 0.0, "the clamped start moved by {worst:e}");
    // The free end moves with the motion.
    let end = (0..3)
        .map(|k| (line[(rows - 1) * 63 + 60 + k] - line[60 + k]).abs())
        .fold(0.0, f64::max);
    assert!(end > 1e-3, "{end:e}");
}
