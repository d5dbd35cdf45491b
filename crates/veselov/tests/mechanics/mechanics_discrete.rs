//! Discrete Lagrangians: derivatives against finite differences of L_d, the
//! two-step form, initialisation from velocities, the fast separable path
//! against the general Newton path, and the declared separable form against
//! the general derivatives.

use crate::common;

use common::{all_methods, scheme};
use nalgebra::{SVector, Vector2};
use veselov::ad::Scalar;
use veselov::mechanics::{
    GalerkinIntegrator, Lagrangian, OneStepMap, PhaseState, SeparableIntegrator, hessian, integrate, jet,
};
use veselov::models::{DoublePendulum, Kepler};

/// `p₀ = −D₁L_d` and `p₁ = D₂L_d` against central differences of `L_d` itself.
#[test]
fn discrete_legendre_transforms_match_finite_differences_of_the_discrete_lagrangian() {
    let (q0, q1) = (Vector2::new(0.4, -0.3), Vector2::new(0.45, -0.2));
    for method in all_methods() {
        let mut map = GalerkinIntegrator::new(DoublePendulum::default(), scheme(method), 0.1).expect("valid");
        let ld = map.discrete_lagrangian(0.2, &q0, &q1).expect("solvable");
        let eps = 1e-5;
        for i in 0..2 {
            let mut e = Vector2::zeros();
            e[i] = eps;
            let d1 = (map.discrete_lagrangian(0.2, &(q0 + e), &q1).expect("ok").value
                - map.discrete_lagrangian(0.2, &(q0 - e), &q1).expect("ok").value)
                / (2.0 * eps);
            let d2 = (map.discrete_lagrangian(0.2, &q0, &(q1 + e)).expect("ok").value
                - map.discrete_lagrangian(0.2, &q0, &(q1 - e)).expect("ok").value)
                / (2.0 * eps);
            // Central differences: truncation O(eps²·L_d''') plus round-off O(1e-16/eps).
            assert!(
                (-ld.minus[i] - d1).abs() < 1e-8,
                "{method:?} D1[{i}]: {} vs {d1}",
                -ld.minus[i]
            );
            assert!(
                (ld.plus[i] - d2).abs() < 1e-8,
                "{method:?} D2[{i}]: {} vs {d2}",
                ld.plus[i]
            );
        }
    }
}

/// The two-step form `(q_{k−1}, q_k) ↦ q_{k+1}` reproduces the position–momentum trajectory.
#[test]
fn two_step_form_matches_position_momentum_form() {
    let x0 = PhaseState::new(0.0, Vector2::new(0.5, 0.1), Vector2::new(0.2, -0.1));
    for method in all_methods() {
        let h = 0.05;
        let mut map = GalerkinIntegrator::new(DoublePendulum::default(), scheme(method), h).expect("valid");
        let run = integrate(&mut map, x0, 20, 1);
        let qs: Vec<_> = run.states.iter().map(|x| x.q).collect();
        let mut two = GalerkinIntegrator::new(DoublePendulum::default(), scheme(method), h).expect("valid");
        let (mut prev, mut cur) = (qs[0], qs[1]);
        for (k, expected) in qs.iter().enumerate().skip(2) {
            let next = two.step_two_point((k - 1) as f64 * h, &prev, &cur).expect("step");
            assert!(
                (next - expected).amax() < 1e-12,
                "{method:?} step {k}: {next:?} vs {expected:?}"
            );
            (prev, cur) = (cur, next);
        }
    }
}

/// The fixed-point separable path equals the general Newton path to round-off, step by step.
#[test]
fn separable_fast_path_equals_general_path() {
    let kepler = Kepler::new(0.6).expect("valid");
    let h = 2.0 * std::f64::consts::PI / 1000.0;
    for method in all_methods() {
        let mut general = GalerkinIntegrator::new(kepler.system(), scheme(method), h).expect("valid");
        let mut fast = SeparableIntegrator::new(kepler.system(), scheme(method), h).expect("valid");
        let mut x = kepler.initial_state();
        for k in 0..1000 {
            let (a, _) = general.step(k, &x).expect("step");
            let (b, stats) = fast.step(k, &x).expect("step");
            assert!(!stats.fallback);
            let d = (a.q - b.q).amax().max((a.p - b.p).amax());
            // Both solve the same equations to round-off; they differ by a few ulps of |p| ≤ 2.
            assert!(d < 2e-14, "{method:?} step {k}: difference {d:e}");
            x = b;
        }
    }
}

/// A Lagrangian without its declaration of the separable form: every
/// derivative goes through the general passes over the whole `L`.
struct Undeclared<L>(L);

impl<L: Lagrangian<N>, const N: usize> Lagrangian<N> for Undeclared<L> {
    fn lagrangian<D: Scalar>(&self, t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> D {
        self.0.lagrangian(t, q, v)
    }
}

/// With `L = ½vᵀMv − V` declared, the jets and Hessians come from `V` alone
/// (`∂L/∂v = Mv`, `∂²L/∂q∂v = 0`): they equal the general passes over the
/// whole `L` to round-off at random points, and the general Newton path
/// steps the same trajectory either way.
#[test]
fn declared_separable_form_equals_the_general_derivatives() {
    let kepler = Kepler::new(0.6).expect("valid");
    let (declared, undeclared) = (kepler.system(), Undeclared(kepler.system()));
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut uniform = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for _ in 0..50 {
        let q = Vector2::new(1.0 + uniform(), uniform());
        let v = Vector2::new(uniform(), uniform());
        let t = uniform();
        let (a, b) = (hessian(&declared, t, &q, &v), hessian(&undeclared, t, &q, &v));
        let scale = 1.0 + b.qq.amax();
        assert!((a.jet.value - b.jet.value).abs() < 1e-15 * scale);
        assert!((a.jet.dq - b.jet.dq).amax() < 1e-15 * scale);
        assert_eq!(a.jet.dv, b.jet.dv);
        assert!((a.qq - b.qq).amax() < 1e-15 * scale, "{:e}", (a.qq - b.qq).amax());
        assert_eq!((a.qv.amax(), b.qv.amax()), (0.0, 0.0));
        assert_eq!(a.vv, b.vv);
        assert_eq!(jet(&declared, t, &q, &v), a.jet);
    }
    let h = 2.0 * std::f64::consts::PI / 1000.0;
    for method in all_methods() {
        let mut fast = GalerkinIntegrator::new(declared.clone(), scheme(method), h).expect("valid");
        let mut general = GalerkinIntegrator::new(Undeclared(declared.clone()), scheme(method), h).expect("valid");
        let mut x = kepler.initial_state();
        for k in 0..1000 {
            let (a, _) = general.step(k, &x).expect("step");
            let (b, _) = fast.step(k, &x).expect("step");
            let d = (a.q - b.q).amax().max((a.p - b.p).amax());
            // The same equations solved to round-off; a few ulps of |p| ≤ 2.
            assert!(d < 2e-14, "{method:?} step {k}: difference {d:e}");
            x = b;
        }
    }
}

/// Initialisation from velocities uses the continuous Legendre transform.
#[test]
fn initial_state_from_velocity() {
    let dp = DoublePendulum::default();
    let (q, v) = (Vector2::new(0.3, -0.4), Vector2::new(0.5, 0.25));
    let x = PhaseState::from_velocity(&dp, 0.0, q, v).expect("finite");
    let back = veselov::mechanics::velocity_from_momentum(&dp, 0.0, &x.q, &x.p).expect("regular");
    assert!((back - v).amax() < 1e-14);
    // p₀ = 2 v₀ + v₁ cos(θ₀ − θ₁) for unit parameters.
    assert!((x.p[0] - (2.0 * v[0] + v[1] * (q[0] - q[1]).cos())).abs() < 1e-15);
}

/// The driver's exact step times `t₀ + k·h` still count as continuing the
/// previous step, so the predictor and the compensated sums stay in use: the
/// driven run costs the same iterations as stepping by hand.
#[test]
fn driver_keeps_the_predictor() {
    let kepler = Kepler::new(0.5).expect("valid");
    let h = 0.0123;
    for method in [
        veselov::mechanics::Method::GalerkinGauss(2),
        veselov::mechanics::Method::GalerkinLobatto(3),
    ] {
        let mut a = SeparableIntegrator::new(kepler.system(), scheme(method), h).expect("valid");
        let run = integrate(&mut a, kepler.initial_state(), 3000, 3000);
        let mut b = SeparableIntegrator::new(kepler.system(), scheme(method), h).expect("valid");
        let mut x = kepler.initial_state();
        let mut total = 0;
        for k in 0..3000 {
            let (next, stats) = b.step(k, &x).expect("step");
            total += stats.iterations;
            x = next;
        }
        assert_eq!(run.total_iterations, total, "{method:?}");
    }
}
