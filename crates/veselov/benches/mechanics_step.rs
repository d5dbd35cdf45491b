//! Nanoseconds per step of the mechanics integrators on their hot path.
//!
//! Each benchmark advances a trajectory one step per iteration (so predictors
//! see a continuing trajectory, as in production runs), restarting from the
//! initial state every 10⁵ steps to stay on the same orbit.

use criterion::{Criterion, criterion_group, criterion_main};

mod common;
use common::bench_map;
use nalgebra::Vector1;
use veselov::mechanics::{GalerkinIntegrator, GalerkinScheme, Method, OneStepMap, PhaseState, SeparableIntegrator};
use veselov::models::{HenonHeiles, Kepler, Pendulum};

fn scheme(m: Method) -> GalerkinScheme {
    GalerkinScheme::new(m).expect("valid")
}

fn mechanics(c: &mut Criterion) {
    let pendulum = Pendulum::default();
    let x0 = PhaseState::new(0.0, Vector1::new(1.0), Vector1::new(0.0));
    bench_map(
        c,
        "pendulum/midpoint/separable",
        SeparableIntegrator::new(pendulum.system(), scheme(Method::Midpoint), 0.1).expect("valid"),
        x0,
    );
    bench_map(
        c,
        "pendulum/midpoint/general",
        GalerkinIntegrator::new(pendulum.system(), scheme(Method::Midpoint), 0.1).expect("valid"),
        x0,
    );

    let kepler = Kepler::new(0.6).expect("valid");
    let h = 2.0 * std::f64::consts::PI / 1000.0;
    for (name, m) in [
        ("gauss-s2", Method::GalerkinGauss(2)),
        ("gauss-s4", Method::GalerkinGauss(4)),
        ("gauss-s6", Method::GalerkinGauss(6)),
        ("lobatto-s3", Method::GalerkinLobatto(3)),
    ] {
        report_evaluations(
            &format!("kepler-e0.6/{name}/separable"),
            SeparableIntegrator::new(kepler.system(), scheme(m), h).expect("valid"),
            kepler.initial_state(),
        );
        bench_map(
            c,
            &format!("kepler-e0.6/{name}/separable"),
            SeparableIntegrator::new(kepler.system(), scheme(m), h).expect("valid"),
            kepler.initial_state(),
        );
        bench_map(
            c,
            &format!("kepler-e0.6/{name}/general"),
            GalerkinIntegrator::new(kepler.system(), scheme(m), h).expect("valid"),
            kepler.initial_state(),
        );
    }

    let hh = HenonHeiles;
    bench_map(
        c,
        "henon-heiles/gauss-s3/separable",
        SeparableIntegrator::new(hh.system(), scheme(Method::GalerkinGauss(3)), 0.05).expect("valid"),
        HenonHeiles::initial_state(),
    );
    bench_map(
        c,
        "henon-heiles/gauss-s3/general",
        GalerkinIntegrator::new(hh.system(), scheme(Method::GalerkinGauss(3)), 0.05).expect("valid"),
        HenonHeiles::initial_state(),
    );
}

/// Print the machine-independent cost beside the timings: mean ∇V
/// evaluations and fixed-point sweeps per step over 10⁴ continuing steps.
fn report_evaluations<M: OneStepMap<2>>(name: &str, mut map: M, x0: PhaseState<2>) {
    let (mut x, mut evaluations, mut sweeps) = (x0, 0, 0);
    let n = 10_000;
    for k in 0..n {
        let (next, stats) = map.step(k, &x).expect("step");
        (x, evaluations, sweeps) = (next, evaluations + stats.force_evaluations, sweeps + stats.iterations);
    }
    eprintln!(
        "{name}: {:.3} ∇V evaluations and {:.3} sweeps per step",
        evaluations as f64 / n as f64,
        sweeps as f64 / n as f64
    );
}

criterion_group!(benches, mechanics);
criterion_main!(benches);
