//! `veselov plot DIR` redraws, from the output files alone, every figure
//! that a run of each kind (and a `verify` study) drew, and lists them.

use std::collections::BTreeSet;
use std::path::Path;

mod common;
use common::{Scratch, example, scenario, set, succeeds, verify_command, veselov};

/// The figure files in `dir`, by name.
fn figures(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .expect("dir")
        .filter_map(Result::ok)
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".svg") || n.ends_with(".png") || n.ends_with(".gif"))
        .collect()
}

/// Delete the figures of `out`, redraw them with `plot`, and check that the
/// same files are back and are the ones `plot` says it wrote.
fn redraws_what_the_run_drew(name: &str, out: &Path, expected: &[&str]) {
    let drawn = figures(out);
    for e in expected {
        assert!(drawn.contains(*e), "{name}: the run did not draw {e}: {drawn:?}");
    }
    for f in &drawn {
        std::fs::remove_file(out.join(f)).expect("remove");
    }
    let stdout = succeeds(veselov().arg("plot").arg(out));
    assert_eq!(figures(out), drawn, "{name}: plot did not redraw the same figures");
    let listed: BTreeSet<String> = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("wrote "))
        .filter_map(|p| Path::new(p).file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    assert_eq!(
        listed, drawn,
        "{name}: plot listed other files than it wrote:\n{stdout}"
    );
    // In PNG: each SVG figure gets its PNG twin.
    succeeds(veselov().args(["plot", "--format", "png"]).arg(out));
    let now = figures(out);
    for f in drawn.iter().filter_map(|f| f.strip_suffix(".svg")) {
        assert!(
            now.contains(&format!("{f}.png")),
            "{name}: no {f}.png after --format png"
        );
    }
}

/// An example, the keys set to shorten it, and figures its run must draw.
type Case = (
    &'static str,
    &'static [(&'static str, &'static str)],
    &'static [&'static str],
);

#[test]
fn plot_redraws_every_kind_of_run() {
    let cases: &[Case] = &[
        (
            "kepler",
            &[("t_end", "3.0")],
            &["energy_error.svg", "orbit.svg", "phase.svg"],
        ),
        (
            "damped_kepler",
            &[("t_end", "2.0")],
            &["energy_balance.svg", "energy_change.svg"],
        ),
        ("kepler_sem", &[("t_end", "3.0")], &["energy_error.svg"]),
        ("rigid_body", &[("t_end", "1.0")], &["body_momentum.svg"]),
        (
            "sine_gordon",
            &[("t_end", "2.0"), ("snapshot_every", "10")],
            &["final_waveform.svg", "spacetime.png"],
        ),
        (
            "klein_gordon_complex",
            &[("t_end", "1.0")],
            &["final_waveform.svg", "spacetime.png"],
        ),
        (
            "sine_gordon_2d",
            &[("t_end", "0.5"), ("snapshot_every", "1")],
            &["energy_error.svg", "field_0.png"],
        ),
        (
            "beam_free_free",
            &[("t_end", "0.02")],
            &["centerline_xz.svg", "momentum.svg", "centerline.gif"],
        ),
        (
            "rod_helix",
            &[("t_end", "0.02")],
            &["centerline_yz.svg", "energy.svg", "centerline.gif"],
        ),
    ];
    for (name, settings, expected) in cases {
        let dir = Scratch::new(&format!("plot-{name}"));
        let mut text = example(&format!("{name}.toml"));
        for (key, value) in *settings {
            text = set(&text, key, value);
        }
        let out = dir.join("out");
        succeeds(
            veselov()
                .args(["run", "--quiet", "--out"])
                .arg(&out)
                .arg(scenario(&dir, &text)),
        );
        redraws_what_the_run_drew(name, &out, expected);
    }
}

#[test]
fn plot_redraws_a_verify_study() {
    let dir = Scratch::new("plot-verify");
    let out = dir.join("study");
    let file = scenario(&dir, &set(&example("harmonic.toml"), "t_end", "1.0"));
    succeeds(&mut verify_command("0.1,0.05,0.025", &out, &file));
    redraws_what_the_run_drew("verify", &out, &["convergence.svg"]);
}

#[test]
fn plot_refuses_what_is_not_a_run() {
    let dir = Scratch::new("plot-nothing");
    let o = veselov().arg("plot").arg(&dir).output().expect("plot");
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("nothing to plot"));
    let o = veselov().arg("plot").arg(dir.join("missing")).output().expect("plot");
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a directory"));
    let o = veselov()
        .args(["plot", "--format", "pdf"])
        .arg(&dir)
        .output()
        .expect("plot");
    assert!(String::from_utf8_lossy(&o.stderr).contains("--format"));
}
