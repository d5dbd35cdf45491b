//! Nanoseconds per step of the variable-step SEM integrators (fixed-energy form).
//! Each benchmark restarts from the first step periodically to stay on its orbit.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};

mod common;
use common::{Undeclared, bench_steps};
use nalgebra::{Vector1, Vector2};
use veselov::mechanics::Lagrangian;
use veselov::models::{DoublePendulum, Kepler, Pendulum};
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
    // The general passes (a Lagrangian that does not declare the form
    // ½ vᵀMv − V): the same Kepler problem, and the double pendulum.
    let sem = SemIntegrator::new(SemAction::new(Undeclared(kepler.system()), SemRule::Midpoint).expect("valid"));
    let (_, s1) = sem
        .start(0.0, x0.q, x0.p, 2.0 * std::f64::consts::PI / 1000.0)
        .expect("start");
    bench(c, "sem/kepler-e0.5-general/midpoint", sem, s1, 20_000);
    let double = DoublePendulum::default();
    let sem = SemIntegrator::new(SemAction::new(double, SemRule::Midpoint).expect("valid"));
    let (_, s1) = sem
        .start(0.0, Vector2::new(0.5, -0.3), Vector2::new(0.0, 0.0), 0.01)
        .expect("start");
    bench(c, "sem/double-pendulum/midpoint", sem, s1, 20_000);
}

/// The passes a step is made of, on Kepler (N = 2) at a pericentre step:
/// the residual (two first-order passes), the part of the exact step
/// Jacobian updated every step (three small hyper-dual passes), the momentum
/// block evaluated with a whole Jacobian (closed form: one second-order pass
/// over `V` per node), the momentum residual alone and the arrival momentum
/// and energy (closed forms: first-order passes over `V`).
fn parts(c: &mut Criterion) {
    let kepler = Kepler::new(0.5).expect("valid");
    let x0 = kepler.initial_state();
    let action = SemAction::new(kepler.system(), SemRule::Midpoint).expect("valid");
    let h = 2.0 * std::f64::consts::PI / 1000.0;
    let q1 = x0.q + x0.p * h;
    let name = "sem/kepler-e0.5/parts";
    c.bench_function(&format!("{name}/residual"), |b| {
        b.iter(|| action.leaving(0.0, black_box(&x0.q), black_box(&q1), h))
    });
    c.bench_function(&format!("{name}/jacobian-along"), |b| {
        b.iter(|| action.step_jacobian_along(0.0, black_box(&x0.q), black_box(&q1), h))
    });
    c.bench_function(&format!("{name}/momentum-block"), |b| {
        b.iter(|| action.momentum_block(0.0, black_box(&x0.q), black_box(&q1), h))
    });
    c.bench_function(&format!("{name}/momentum-residual"), |b| {
        b.iter(|| action.leaving_momentum(0.0, black_box(&x0.q), black_box(&q1), h))
    });
    c.bench_function(&format!("{name}/arrival"), |b| {
        b.iter(|| action.arrival(0.0, black_box(&x0.q), black_box(&q1), h))
    });
}

criterion_group!(benches, sem, parts);
criterion_main!(benches);
