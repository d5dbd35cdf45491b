//! The free Cosserat rod on the leapfrog lattice (split vertex step of note
//! 003 §3.6): wall time per step (one Δt for every material point = two
//! lattice levels) for 100- and 1000-element rods of PyElastica's
//! Timoshenko example material (length 3, radius 0.25, density 5000,
//! E = 1e6, shear modulus 1e4), at PyElastica's own limit Δt = 0.0705·dl;
//! the Newton iterations per vertex; and the largest stable step at 100
//! elements (bisection on Δt, each trial 20,000 steps, printed in units of
//! dl before the timings: near the linear limit a rod can run thousands of
//! steps before its waves have grown, and whether it does is not monotone
//! in Δt there, so the bisection gives a step below which the trials it
//! made ran, not a sharp threshold); and, beside criterion's mean, the
//! least time per step over 60 blocks of 200 steps (`RAYON_NUM_THREADS=1`
//! for one thread). The steps run on a thread of the pool
//! ([`veselov::run::on_pool`]), as the command line runs them. A third case
//! damps the 100-element rod and loads its end ([`RodLoads`]) and takes
//! each level's impulse of the loads as well, the work a run of a loaded
//! rod does per level (the vertex at the loaded end is solved alone, the
//! others in groups of eight), and a fourth the free 100-element rod one
//! vertex at a time (`with_vertex_lanes(1)`), the same bits as its default
//! groups of eight.
//!
//! `cargo bench -p veselov --bench rod_step -- --quick`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::Vector3;
use veselov::field::cauchy::{CauchyMarcher, CauchyOptions};
use veselov::field::fibre::{Pose, PositionRotation};
use veselov::lie::so3;
use veselov::models::rod::{CosseratCell, CosseratDensity, RodLoads, RodParameters, ShearFrame};
use veselov::models::rod::{CrossSection, Material, RodLattice, Shear, largest_step, load_impulse, rod_parameters};
use veselov::run::on_pool;

const LENGTH: f64 = 3.0;

/// Levels of each trial of the stability bisection: 20,000 steps.
const STABILITY_LEVELS: usize = 40_000;

fn parameters() -> RodParameters {
    let material = Material {
        density: 5000.0,
        young: 1e6,
        shear: Shear::Modulus(1e4),
        shear_coefficient: 1.0,
    };
    rod_parameters(&CrossSection::Circle { radius: 0.25 }, &material).expect("valid rod")
}

type Rod = CauchyMarcher<PositionRotation, CosseratCell, 6>;

/// A straight rod along e₃ with a small bending and twisting perturbation
/// that excites the short waves (a hash-like pattern in s).
fn rod(elements: usize, dt: f64) -> (Rod, RodLattice) {
    rod_with(elements, dt, None, ShearFrame::Vertex)
}

/// [`rod`] with `loads`, if any, and the shear in `frame`.
fn rod_with(elements: usize, dt: f64, loads: Option<RodLoads>, frame: ShearFrame) -> (Rod, RodLattice) {
    let lattice = RodLattice::new(elements + 1, LENGTH, dt).expect("lattice");
    let mut cell = CosseratCell::new(CosseratDensity::free(parameters()), lattice.ds(), dt)
        .expect("spacings")
        .with_shear_frame(frame);
    if let Some(loads) = loads {
        cell = cell.with_loads(loads).expect("valid loads");
    }
    let data = lattice.cauchy_data(|s, t| {
        let noise = (s * 1234.567).sin() * 1e-3;
        let tilt = Vector3::new(noise, 0.5 * noise, 0.2 * noise);
        Pose::new(Vector3::new(noise * (1.0 + t), 0.0, s), so3::exp(&tilt))
    });
    let m = CauchyMarcher::with_window(
        cell,
        lattice.torus().clone(),
        0,
        &data,
        CauchyOptions {
            tolerance: 1e-13,
            ..CauchyOptions::default()
        },
        lattice.window(),
    )
    .expect("marcher");
    (m, lattice)
}

/// Whether `levels` levels run without a solve failure and stay near the
/// straight rod (positions within 0.1 of their start).
fn stable(elements: usize, dt: f64, levels: usize) -> bool {
    let (mut m, _) = rod(elements, dt);
    for _ in 0..levels {
        if m.step().is_err() {
            return false;
        }
    }
    let w = m.top_level();
    m.level_values(w)
        .expect("level")
        .iter()
        .all(|y| y.position[0].abs() < 0.1 && y.position[1].abs() < 0.1)
}

fn report() {
    let elements = 100;
    let dl = LENGTH / elements as f64;
    let (mut lo, mut hi) = (0.05 * dl, 0.5 * dl);
    for _ in 0..10 {
        let mid = 0.5 * (lo + hi);
        if stable(elements, mid, STABILITY_LEVELS) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let predicted = largest_step(&parameters(), 2.0 * dl).expect("finite speeds");
    println!(
        "largest stable step at {elements} elements ({} steps): {:.4}·dl (unstable at {:.4}·dl); \
         predicted limit {:.4}·dl; PyElastica 0.0705·dl",
        STABILITY_LEVELS / 2,
        lo / dl,
        hi / dl,
        predicted / dl
    );
    for elements in [100, 1000] {
        let dl = LENGTH / elements as f64;
        let (mut m, lattice) = rod(elements, 0.0705 * dl);
        let (mut iterations, mut jacobians, mut vertices) = (0, 0, 0);
        for _ in 0..200 {
            let r = m.step().expect("stable");
            iterations += r.iterations;
            jacobians += r.jacobians;
            vertices += (0..lattice.torus().level_size())
                .filter(|&i| m.is_active(r.level, i))
                .count();
        }
        println!(
            "{elements} elements: Newton iterations per vertex {:.2}, Jacobians per vertex {:.2}",
            iterations as f64 / vertices as f64,
            jacobians as f64 / vertices as f64
        );
        // The least time per step over blocks of 200 steps: the cost of the
        // step itself, with the interruptions of a shared machine (which
        // inflate criterion's mean) left out.
        let best = on_pool(|| {
            let mut best = f64::INFINITY;
            for _ in 0..60 {
                let started = std::time::Instant::now();
                for _ in 0..200 {
                    black_box(m.step().expect("stable"));
                    black_box(m.step().expect("stable"));
                }
                best = best.min(started.elapsed().as_secs_f64() / 200.0);
            }
            best
        });
        println!(
            "{elements} elements: best of 60 blocks of 200 steps {:.1} µs per step (two levels, {} threads)",
            best * 1e6,
            rayon::current_num_threads()
        );
    }
}

/// The wall time of `steps` steps (two levels each) of `m` on a thread of
/// the pool.
fn time_steps(m: &mut Rod, steps: u64) -> std::time::Duration {
    on_pool(|| {
        let started = std::time::Instant::now();
        for _ in 0..steps {
            black_box(m.step().expect("stable"));
            black_box(m.step().expect("stable"));
        }
        started.elapsed()
    })
}

fn bench(c: &mut Criterion) {
    report();
    let mut group = c.benchmark_group("rod_step");
    for elements in [100, 1000] {
        let dl = LENGTH / elements as f64;
        group.bench_function(format!("{elements} elements, dt = 0.0705 dl (two levels)"), |b| {
            let (mut m, _) = rod(elements, 0.0705 * dl);
            b.iter_custom(|steps| time_steps(&mut m, steps));
        });
    }
    // The same 100-element rod one vertex at a time (the scalar split
    // step; by default eight vertices are solved side by side, with the
    // same bits).
    let elements = 100;
    let dl = LENGTH / elements as f64;
    group.bench_function(format!("{elements} elements, one vertex at a time (two levels)"), |b| {
        let (m, _) = rod(elements, 0.0705 * dl);
        let mut m = m.with_vertex_lanes(1);
        b.iter_custom(|steps| time_steps(&mut m, steps));
    });
    // The shear in the centred frame (no locking; the same split step and
    // lanes with its frames).
    group.bench_function(format!("{elements} elements, centred shear frame (two levels)"), |b| {
        let (mut m, _) = rod_with(elements, 0.0705 * dl, None, ShearFrame::Centred);
        b.iter_custom(|steps| time_steps(&mut m, steps));
    });
    let loads = RodLoads {
        damping_linear: 1.0,
        damping_angular: 0.01,
        end_force: Vector3::new(10.0, 0.0, 0.0),
        end_torque: Vector3::zeros(),
        tip: elements as i64,
        ramp: 1.0,
        start: 0.0,
    };
    group.bench_function(
        format!("{elements} elements, damped and end-loaded, with the level impulses (two levels)"),
        |b| {
            let (mut m, _) = rod_with(
                elements,
                0.0705 * LENGTH / elements as f64,
                Some(loads),
                ShearFrame::Vertex,
            );
            b.iter_custom(|steps| {
                on_pool(|| {
                    let started = std::time::Instant::now();
                    for _ in 0..2 * steps {
                        black_box(m.step().expect("stable"));
                        black_box(load_impulse(&m).expect("defined after a step"));
                    }
                    started.elapsed()
                })
            });
        },
    );
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench
}
criterion_main!(benches);
