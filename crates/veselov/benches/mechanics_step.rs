//! Nanoseconds per step of the mechanics integrators on their hot path.
//!
//! Each benchmark advances a trajectory one step per iteration (so predictors
//! see a continuing trajectory, as in production runs), restarting from the
//! initial state every 10⁵ steps to stay on the same orbit.

use criterion::{Criterion, criterion_group, criterion_main};

mod common;
use common::bench_map;
use nalgebra::Vector1;
use veselov::mechanics::{GalerkinIntegrator, GalerkinScheme, Method, PhaseState, SeparableIntegrator};
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
        ("lobatto-s3", Method::GalerkinLobatto(3)),
    ] {
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

criterion_group!(benches, mechanics);
criterion_main!(benches);
