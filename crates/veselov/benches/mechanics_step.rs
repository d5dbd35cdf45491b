//! Nanoseconds per step of the mechanics integrators on their hot path.
//!
//! Each benchmark advances a trajectory one step per iteration (so predictors
//! see a continuing trajectory, as in production runs), restarting from the
//! initial state every 10⁵ steps to stay on the same orbit.

use criterion::{Criterion, criterion_group, criterion_main};

mod common;
use common::{Undeclared, bench_map};
use nalgebra::{SVector, Vector1, Vector2};
use veselov::ad::Scalar;
use veselov::mechanics::{GalerkinIntegrator, GalerkinScheme, Lagrangian, Method, PhaseState, SeparableIntegrator};
use veselov::models::{DoublePendulum, HenonHeiles, Kepler, Pendulum};

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

    // Kepler without its declaration of the separable form: the general
    // path's derivative passes over the whole L, as for a Lagrangian that is
    // not ½vᵀMv − V.
    bench_map(
        c,
        "kepler-e0.6/gauss-s2/general-undeclared",
        GalerkinIntegrator::new(Undeclared(kepler.system()), scheme(Method::GalerkinGauss(2)), h).expect("valid"),
        kepler.initial_state(),
    );

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

/// A charged particle in a uniform magnetic field `B` and a harmonic trap:
/// `L = ½|v|² + (B/2)(x v_y − y v_x) − ½|q|²` (not separable: the general path).
struct ChargedParticle {
    field: f64,
}

impl Lagrangian<2> for ChargedParticle {
    fn lagrangian<D: Scalar>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        let half = D::from(0.5);
        half * v.dot(v) + D::from(0.5 * self.field) * (q[0] * v[1] - q[1] * v[0]) - half * q.dot(q)
    }
}

/// The Newton path on Lagrangians that are not `½vᵀMv − V`.
fn non_separable(c: &mut Criterion) {
    let lobatto4 = || scheme(Method::GalerkinLobatto(4));
    let x0 = PhaseState::new(0.0, Vector2::new(0.5, -0.3), Vector2::new(0.0, 0.0));
    bench_map(
        c,
        "double-pendulum/lobatto-s4/general",
        GalerkinIntegrator::new(DoublePendulum::default(), lobatto4(), 0.01).expect("valid"),
        x0,
    );
    let particle = || ChargedParticle { field: 2.0 };
    let x0 = PhaseState::new(0.0, Vector2::new(1.0, 0.0), Vector2::new(0.0, 1.5));
    for (name, m) in [
        ("gauss-s2", Method::GalerkinGauss(2)),
        ("gauss-s4", Method::GalerkinGauss(4)),
    ] {
        bench_map(
            c,
            &format!("charged-particle/{name}/general"),
            GalerkinIntegrator::new(particle(), scheme(m), 0.01).expect("valid"),
            x0,
        );
    }
}

criterion_group!(benches, mechanics, non_separable);
criterion_main!(benches);
