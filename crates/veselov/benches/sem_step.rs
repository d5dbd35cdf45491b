//! Nanoseconds per step of the variable-step SEM integrators (fixed-energy form).
//! Each benchmark restarts from the first step periodically to stay on its orbit.

use criterion::{Criterion, criterion_group, criterion_main};

mod common;
use common::bench_steps;
use nalgebra::Vector1;
use veselov::mechanics::Lagrangian;
use veselov::models::{Kepler, Pendulum};
use veselov::sem::{SemAction, SemIntegrator, SemRule, SemState};

fn bench<L: Lagrangian<N>, const N: usize>(
    c: &mut Criterion,
    name: &str,
    mut sem: SemIntegrator<L, N>,
    s1: SemState<N>,
    restart: usize,
) {
    // Step indices start at 1: step 0 is the starting step of `start`.
    bench_steps(c, name, s1, restart, |k, s| sem.step(k + 1, s).expect("step").0);
}

fn sem(c: &mut Criterion) {
    let pendulum = Pendulum::default();
    for (name, rule) in [("midpoint", SemRule::Midpoint), ("averaged-2", SemRule::Averaged(2))] {
        let sem = SemIntegrator::new(SemAction::new(pendulum.system(), rule).expect("valid"));
        let (_, s1) = sem
            .start(0.0, Vector1::new(1.0), Vector1::new(0.0), 0.1)
            .expect("start");
        // The averaged rule degenerates at the bottom of the swing (c = −|∇V|²/8 → 0,
        // note 001 §3.3): restart it every 10 steps, before q reaches 0.
        let restart = if rule == SemRule::Midpoint { 20_000 } else { 10 };
        bench(c, &format!("sem/pendulum/{name}"), sem, s1, restart);
    }
    let kepler = Kepler::new(0.5).expect("valid");
    let x0 = kepler.initial_state();
    for (name, rule) in [("midpoint", SemRule::Midpoint), ("averaged-2", SemRule::Averaged(2))] {
        let sem = SemIntegrator::new(SemAction::new(kepler.system(), rule).expect("valid"));
        let (_, s1) = sem
            .start(0.0, x0.q, x0.p, 2.0 * std::f64::consts::PI / 1000.0)
            .expect("start");
        bench(c, &format!("sem/kepler-e0.5/{name}"), sem, s1, 20_000);
    }
}

criterion_group!(benches, sem);
criterion_main!(benches);
