//! Shared driver of the step benchmarks.

use std::hint::black_box;

use criterion::Criterion;
use nalgebra::SVector;
use veselov::ad::Scalar;
use veselov::mechanics::{Lagrangian, OneStepMap, PhaseState};

/// A Lagrangian without its declaration of the separable form
/// ([`Lagrangian::constant_mass`]): every derivative takes the general
/// passes over the whole `L`, as for any Lagrangian that is not `½vᵀMv − V`.
#[allow(dead_code)] // not every benchmark binary needs it
pub struct Undeclared<L>(pub L);

impl<L: Lagrangian<N>, const N: usize> Lagrangian<N> for Undeclared<L> {
    fn lagrangian<D: Scalar>(&self, t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> D {
        self.0.lagrangian(t, q, v)
    }
}

/// Steps between restarts from the initial state.
pub const RESTART: usize = 10_000;

/// Benchmark one call of `step(k, state)` along a trajectory from `x0`,
/// restarting from `x0` every `restart` steps to stay on the same orbit.
pub fn bench_steps<S: Copy>(
    c: &mut Criterion,
    name: &str,
    x0: S,
    restart: usize,
    mut step: impl FnMut(usize, &S) -> S,
) {
    let mut x = x0;
    let mut k = 0usize;
    c.bench_function(name, |b| {
        b.iter(|| {
            if k.is_multiple_of(restart) {
                x = x0;
            }
            x = step(k, black_box(&x));
            k += 1;
        })
    });
}

/// Benchmark one step of `map` along a trajectory from `x0`, restarting
/// every [`RESTART`] steps to stay on the same orbit, after printing its
/// machine-independent cost ([`report_evaluations`]).
#[allow(dead_code)] // not every benchmark binary steps a `OneStepMap`
pub fn bench_map<const N: usize, M: OneStepMap<N>>(c: &mut Criterion, name: &str, mut map: M, x0: PhaseState<N>) {
    report_evaluations(name, &mut map, x0);
    bench_steps(c, name, x0, RESTART, |k, x| map.step(k, x).expect("step").0);
}

/// Print the machine-independent cost beside the timings, over 10⁴
/// continuing steps: iterations (fixed-point sweeps or Newton residuals),
/// exact Jacobians and ∇V evaluations per step.
pub fn report_evaluations<const N: usize, M: OneStepMap<N>>(name: &str, map: &mut M, x0: PhaseState<N>) {
    let (mut x, mut evaluations, mut iterations, mut jacobians) = (x0, 0, 0, 0);
    let n = 10_000;
    for k in 0..n {
        let (next, stats) = map.step(k, &x).expect("step");
        x = next;
        evaluations += stats.force_evaluations;
        iterations += stats.iterations;
        jacobians += stats.jacobians;
    }
    let per = |c: usize| c as f64 / n as f64;
    eprintln!(
        "{name}: per step {:.3} iterations, {:.3} Jacobians, {:.3} ∇V evaluations",
        per(iterations),
        per(jacobians),
        per(evaluations)
    );
}
