//! Lattice fields in 1+1 and on the 2+1 CFK lattice: runs, their conserved
//! quantities and outputs, and errors naming the key.

use crate::common::{Scratch, run_scenario, scenario, summary, veselov};
use crate::shared::{failing, relative_energy_error_is_stated};

/// A lattice's time step is the lattice's: a t_end it does not divide ends
/// the run at the next level, and the run says so (1+1 and 2+1 alike).
#[test]
fn lattice_runs_say_when_they_end_after_t_end() {
    let dir = Scratch::new("field-end");
    let cases = [
        (
            "one",
            "[model]\nname = \"wave\"\n[lattice]\nnodes = 64\nlength = 8.0\ncourant = 0.5\n\
             [method]\nscheme = \"triangle\"\n[initial]\nkind = \"dalembert\"\n[time]\nt_end = 1.03\n[output]\nplots = false\n",
            1.0625,
        ),
        (
            "two",
            "[model]\nname = \"wave\"\n[lattice]\nkind = \"cfk\"\nspace_dimension = 2\nnodes = [8, 8]\n\
             spacing = 0.3\ndt = 0.1\n[initial]\nkind = \"standing-wave\"\n[time]\nt_end = 1.03\n\
             [output]\nplots = false\n",
            1.1,
        ),
    ];
    for (name, text, end) in cases {
        let out = dir.join(name);
        let run = veselov()
            .arg("run")
            .arg(scenario(&dir, text))
            .arg("--out")
            .arg(&out)
            .assert()
            .success();
        let err = String::from_utf8_lossy(&run.get_output().stderr).into_owned();
        assert!(err.contains("does not divide t_end"), "{name}: {err}");
        let t_final = summary(&out)["t_final"].as_f64().expect("t_final");
        assert!((t_final - end).abs() < 1e-12, "{name}: t_final = {t_final}");
    }
}

#[test]
fn lattice_field_run_reports_energy_and_charges() {
    let dir = Scratch::new("field-wave");
    let out = dir.join("out");
    let path = scenario(
        &dir,
        "[model]\nname = \"wave\"\n[lattice]\nnodes = 64\nlength = 8.0\ncourant = 0.5\n\
         [method]\nscheme = \"guo\"\n[initial]\nkind = \"dalembert\"\ndrift = 0.2\n\
         [time]\nt_end = 5.0\n[output]\nsnapshot_every = 8\nenergy_every = 4\nenergy_block = 20\nplots = false\n",
    );
    run_scenario(&out, &path).success();
    let s = summary(&out);
    assert_eq!(s["status"], "ok");
    assert_eq!(s["nodes"], 64);
    // dt = courant·dx = 0.0625: 80 levels reach t = 5.
    assert_eq!(s["levels"], 80);
    // Guo's E^{j+½} is conserved exactly for N = 0 up to the solve tolerance.
    let e0 = s["energy_initial"].as_f64().expect("energy").abs();
    assert!(s["energy_error_max"].as_f64().expect("err") <= 1e-11 * e0, "{s}");
    relative_energy_error_is_stated(&s);
    assert!(s["charges_error_max"]["shift_charge"].as_f64().expect("charge") <= 1e-12);
    let npy = std::fs::read(out.join("snapshots.npy")).expect("npy");
    let header = String::from_utf8_lossy(&npy[..128]).into_owned();
    // Level 0, every 8th level from 8 to 80: 11 rows of 64 nodes.
    assert!(header.contains("'shape': (11, 64)"), "{header}");
    // 79 energies (levels (1, 2) … (79, 80)) in blocks of 20: 4 rows.
    let blocks = std::fs::read_to_string(out.join("energy_blocks.csv")).expect("blocks");
    assert!(blocks.starts_with("t_start,levels,min,mean,max"));
    assert_eq!(blocks.lines().count(), 1 + 4);
}

#[test]
fn lattice_field_errors_name_the_key() {
    let dir = Scratch::new("field-errors");
    let base = |lattice: &str, method: &str, initial: &str| {
        format!(
            "[model]\nname = \"sine-gordon\"\n[lattice]\n{lattice}\n[method]\n{method}\n[initial]\n{initial}\n\
             [time]\nt_end = 1.0\n"
        )
    };
    let ok_lattice = "nodes = 32\nlength = 40.0\ncourant = 0.125";
    let cases = [
        (
            base(
                "nodes = 2\nlength = 40.0\ncourant = 0.1",
                "scheme = \"triangle\"",
                "kind = \"kink-antikink\"",
            ),
            "lattice.nodes",
        ),
        (
            base(
                "nodes = 32\nlength = 40.0\ndt = 0.1\ncourant = 0.1",
                "scheme = \"triangle\"",
                "kind = \"kink-antikink\"",
            ),
            "lattice",
        ),
        (
            base(
                "nodes = 32\nlength = -4.0\ncourant = 0.1",
                "scheme = \"triangle\"",
                "kind = \"kink-antikink\"",
            ),
            "lattice.length",
        ),
        (
            base(ok_lattice, "scheme = \"leapfrog\"", "kind = \"kink-antikink\""),
            "method.scheme",
        ),
        (
            base(ok_lattice, "scheme = \"triangle\"", "kind = \"soliton\""),
            "initial.kind",
        ),
        (
            base(
                ok_lattice,
                "scheme = \"triangle\"",
                "kind = \"kink-antikink\"\nspeed = 0.5",
            ),
            "initial.speed",
        ),
        (
            base(
                ok_lattice,
                "scheme = \"triangle\"\norder = 2",
                "kind = \"kink-antikink\"",
            ),
            "order",
        ),
        (
            base(
                "nodes = 32\nlength = 40.0\ncourant = 0.1\nboundary = \"spiral\"",
                "scheme = \"triangle\"",
                "kind = \"kink\"",
            ),
            "lattice.boundary",
        ),
    ];
    for (i, (text, needle)) in cases.iter().enumerate() {
        let path = scenario(&dir, text);
        let out = dir.join(format!("out{i}"));
        let assert = run_scenario(&out, &path).failure();
        let stderr = String::from_utf8_lossy(&assert.get_output().stderr).into_owned();
        assert!(stderr.contains(needle), "case {i}: `{needle}` not in: {stderr}");
    }
}

#[test]
fn generic_lattice_paths_complex_field_and_fixed_ends() {
    let dir = Scratch::new("field-generic");
    let out = dir.join("complex");
    let path = scenario(
        &dir,
        "[model]\nname = \"klein-gordon-complex\"\nparams = { m2 = 1.0, lambda = 0.5 }\n\
         [lattice]\nnodes = 32\nlength = 10.0\ncourant = 0.25\n[method]\nscheme = \"symmetric-rectangle\"\n\
         [initial]\nkind = \"plane-wave\"\namplitude = 0.8\nmode = 2\n[time]\nt_end = 2.0\n[output]\nplots = false\n",
    );
    run_scenario(&out, &path).success();
    let s = summary(&out);
    assert_eq!(s["status"], "ok", "{s}");
    assert_eq!(s["path"], "generic");
    let q = s["charges_error_max"]["phase_charge"].as_f64().expect("phase charge");
    assert!(q <= 1e-12, "phase charge error {q:e}");
    let npy = std::fs::read(out.join("snapshots.npy")).expect("npy");
    let header = String::from_utf8_lossy(&npy[..128]).into_owned();
    assert!(header.contains(", 32, 2)"), "{header}");

    let out = dir.join("dirichlet");
    let path = scenario(
        &dir,
        "[model]\nname = \"sine-gordon\"\n[lattice]\nnodes = 41\nlength = 20.0\nboundary = \"dirichlet\"\n\
         courant = 0.25\n[method]\nscheme = \"triangle\"\n[initial]\nkind = \"kink\"\nx0 = 6.0\nspeed = 0.3\n\
         [time]\nt_end = 4.0\n[output]\nplots = false\n",
    );
    run_scenario(&out, &path).success();
    let s = summary(&out);
    assert_eq!(s["status"], "ok", "{s}");
    assert_eq!(s["boundary"], "dirichlet");

    // Non-variational schemes and triangles with free ends are refused, naming the key.
    for (lattice, scheme, needle) in [
        ("boundary = \"dirichlet\"", "guo", "method.scheme"),
        ("boundary = \"free\"", "triangle", "lattice"),
    ] {
        let path = scenario(
            &dir,
            &format!(
                "[model]\nname = \"wave\"\n[lattice]\nnodes = 20\nlength = 5.0\n{lattice}\ncourant = 0.5\n\
                 [method]\nscheme = \"{scheme}\"\n[initial]\nkind = \"dalembert\"\n[time]\nt_end = 1.0\n"
            ),
        );
        let assert = run_scenario(dir.join(scheme), &path).failure();
        let stderr = String::from_utf8_lossy(&assert.get_output().stderr).into_owned();
        assert!(stderr.contains(needle), "`{needle}` not in {stderr}");
    }
}

/// A 2+1 field on the CFK lattice: the snapshot array has the grid's shape,
/// the free field's shift momentum is conserved to round-off, the phase
/// charge of the complex field too, and bad lattice keys are refused by name.
#[test]
fn cfk_lattice_fields_run_and_conserve_their_momenta() {
    let dir = Scratch::new("cfk");
    let text = |model: &str, initial: &str, dt: f64| {
        format!(
            "[model]\nname = \"{model}\"\n[lattice]\nkind = \"cfk\"\nspace_dimension = 2\nnodes = [12, 10]\n\
             spacing = 0.3\ndt = {dt}\n[initial]\nkind = \"{initial}\"\namplitude = 0.5\n[time]\nt_end = 3.0\n\
             [output]\nsnapshot_every = 5\nplots = false\n"
        )
    };
    for (model, initial, column) in [
        ("wave", "standing-wave", "shift_momentum"),
        ("klein-gordon-complex", "plane-wave", "phase_charge"),
    ] {
        let out = dir.join(model);
        let file = scenario(&dir, &text(model, initial, 0.1));
        run_scenario(&out, &file).success();
        let s = summary(&out);
        assert_eq!(s["status"], "ok", "{model}: {s}");
        assert_eq!(s["time_steps"], 30, "{model}");
        let drift = s["charges_error_max"][column].as_f64().expect("charge error");
        assert!(drift < 1e-12, "{model}: {column} drift {drift:e}");
        relative_energy_error_is_stated(&s);
        let momentum = std::fs::read_to_string(out.join("momentum.csv")).expect("momentum.csv");
        assert_eq!(momentum.lines().next(), Some(format!("t,p_x,p_y,{column}").as_str()));
        assert_eq!(momentum.lines().count(), 32, "{model}: one row per time step");
        let npy = std::fs::read(out.join("snapshots.npy")).expect("snapshots.npy");
        let header = String::from_utf8_lossy(&npy[..128]).to_string();
        let shape = if model == "wave" {
            "(7, 12, 10)"
        } else {
            "(7, 12, 10, 2)"
        };
        assert!(header.contains(shape), "{model}: {header}");
    }
    let err = failing("cfk-unstable", &text("sine-gordon", "pulse", 0.15));
    assert!(err.contains("`lattice`") && err.contains("stability limit"), "{err}");
    // At the limit exactly: spacing 0.1 and courant 0.4 give dt/dx =
    // 0.4000000000000001 in floating point, which is not above the limit.
    let at_limit = text("sine-gordon", "pulse", 0.1)
        .replace("spacing = 0.3", "spacing = 0.1")
        .replace("dt = 0.1", "courant = 0.4")
        .replace("t_end = 3.0", "t_end = 0.2");
    let out = dir.join("at-limit");
    run_scenario(&out, scenario(&dir, &at_limit)).success();
    let err = failing("cfk-initial", &text("sine-gordon", "plane-wave", 0.1));
    assert!(err.contains("`initial.kind`"), "{err}");
}
