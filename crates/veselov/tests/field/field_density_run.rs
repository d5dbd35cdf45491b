//! The density-driven path: cell energies, the run driver on vector fields and
//! on Dirichlet lattices, and the exact complex Klein–Gordon plane wave.

use nalgebra::SVector;
use veselov::spacetime::{
    Boundary, ComplexKleinGordon, ComplexPlaneWave, DensityRunConfig, FastMarcher, InitialData, Lattice, NonlinearWave,
    RectangleRule, Scheme, SineGordon, SolverOptions, TriangleRule, Wave, level_energy, run_density,
};

type V1 = SVector<f64, 1>;

fn lift(y: &[f64]) -> Vec<V1> {
    y.iter().map(|&v| V1::new(v)).collect()
}

/// With the symmetric rectangle rule the cell energy ½φ_t² + ½φ_x² − N(φ̄) is
/// the footnote-4 energy of seed 002 the fast path reports: equal to
/// round-off on every level of a breather run.
#[test]
fn cell_energy_is_the_footnote_4_energy() {
    let lat = Lattice::periodic(64, 20.0, 4.0).expect("valid");
    let (y0, y1) = InitialData::Breather { omega: 0.6, x0: 10.0 }
        .levels(&lat)
        .expect("data");
    let opts = SolverOptions {
        rel_tol: 1e-15,
        ..SolverOptions::default()
    };
    let mut fast = FastMarcher::new(SineGordon, Scheme::SymmetricRectangle, lat, &y0, &y1, opts).expect("valid");
    let rule = RectangleRule {
        density: NonlinearWave(SineGordon),
        dt: lat.dt(),
        dx: lat.dx(),
        symmetric: true,
    };
    for _ in 0..50 {
        fast.step().expect("step");
        // The fast path's energy after a step is that of the levels (j−1, j)
        // just completed.
        let generic = level_energy(&rule, &lat, &lift(fast.previous()), &lift(fast.current()));
        let reported = fast.energy();
        assert!(
            (generic - reported).abs() <= 1e-13 * reported.abs(),
            "{generic} vs {reported}"
        );
    }
}

/// Complex Klein–Gordon plane wave, triangles, periodic: the phase charge is
/// conserved to round-off, the energy stays within a small band, and the
/// field converges to the exact wave at second order.
#[test]
fn complex_plane_wave_run() {
    let wave = ComplexPlaneWave {
        amplitude: 0.8,
        mode: 2,
        m2: 1.0,
        lambda: 0.5,
    };
    let t_end = 2.0;
    let mut errors = Vec::new();
    let mut steps = Vec::new();
    for nodes in [32usize, 64, 128] {
        let lat = Lattice::periodic(nodes, 10.0, 4.0).expect("valid");
        let (y0, y1) = wave.levels(&lat).expect("levels");
        let rule = TriangleRule {
            density: NonlinearWave(ComplexKleinGordon {
                m2: wave.m2,
                lambda: wave.lambda,
            }),
            dt: lat.dt(),
            dx: lat.dx(),
        };
        let rotation = |y: &SVector<f64, 2>| SVector::<f64, 2>::new(-y[1], y[0]);
        let config = DensityRunConfig {
            t_end,
            snapshot_every: 0,
            rel_tol: 1e-14,
        };
        let run = run_density(rule, lat, y0, y1, &config, Some(&rotation), |_| true).expect("valid run");
        assert!(run.status.is_ok(), "{:?}", run.status);
        let q0 = run.charges[0];
        let drift = run.charges.iter().fold(0.0_f64, |m, q| m.max((q - q0).abs())) / q0.abs();
        println!("{nodes} nodes: phase charge drift {drift:e}");
        assert!(drift <= 1e-12, "phase charge drift {drift:e} with {nodes} nodes");
        let e0 = run.energies[0];
        let band = run.energies.iter().fold(0.0_f64, |m, e| m.max((e - e0).abs())) / e0.abs();
        assert!(band <= 1e-2, "energy band {band:e}");
        let exact = wave.exact(&lat, run.final_time).expect("exact");
        let err = run
            .final_level
            .iter()
            .zip(&exact)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).amax()));
        errors.push(err);
        steps.push(lat.dt());
    }
    let fit = veselov::diagnostics::fit_order(&steps, &errors, 1e-12).expect("fit");
    println!("errors {errors:?}, order {}", fit.order);
    assert!((fit.order - 2.0).abs() <= 0.2, "order {} from {errors:?}", fit.order);
}

/// Wave equation between fixed ends (Dirichlet), symmetric rectangles: the
/// ends stay fixed and the run reaches t_end. For N = 0 the box scheme (5.12)
/// conserves its quadratic footnote-4 energy exactly (the scheme is the
/// implicit midpoint rule in both directions), so the energy is checked at
/// round-off level (1e-12 relative over 240 levels).
#[test]
fn dirichlet_wave_run() {
    let nodes = 101;
    let length = 10.0;
    let dx = length / (nodes - 1) as f64;
    let lat = Lattice::new(nodes, dx, 0.5 * dx, Boundary::Dirichlet { left: 0.0, right: 0.0 }).expect("valid");
    let bump = |x: f64, t: f64| {
        let f = |s: f64| (-(s - 5.0) * (s - 5.0) * 4.0).exp();
        0.5 * (f(x - t) + f(x + t))
    };
    let y0: Vec<V1> = (0..nodes).map(|i| V1::new(bump(i as f64 * dx, 0.0))).collect();
    let y1: Vec<V1> = (0..nodes).map(|i| V1::new(bump(i as f64 * dx, lat.dt()))).collect();
    let rule = RectangleRule {
        density: NonlinearWave(Wave),
        dt: lat.dt(),
        dx,
        symmetric: true,
    };
    let config = DensityRunConfig {
        t_end: 12.0,
        snapshot_every: 10,
        rel_tol: 1e-14,
    };
    let run = run_density(rule, lat, y0, y1, &config, None, |_| true).expect("valid");
    assert!(run.status.is_ok(), "{:?}", run.status);
    assert!(run.final_time >= 12.0);
    assert_eq!(run.final_level[0][0], 0.0);
    assert_eq!(run.final_level[nodes - 1][0], 0.0);
    let e0 = run.energies[0];
    let band = run.energies.iter().fold(0.0_f64, |m, e| m.max((e - e0).abs())) / e0;
    println!("Dirichlet wave: energy band {band:e}, {} levels", run.final_index);
    assert!(band <= 1e-12, "energy band {band:e}");
    // The pulses have reflected off both ends (t = 12 > 5 + 5): the field is
    // not the free d'Alembert solution any more, but its energy is kept.
    assert!(run.snapshots.len() >= 10);
}
