//! The global space–time boundary-value solve
//! ([`veselov::field::boundary_value`]) on the beam: given only the first
//! and the last level of a time-marched free beam, Newton on the whole
//! domain recovers every level in between, from a perturbed guess and from
//! the first level held still — a second path to the marched solution.

use nalgebra::SVector;
use veselov::complex::{SpacetimeLattice, TopCells};
use veselov::evolution::marcher::{Direction, EndCondition, Evolution000};
use veselov::field::boundary_value::solve_boundary_value;
use veselov::field::cauchy::CauchyOptions;
use veselov::field::fibre::RigidMotions;
use veselov::lie::{CayleyMap, Retraction, SE3, se3};
use veselov::models::beam::{BeamDensity, BeamProperties, CayleyBeam, beam_lagrangian, straight};

const CELLS: usize = 5;
const LEVELS: usize = 10;

fn lagrangian(dt: f64, ds: f64) -> CayleyBeam {
    let p = BeamProperties::from_diagonals([0.5, 0.5, 1.0, 1.0, 1.0, 1.0], [0.5, 0.5, 0.6, 1.0, 1.0, 1.0])
        .expect("positive");
    beam_lagrangian(BeamDensity::new(p), dt, ds).expect("lagrangian")
}

/// The levels 0 … LEVELS of a free beam marched in time from a bent,
/// moving start (node a of level j at `levels[j][a]`).
fn marched(dt: f64, ds: f64) -> Vec<Vec<SE3<f64>>> {
    let wave = |a: usize| {
        let s = a as f64;
        SVector::<f64, 6>::from([0.2 * s.sin(), 0.1, -0.2 * s.cos(), 0.05, 0.1 * s.sin(), 0.0])
    };
    let g0: Vec<SE3<f64>> = (0..=CELLS)
        .map(|a| straight(ds, a).compose(&se3::exp(&(wave(a) * 0.05))))
        .collect();
    let g1: Vec<SE3<f64>> = g0
        .iter()
        .enumerate()
        .map(|(a, g)| g.compose(&CayleyMap::tau(&(wave(a + 2) * dt))))
        .collect();
    let mut evo = Evolution000::<RigidMotions, _, 6>::new(
        Direction::Time,
        lagrangian(dt, ds),
        &g0,
        &g1,
        EndCondition::Natural,
        EndCondition::Natural,
        CauchyOptions::default(),
    )
    .expect("evolution");
    let level =
        |evo: &Evolution000<RigidMotions, CayleyBeam, 6>, back| (0..=CELLS).map(|a| evo.value(back, a)).collect();
    let mut levels = vec![level(&evo, 1), level(&evo, 0)];
    for _ in 1..LEVELS {
        evo.step().expect("step");
        levels.push(level(&evo, 0));
    }
    levels
}

/// Solves the boundary-value problem with the first and last levels of the
/// marched field as data, from `guess(j, a)` inside; returns the largest
/// chart distance to the marched field and the Newton iterations.
fn recover(guess: impl Fn(&[Vec<SE3<f64>>], usize, usize) -> SE3<f64>) -> (f64, usize) {
    let (dt, ds) = (0.05, 0.1);
    let field = marched(dt, ds);
    let lattice = SpacetimeLattice::seed000(LEVELS, CELLS).expect("lattice");
    let mut values = vec![SE3::identity(); lattice.vertex_count()];
    let mut known = vec![false; lattice.vertex_count()];
    for j in 0..=LEVELS {
        for a in 0..=CELLS {
            let v = lattice.vertex_at(a as i64, j as i64).expect("vertex");
            let data = j == 0 || j == LEVELS;
            known[v] = data;
            values[v] = if data { field[j][a] } else { guess(&field, j, a) };
        }
    }
    let options = CauchyOptions {
        tolerance: 1e-13,
        max_iterations: 20,
    };
    let report =
        solve_boundary_value::<RigidMotions, _, 6>(&lattice, &lagrangian(dt, ds), &mut values, &known, &options)
            .expect("boundary-value solve");
    assert_eq!(report.unknowns, (LEVELS - 1) * (CELLS + 1));
    let mut worst: f64 = 0.0;
    for j in 0..=LEVELS {
        for a in 0..=CELLS {
            let v = lattice.vertex_at(a as i64, j as i64).expect("vertex");
            let d = se3::log(&field[j][a].inverse().compose(&values[v])).expect("close");
            worst = worst.max(d.amax());
        }
    }
    (worst, report.iterations)
}

/// From the marched field moved by 10⁻² in every chart direction, and from
/// the first level held still at every inner level (a guess off by the whole
/// motion), Newton converges quadratically to the marched field: measured
/// distances at round-off, in a handful of iterations. The beam's slaved
/// last node and its natural ends are equations of the same solve.
#[test]
fn the_whole_domain_solve_recovers_the_marched_beam_from_its_end_levels() {
    let perturbed = |field: &[Vec<SE3<f64>>], j: usize, a: usize| {
        let k = (7 * j + 3 * a) as f64;
        let xi = SVector::<f64, 6>::from_fn(|i, _| 1e-2 * (k + i as f64).sin());
        field[j][a].compose(&se3::exp(&xi))
    };
    let still = |field: &[Vec<SE3<f64>>], _: usize, a: usize| field[0][a];
    for (name, worst_and_iterations) in [("perturbed", recover(perturbed)), ("still", recover(still))] {
        let (worst, iterations) = worst_and_iterations;
        eprintln!("{name} guess: largest distance to the marched field {worst:e} after {iterations} iterations");
        assert!(worst < 1e-10, "{name}: {worst:e}");
        assert!((1..=8).contains(&iterations), "{name}: {iterations} iterations");
    }
}

/// A Lagrangian with cell forces and values of the wrong length are refused.
#[test]
fn the_boundary_value_solve_refuses_forces_and_wrong_sizes() {
    let lattice = SpacetimeLattice::seed000(3, 2).expect("lattice");
    let n = lattice.vertex_count();
    let mut values = vec![SE3::identity(); n];
    let known = vec![true; n];
    let options = CauchyOptions::default();
    let p = BeamProperties::from_diagonals([0.5, 0.5, 1.0, 1.0, 1.0, 1.0], [0.5, 0.5, 0.6, 1.0, 1.0, 1.0])
        .expect("positive");
    let damped: CayleyBeam =
        beam_lagrangian(BeamDensity::new(p).with_damping([0.1; 6]).expect("damping"), 0.05, 0.1).expect("lagrangian");
    let e = solve_boundary_value::<RigidMotions, _, 6>(&lattice, &damped, &mut values, &known, &options)
        .expect_err("forces refused");
    assert!(e.to_string().contains("conservative"), "{e}");
    let e = solve_boundary_value::<RigidMotions, _, 6>(
        &lattice,
        &lagrangian(0.05, 0.1),
        &mut values[..n - 1],
        &known,
        &options,
    )
    .expect_err("length refused");
    assert!(e.to_string().contains("field values"), "{e}");
}
