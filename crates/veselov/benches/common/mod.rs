//! Shared driver of the step benchmarks.

use std::hint::black_box;

use criterion::Criterion;
use veselov::mechanics::{OneStepMap, PhaseState};

/// Steps between restarts from the initial state.
pub const RESTART: usize = 10_000;

/// Benchmark one step of `map` along a trajectory from `x0`, restarting
/// every [`RESTART`] steps to stay on the same orbit.
pub fn bench_map<const N: usize, M: OneStepMap<N>>(c: &mut Criterion, name: &str, mut map: M, x0: PhaseState<N>) {
    let mut x = x0;
    let mut k = 0usize;
    c.bench_function(name, |b| {
        b.iter(|| {
            if k.is_multiple_of(RESTART) {
                x = x0;
            }
            x = map.step(k, black_box(&x)).expect("step").0;
            k += 1;
        })
    });
}
