//! The SE(3) beam on seed 000's lattice: nanoseconds per node update (one
//! 6-D Newton solve of the core's flow marcher, through the Cayley map: in
//! the moving increment x = τ⁻¹(g₁⁻¹g₂) of the split Lagrangian, with its
//! Jacobian in closed form at the start, kept with its factors and inverse
//! from level to level, refreshed when an iteration contracts less than
//! fourfold; the slaved node likewise, through the stored value) for time
//! evolution (a free–free beam, A = 16 space cells: 16 updates per level,
//! the slaved node included; `time_trapezoid`, the command's time evolution
//! with the trapezoid rule in s, 17 ordinary updates per level) and space evolution (zero momentum, N = 16
//! time cells: 16 updates per column). One sample steps 4 levels: divide
//! its time by 64. `step` times the first 4 levels of a run (every node
//! evaluates its first Jacobian on the first level); `step_after_4_levels`
//! the next 4, every node starting from its own kept factors, as in a long
//! run. Newton iterations and Jacobians per node are printed once before
//! the timings (machine-independent counts, over 200 levels in time and 8
//! in space).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::SVector;
use veselov::evolution::marcher::{Direction, EndCondition, Evolution000};
use veselov::evolution::split::KineticQuadrature;
use veselov::field::cauchy::CauchyOptions;
use veselov::field::fibre::RigidMotions;
use veselov::lie::{CayleyMap, Retraction, SE3, se3};
use veselov::models::beam::{BeamDensity, BeamProperties, CayleyBeam, beam_lagrangian, straight};

const CELLS: usize = 16;

fn beam(dt: f64, ds: f64) -> CayleyBeam {
    let p = BeamProperties::from_diagonals([0.5, 0.5, 1.0, 1.0, 1.0, 1.0], [0.5, 0.5, 0.6, 1.0, 1.0, 1.0])
        .expect("positive");
    beam_lagrangian(BeamDensity::new(p), dt, ds).expect("lagrangian")
}

fn wave(k: usize) -> SVector<f64, 6> {
    let s = k as f64;
    SVector::from([
        0.03 * (0.3 * s).sin(),
        -0.02,
        0.01 * (0.2 * s).cos(),
        0.01,
        -0.01 * (0.4 * s).sin(),
        0.0,
    ])
}

fn time_evolution() -> Beam {
    time_evolution_with(false)
}

/// The time evolution with the trapezoid rule in s and an end cell (the
/// command's time evolution): 17 updates per level, the free end's node an
/// ordinary one.
fn trapezoid_time_evolution() -> Beam {
    time_evolution_with(true)
}

fn time_evolution_with(trapezoid: bool) -> Beam {
    let (dt, ds) = (0.05, 0.1);
    let g0: Vec<SE3<f64>> = (0..=CELLS)
        .map(|a| straight(ds, a).compose(&se3::exp(&wave(a))))
        .collect();
    let g1: Vec<SE3<f64>> = g0
        .iter()
        .enumerate()
        .map(|(a, g)| g.compose(&CayleyMap::tau(&(wave(a + 3) * dt))))
        .collect();
    let (lag, far) = if trapezoid {
        (
            beam(dt, ds).with_quadrature(KineticQuadrature::Trapezoid { last: CELLS }),
            EndCondition::EndCell,
        )
    } else {
        (beam(dt, ds), EndCondition::Natural)
    };
    Evolution000::new(
        Direction::Time,
        lag,
        &g0,
        &g1,
        EndCondition::Natural,
        far,
        CauchyOptions::default(),
    )
    .expect("evolution")
}

fn space_evolution() -> Beam {
    let (dt, ds) = (0.1, 0.05);
    let c0: Vec<SE3<f64>> = (0..=CELLS).map(|j| se3::exp(&(wave(0) * (j as f64 * dt)))).collect();
    let e6 = SVector::<f64, 6>::from([0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    let c1: Vec<SE3<f64>> = c0
        .iter()
        .enumerate()
        .map(|(j, g)| g.compose(&CayleyMap::tau(&((e6 + wave(j) * 0.1) * ds))))
        .collect();
    Evolution000::new(
        Direction::Space,
        beam(dt, ds),
        &c0,
        &c1,
        EndCondition::Natural,
        EndCondition::Natural,
        CauchyOptions::default(),
    )
    .expect("evolution")
}

type Beam = Evolution000<RigidMotions, CayleyBeam, 6>;
/// (name, constructor, levels for the iteration count).
type Run = (&'static str, fn() -> Beam, usize);

fn bench(c: &mut Criterion) {
    let runs: [Run; 3] = [
        ("time", time_evolution, 200),
        ("time_trapezoid", trapezoid_time_evolution, 200),
        ("space", space_evolution, 8),
    ];
    for (name, make, levels) in runs {
        // Machine-independent counts over a short run.
        let mut evo = make();
        let (mut iterations, mut jacobians) = (0, 0);
        for _ in 0..levels {
            let r = evo.step().expect("step");
            iterations += r.iterations;
            jacobians += r.jacobians;
        }
        // The trapezoid's end node is an ordinary node: one more per level.
        let per_level = CELLS + usize::from(name == "time_trapezoid");
        let updates = (levels * per_level) as f64;
        println!(
            "beam {name} evolution: {:.2} Newton iterations and {:.2} Jacobians per node update",
            iterations as f64 / updates,
            jacobians as f64 / updates
        );
        let mut group = c.benchmark_group(format!("beam_{name}_level_{CELLS}_nodes"));
        group.sample_size(10);
        group.bench_function("step", |b| {
            b.iter_batched_ref(
                make,
                |evo| {
                    for _ in 0..4 {
                        black_box(evo.step().expect("step"));
                    }
                },
                criterion::BatchSize::LargeInput,
            )
        });
        // The same 4 levels after 4 untimed ones: every node starts from the
        // Jacobian factors of its last solve, as in a long run.
        group.bench_function("step_after_4_levels", |b| {
            b.iter_batched_ref(
                || {
                    let mut evo = make();
                    for _ in 0..4 {
                        evo.step().expect("warm-up step");
                    }
                    evo
                },
                |evo| {
                    for _ in 0..4 {
                        black_box(evo.step().expect("step"));
                    }
                },
                criterion::BatchSize::LargeInput,
            )
        });
        group.finish();
    }
}

criterion_group!(benches, bench, bench_boundary_value);
criterion_main!(benches);

/// The global space–time boundary-value solve: a free beam of 16 cells over
/// 16 levels of a time march, given its first and last levels, recovered
/// from the marched field moved by 10⁻³ (15 inner levels × 17 nodes: 255
/// unknown frames, 1530 unknowns). The Newton iterations are printed once.
fn bench_boundary_value(c: &mut Criterion) {
    use veselov::complex::{SpacetimeLattice, TopCells};
    use veselov::field::boundary_value::solve_boundary_value;
    let levels = 16;
    let mut evo = time_evolution();
    let mut field = vec![(0..=CELLS).map(|a| evo.value(1, a)).collect::<Vec<_>>()];
    field.push((0..=CELLS).map(|a| evo.value(0, a)).collect());
    for _ in 1..levels {
        evo.step().expect("step");
        field.push((0..=CELLS).map(|a| evo.value(0, a)).collect());
    }
    let lattice = SpacetimeLattice::seed000(levels, CELLS).expect("lattice");
    let mut guess = vec![SE3::identity(); lattice.vertex_count()];
    let mut known = vec![false; lattice.vertex_count()];
    for (j, level) in field.iter().enumerate() {
        for (a, g) in level.iter().enumerate() {
            let v = lattice.vertex_at(a as i64, j as i64).expect("vertex");
            known[v] = j == 0 || j == levels;
            guess[v] = if known[v] {
                *g
            } else {
                g.compose(&se3::exp(&(wave(j + a) * 0.03)))
            };
        }
    }
    let options = CauchyOptions::default();
    let lag = beam(0.05, 0.1);
    let mut values = guess.clone();
    let report =
        solve_boundary_value::<RigidMotions, _, 6>(&lattice, &lag, &mut values, &known, &options).expect("solve");
    println!(
        "beam boundary-value solve: {} unknown frames, {} Newton iterations",
        report.unknowns, report.iterations
    );
    let mut group = c.benchmark_group("beam_boundary_value_16_levels_17_nodes");
    group.sample_size(10);
    group.bench_function("solve", |b| {
        b.iter_batched_ref(
            || guess.clone(),
            |values| {
                black_box(
                    solve_boundary_value::<RigidMotions, _, 6>(&lattice, &lag, values, &known, &options)
                        .expect("solve"),
                )
            },
            criterion::BatchSize::LargeInput,
        )
    });
    group.finish();
}
