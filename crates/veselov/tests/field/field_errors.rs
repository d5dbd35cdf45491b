//! Bad parameters give typed errors naming the parameter; failing runs keep
//! what they computed.

use veselov::Error;
use veselov::spacetime::{
    Boundary, ComplexKleinGordon, FastMarcher, FieldRunConfig, GenericMarcher, InitialData, Lattice, Model,
    NonlinearWave, PeriodicKink, Scheme, SineGordon, SolverOptions, TriangleRule, run_lattice,
};

fn names(e: &Error) -> String {
    match e {
        Error::InvalidParameter { name, .. } => name.clone(),
        Error::NonFinite { what, .. } | Error::DimensionMismatch { what, .. } => what.clone(),
        other => format!("{other:?}"),
    }
}

#[test]
fn lattice_parameters_are_validated() {
    let e = |r: veselov::Result<Lattice>| names(&r.expect_err("must be rejected"));
    assert_eq!(e(Lattice::new(2, 0.1, 0.1, Boundary::Periodic)), "nodes");
    assert_eq!(e(Lattice::new(10, 0.0, 0.1, Boundary::Periodic)), "dx");
    assert_eq!(e(Lattice::new(10, f64::NAN, 0.1, Boundary::Periodic)), "dx");
    assert_eq!(e(Lattice::new(10, 0.1, -1.0, Boundary::Periodic)), "dt");
    assert_eq!(e(Lattice::new(10, 0.1, f64::INFINITY, Boundary::Periodic)), "dt");
    assert_eq!(
        e(Lattice::new(10, 0.1, 0.1, Boundary::Winding { jump: f64::NAN })),
        "boundary"
    );
    assert_eq!(
        e(Lattice::new(
            10,
            0.1,
            0.1,
            Boundary::Dirichlet {
                left: 0.0,
                right: f64::NAN
            }
        )),
        "boundary"
    );
    assert_eq!(e(Lattice::periodic(10, -40.0, 8.0)), "length");
    assert_eq!(e(Lattice::periodic(10, 40.0, 0.0)), "ratio");
}

#[test]
fn marcher_inputs_are_validated() {
    let lat = Lattice::periodic(8, 4.0, 2.0).expect("valid");
    let y = vec![0.0; 8];
    let o = SolverOptions::default();
    let mk = |lat: Lattice, a: &[f64], b: &[f64], o: SolverOptions| {
        names(&FastMarcher::new(SineGordon, Scheme::Triangle, lat, a, b, o).expect_err("must be rejected"))
    };
    assert_eq!(mk(lat, &y[..7], &y, o), "y0");
    let mut bad = y.clone();
    bad[3] = f64::NAN;
    assert_eq!(mk(lat, &y, &bad, o), "y1");
    assert_eq!(mk(lat, &y, &y, SolverOptions { rel_tol: 0.0, ..o }), "rel_tol");
    assert_eq!(
        mk(lat, &y, &y, SolverOptions { extrapolation: 10, ..o }),
        "extrapolation"
    );
    assert_eq!(mk(lat, &y, &y, SolverOptions { max_iter: 0, ..o }), "max_iter");
    let dir = Lattice::new(8, 0.5, 0.25, Boundary::Dirichlet { left: 0.0, right: 0.0 }).expect("valid");
    assert_eq!(mk(dir, &y, &y, o), "boundary");
    // Free ends with triangles are rejected by the generic marcher.
    let free = Lattice::new(8, 0.5, 0.25, Boundary::Free).expect("valid");
    let lag = TriangleRule {
        density: NonlinearWave(ComplexKleinGordon { m2: 1.0, lambda: 0.0 }),
        dt: 0.25,
        dx: 0.5,
    };
    let v = vec![nalgebra::Vector2::zeros(); 8];
    let err = GenericMarcher::new(lag, free, v.clone(), v).expect_err("free triangles");
    assert_eq!(names(&err), "boundary");
}

#[test]
fn initial_data_parameters_are_validated() {
    let lat = Lattice::periodic(16, 40.0, 8.0).expect("valid");
    let e = |d: InitialData| names(&d.levels(&lat).expect_err("must be rejected"));
    assert_eq!(e(InitialData::Kink { x0: 0.0, speed: 1.0 }), "speed");
    assert_eq!(e(InitialData::Breather { omega: 1.5, x0: 0.0 }), "omega");
    assert_eq!(
        e(InitialData::DAlembert {
            amplitude: 1.0,
            mode: 0,
            drift: 0.0
        }),
        "mode"
    );
    assert_eq!(names(&PeriodicKink::new(10.0, 0.0).expect_err("epsilon")), "epsilon");
    assert_eq!(names(&PeriodicKink::new(-1.0, 1e-6).expect_err("period")), "period");
}

#[test]
fn failing_runs_keep_what_they_computed() {
    // h/k = 1.1 violates the Courant limit of the triangle scheme: the run
    // fails at some level and returns the levels before it.
    let lat = Lattice::periodic(64, 8.0, 1.0 / 1.1).expect("valid");
    let config = FieldRunConfig {
        model: Model::Wave,
        scheme: Scheme::Triangle,
        lattice: lat,
        initial: InitialData::DAlembert {
            amplitude: 1.0,
            mode: 1,
            drift: 0.0,
        },
        t_end: 1000.0,
        snapshot_every: 10,
        energy_block: 100,
        keep_energies: true,
        recentre_every: 0,
        solver: SolverOptions::default(),
    };
    let run = run_lattice(&config, |_| true).expect("valid configuration");
    let Err(Error::LevelSolveFailure { level, .. }) = run.status else {
        panic!("expected a level-solve failure, got {:?}", run.status);
    };
    assert_eq!(level, run.final_index + 1);
    assert!(run.final_index > 2 && !run.snapshots.is_empty() && !run.energies.is_empty());
    let bad = FieldRunConfig { t_end: -1.0, ..config };
    assert_eq!(names(&run_lattice(&bad, |_| true).expect_err("t_end")), "t_end");
}

#[test]
fn driver_reproduces_the_marcher_and_stops_on_request() {
    let config = FieldRunConfig {
        keep_energies: true,
        ..FieldRunConfig::sine_gordon_section_5_2(Scheme::Triangle, 10.0).expect("valid")
    };
    let mut seen = 0;
    let run = run_lattice(&config, |info| {
        seen += 1;
        info.level < 200
    })
    .expect("valid");
    assert!(run.status.is_ok() && run.stopped);
    assert_eq!(run.final_index, 200);
    assert_eq!(seen, 199);
    assert_eq!(run.energies.len(), 199);
    let (y0, y1) = config.initial.levels(&config.lattice).expect("data");
    let mut m = FastMarcher::new(SineGordon, Scheme::Triangle, config.lattice, &y0, &y1, config.solver).expect("ok");
    while m.level() < 200 {
        m.step().expect("step");
    }
    assert_eq!(m.energy(), run.energies[198]);
}
