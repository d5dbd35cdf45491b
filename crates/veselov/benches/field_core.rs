//! The field core's Cauchy marcher: nanoseconds per vertex update (one
//! Legendre solve plus the gradients of the n! cells it completes) on the
//! 2+1 CFK lattice, for a scalar sine-Gordon field (P1 simplices, a cell
//! Lagrangian written by hand), the same field from the smooth density
//! through the midpoint rule (the command line's path) with derivatives by
//! the interpolant's chain rule and, side by side, by dual numbers over the
//! whole cell, and for a frame field in ℝ³ × SO(3) (also with a fresh
//! Jacobian at every vertex: the hyper-dual blocks' hot path); with 1 and 2
//! threads.
//! Each level has `nodes²` vertices: divide the time per level by it. The
//! levels run on a thread of the pool, as the command line runs them.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::{Matrix3, SVector, Vector3};
use veselov::ad::Scalar;
use veselov::complex::{CfkTorus, TopCell, permutation};
use veselov::field::cauchy::{CauchyMarcher, CauchyOptions};
use veselov::field::cell::DiscreteLagrangian;
use veselov::field::discretize::{CfkNodes, MidpointRule};
use veselov::field::fibre::{Euclidean, Fibre, Pose, PositionRotation};
use veselov::lie::so3;
use veselov::spacetime::potential::{NonlinearWave, SineGordon};

const NODES: usize = 32;
/// Nodes per axis of the frame-field run (its vertex solves are 6-D, with
/// SO(3) logarithms over dual numbers, hyper-dual in the Jacobian blocks).
const FRAME_NODES: usize = 6;

/// 𝓛 = ½φ_t² − ½|∇φ|² − (1 − cos φ), P1 on the simplices of the space–time
/// CFK lattice x_a = Δx(v_a − w/3), t = wΔt/3.
struct SineGordonP1 {
    inverse: Vec<Matrix3<f64>>,
    volume: f64,
}

impl SineGordonP1 {
    fn new(dx: f64, dt: f64) -> Self {
        let node = |v: &[i64; 3]| {
            let w = (v[0] + v[1] + v[2]) as f64;
            Vector3::new(dx * (v[0] as f64 - w / 3.0), dx * (v[1] as f64 - w / 3.0), dt * w / 3.0)
        };
        let mut volume = 0.0;
        let inverse = (0..6)
            .map(|s| {
                let p = permutation(3, s);
                let mut v = [0i64; 3];
                let x0 = node(&v);
                let mut t = Matrix3::zeros();
                for l in 0..3 {
                    v[p[l]] += 1;
                    t.set_column(l, &(node(&v) - x0));
                }
                volume = t.determinant().abs() / 6.0;
                t.try_inverse().expect("non-degenerate simplex")
            })
            .collect();
        Self { inverse, volume }
    }
}

impl DiscreteLagrangian<Euclidean<1>, 1> for SineGordonP1 {
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[SVector<D, 1>]) -> D {
        let inv = &self.inverse[cell.shape];
        let d = [y[1][0] - y[0][0], y[2][0] - y[0][0], y[3][0] - y[0][0]];
        let g = |a: usize| d[0] * inv[(0, a)] + d[1] * inv[(1, a)] + d[2] * inv[(2, a)];
        let (gx, gy, gt) = (g(0), g(1), g(2));
        let mean = (y[0][0] + y[1][0] + y[2][0] + y[3][0]) * 0.25;
        ((gt * gt - gx * gx - gy * gy) * 0.5 - (D::one() - mean.cos())) * self.volume
    }
}

/// A frame field: kinetic terms ½|r_n − r_0|² + ½|log R₀ᵀR_n|² on the
/// time-like edge (v₀, v_n) of each simplex, strain terms
/// −½|Rᵀ(r_{l+1} − r_l) − e₁|² − ½|log R_lᵀR_{l+1}|² on its path edges.
struct FrameField;

fn edge<D: Scalar>(a: &Pose<D>, b: &Pose<D>, rest: f64) -> D {
    let strain =
        a.rotation.matrix().transpose() * (b.position - a.position) - Vector3::new(D::from(rest), D::zero(), D::zero());
    let bend = so3::log(&a.rotation.inverse().compose(&b.rotation)).unwrap_or_else(|_| Vector3::zeros());
    (strain.dot(&strain) + bend.dot(&bend)) * 0.5
}

impl DiscreteLagrangian<PositionRotation, 6> for FrameField {
    fn cell_lagrangian<D: Scalar>(&self, _cell: &TopCell, y: &[Pose<D>]) -> D {
        let n = y.len() - 1;
        let mut lag = edge(&y[0], &y[n], 0.0) * 4.0;
        for l in 0..n {
            lag -= edge(&y[l], &y[l + 1], 0.5) * 0.1;
        }
        lag
    }
}

fn scalar_data(torus: &CfkTorus) -> Vec<Vec<SVector<f64, 1>>> {
    (0..6)
        .map(|w| {
            (0..torus.level_size())
                .map(|i| {
                    let v = torus.vertex(w, i);
                    SVector::from([0.3 * ((v[0] as f64) * 0.4).sin() + 0.2 * ((v[1] as f64) * 0.2).cos()])
                })
                .collect()
        })
        .collect()
}

fn frame_data(torus: &CfkTorus) -> Vec<Vec<Pose<f64>>> {
    (0..6)
        .map(|w| {
            (0..torus.level_size())
                .map(|i| {
                    let v = torus.vertex(w, i);
                    let s = (v[0] - v[1]) as f64 * 0.5;
                    Pose::new(
                        Vector3::new(s, 0.01 * w as f64, 0.0),
                        so3::exp(&Vector3::new(0.01 * s, 0.0, 0.001 * w as f64)),
                    )
                })
                .collect()
        })
        .collect()
}

fn bench_marcher<F: Fibre<M>, L: DiscreteLagrangian<F, M>, const M: usize>(
    c: &mut Criterion,
    name: &str,
    nodes: usize,
    make: impl Fn() -> CauchyMarcher<F, L, M> + Sync,
) where
    F::Point<f64>: Send + Sync,
{
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool");
        let mut m = make();
        let (mut iterations, mut jacobians, mut solved) = (0usize, 0usize, 0usize);
        let mut levels = 0usize;
        c.bench_function(&format!("{name}/{nodes}x{nodes}/threads={threads}"), |b| {
            // The levels run on a thread of the pool, as the command line
            // runs them (one hand-over into the pool per sample, not per level).
            b.iter_custom(|count| {
                pool.install(|| {
                    let mut elapsed = std::time::Duration::ZERO;
                    for _ in 0..count {
                        if levels >= 400 {
                            m = make();
                            levels = 0;
                        }
                        let started = std::time::Instant::now();
                        let report = m.step().expect("level");
                        elapsed += started.elapsed();
                        iterations += report.iterations;
                        jacobians += report.jacobians;
                        solved += nodes * nodes;
                        levels += 1;
                        black_box(report);
                    }
                    elapsed
                })
            })
        });
        let per = |k: usize| k as f64 / solved.max(1) as f64;
        println!(
            "{name}: {:.2} Newton iterations, {:.2} Jacobians per vertex",
            per(iterations),
            per(jacobians)
        );
    }
}

fn field_core(c: &mut Criterion) {
    let torus = CfkTorus::new(3, &[NODES, NODES]).expect("torus");
    bench_marcher(c, "sine-gordon-2+1", NODES, || {
        CauchyMarcher::new(
            SineGordonP1::new(0.2, 0.05),
            torus.clone(),
            0,
            &scalar_data(&torus),
            CauchyOptions::default(),
        )
        .expect("marcher")
    });
    let nodes = CfkNodes::<3>::space_time(0.2, 0.05).expect("node map");
    for (name, chain_rule) in [
        ("sine-gordon-2+1-midpoint-rule", true),
        ("sine-gordon-2+1-midpoint-rule-cell-duals", false),
    ] {
        bench_marcher(c, name, NODES, || {
            CauchyMarcher::new(
                MidpointRule::new(NonlinearWave(SineGordon), nodes).with_chain_rule(chain_rule),
                torus.clone(),
                0,
                &scalar_data(&torus),
                CauchyOptions::default(),
            )
            .expect("marcher")
        });
    }
    let frames = CfkTorus::new(3, &[FRAME_NODES, FRAME_NODES]).expect("torus");
    // With the Jacobian kept and Broyden's update (the default), and with a
    // fresh Jacobian (hyper-dual blocks) at every vertex.
    for (name, reuse) in [
        ("frame-field-2+1", true),
        ("frame-field-2+1-jacobian-every-vertex", false),
    ] {
        bench_marcher(c, name, FRAME_NODES, || {
            CauchyMarcher::new(
                FrameField,
                frames.clone(),
                0,
                &frame_data(&frames),
                CauchyOptions::default(),
            )
            .expect("marcher")
            .with_jacobian_reuse(reuse)
        });
    }
}

criterion_group!(benches, field_core);
criterion_main!(benches);
