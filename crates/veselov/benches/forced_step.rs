//! Nanoseconds per step of the forced (discrete Lagrange–d'Alembert) integrators.

use criterion::{Criterion, criterion_group, criterion_main};

mod common;
use common::bench_map;
use nalgebra::{Matrix2, Vector2};
use veselov::mechanics::{GalerkinIntegrator, GalerkinScheme, Method, PhaseState, SeparableIntegrator};
use veselov::models::{DampedOscillator, VanDerPol};

fn forced(c: &mut Criterion) {
    let vdp = VanDerPol::default();
    let lobatto3 = || GalerkinScheme::new(Method::GalerkinLobatto(3)).expect("valid");
    let h = 0.01;
    bench_map(
        c,
        "van-der-pol/lobatto-s3/separable",
        SeparableIntegrator::with_force(vdp.system(), vdp.force(), lobatto3(), h).expect("valid"),
        VanDerPol::initial_state(),
    );
    bench_map(
        c,
        "van-der-pol/lobatto-s3/general",
        GalerkinIntegrator::with_force(vdp.system(), vdp.force(), lobatto3(), h).expect("valid"),
        VanDerPol::initial_state(),
    );

    let osc = DampedOscillator::new(
        Matrix2::identity(),
        Matrix2::new(2.0, -1.0, -1.0, 2.0),
        Matrix2::identity() * 0.1,
    )
    .expect("valid");
    let x0 = PhaseState::new(0.0, Vector2::new(1.0, 0.0), Vector2::new(0.0, 0.5));
    let mid = || GalerkinScheme::new(Method::Midpoint).expect("valid");
    bench_map(
        c,
        "damped-oscillator/midpoint/separable",
        SeparableIntegrator::with_force(osc.system(), osc.force(), mid(), 0.01).expect("valid"),
        x0,
    );
    bench_map(
        c,
        "damped-oscillator/midpoint/general",
        GalerkinIntegrator::with_force(osc.system(), osc.force(), mid(), 0.01).expect("valid"),
        x0,
    );
}

criterion_group!(benches, forced);
criterion_main!(benches);
