//! Exact conservation of Noether momenta and bounded energy error.

use crate::common;

use common::{all_methods, scheme};
use nalgebra::Vector1;
use veselov::diagnostics::momentum_series;
use veselov::mechanics::{GalerkinIntegrator, OneStepMap, PhaseState, SeparableIntegrator, integrate};
use veselov::models::{Kepler, Pendulum};

fn angular_drift<M: OneStepMap<2>>(map: &mut M, x0: PhaseState<2>, steps: usize) -> f64 {
    let run = integrate(map, x0, steps, 1);
    assert!(run.failure.is_none(), "{:?}", run.failure);
    momentum_series(&Kepler::angular_symmetry(), &run.states).max_rel_error()
}

/// Kepler, e = 0.5, h = 2π/200, 10⁴ steps (50 orbits): the angular momentum
/// is a discrete Noether momentum of every method and must stay within 1e-12
/// relative (round-off only).
#[test]
fn kepler_angular_momentum_is_conserved_by_every_method() {
    let kepler = Kepler::new(0.5).expect("valid");
    let x0 = kepler.initial_state();
    let h = 2.0 * std::f64::consts::PI / 200.0;
    for method in all_methods() {
        let mut general = GalerkinIntegrator::new(kepler.system(), scheme(method), h).expect("valid");
        let drift = angular_drift(&mut general, x0, 10_000);
        assert!(drift <= 1e-12, "{method:?} general path: relative drift {drift:e}");
        let mut fast = SeparableIntegrator::new(kepler.system(), scheme(method), h).expect("valid");
        let drift = angular_drift(&mut fast, x0, 10_000);
        assert!(drift <= 1e-12, "{method:?} separable path: relative drift {drift:e}");
    }
}

/// Pendulum, midpoint, h = 0.1, 10⁶ steps: the energy error oscillates without
/// drift: its maximum over the last tenth is within 10% of that over the first tenth.
#[test]
fn pendulum_midpoint_energy_error_does_not_drift() {
    let pendulum = Pendulum::default();
    let x0 = PhaseState::new(0.0, Vector1::new(1.0), Vector1::new(0.0));
    let e0 = pendulum.energy(&x0);
    let mut map =
        SeparableIntegrator::new(pendulum.system(), scheme(veselov::mechanics::Method::Midpoint), 0.1).expect("valid");
    let steps = 1_000_000;
    let tenth = steps / 10;
    let (mut first, mut last) = (0.0_f64, 0.0_f64);
    let mut x = x0;
    for k in 0..steps {
        x = map.step(k, &x).expect("step").0;
        let err = (pendulum.energy(&x) - e0).abs();
        if k < tenth {
            first = first.max(err);
        } else if k >= steps - tenth {
            last = last.max(err);
        }
    }
    assert!(first > 0.0);
    assert!(
        (last - first).abs() <= 0.1 * first,
        "first tenth {first:e}, last tenth {last:e}"
    );
}
