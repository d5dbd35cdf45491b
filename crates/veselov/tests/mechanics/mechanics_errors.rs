//! Bad input gives a typed error, never NaN or a panic.

use nalgebra::{SVector, Vector1, Vector2};
use veselov::Error;
use veselov::ad::Scalar;
use veselov::mechanics::{
    GalerkinIntegrator, GalerkinScheme, Lagrangian, Method, OneStepMap, PhaseState, acceleration, integrate,
    velocity_from_momentum,
};
use veselov::models::{Kepler, Pendulum};
use veselov::solve::NewtonOptions;

#[test]
fn non_finite_initial_data_is_rejected() {
    let mut map =
        GalerkinIntegrator::new(Pendulum::default().system(), GalerkinScheme::midpoint(), 0.1).expect("valid");
    let bad = PhaseState::new(0.0, Vector1::new(f64::NAN), Vector1::new(0.0));
    assert!(matches!(map.step(0, &bad), Err(Error::NonFinite { ref what, .. }) if what == "q"));
    let run = integrate(
        &mut map,
        PhaseState::new(0.0, Vector1::new(0.0), Vector1::new(f64::INFINITY)),
        10,
        1,
    );
    assert!(matches!(run.failure, Some(Error::NonFinite { ref what, .. }) if what == "p"));
    assert!(matches!(
        PhaseState::<1>::from_slices(0.0, &[1.0], &[f64::NAN]),
        Err(Error::NonFinite { .. })
    ));
}

#[test]
fn dimension_mismatch_is_rejected() {
    let err = PhaseState::<2>::from_slices(0.0, &[1.0, 2.0, 3.0], &[0.0, 0.0]).expect_err("mismatch");
    assert_eq!(
        err,
        Error::DimensionMismatch {
            what: "q".into(),
            expected: 2,
            got: 3
        }
    );
}

#[test]
fn non_positive_step_is_rejected() {
    for h in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        let r = GalerkinIntegrator::new(Pendulum::default().system(), GalerkinScheme::midpoint(), h);
        assert!(matches!(r, Err(Error::InvalidStep { .. })), "h = {h}");
    }
}

#[test]
fn invalid_method_parameters_are_rejected() {
    assert!(
        matches!(GalerkinScheme::new(Method::Alpha(1.5)), Err(Error::InvalidParameter { ref name, .. }) if name == "alpha")
    );
    assert!(
        matches!(GalerkinScheme::new(Method::GalerkinLobatto(1)), Err(Error::InvalidParameter { ref name, .. }) if name == "stages")
    );
    assert!(matches!(
        GalerkinScheme::new(Method::GalerkinGauss(0)),
        Err(Error::InvalidParameter { .. })
    ));
    assert!(matches!(Kepler::new(1.0), Err(Error::InvalidParameter { ref name, .. }) if name == "eccentricity"));
}

/// Parameters that are each fine but whose products overflow or vanish are
/// refused by name, so that `system()` never meets a non-finite or zero
/// inertia.
#[test]
fn pendulum_products_that_overflow_or_vanish_are_rejected() {
    let name_of = |r: veselov::Result<Pendulum>| match r {
        Err(Error::InvalidParameter { name, .. }) => name,
        other => panic!("expected an invalid parameter, got {other:?}"),
    };
    assert_eq!(name_of(Pendulum::new(1.0, 1e300, 9.81)), "mass·length²");
    assert_eq!(name_of(Pendulum::new(1e-300, 1e-20, 1.0)), "mass·length²");
    // Subnormal (1e-320): 1/(m ℓ²) would overflow.
    assert_eq!(name_of(Pendulum::new(1e-300, 1e-10, 1.0)), "mass·length²");
    assert_eq!(name_of(Pendulum::new(1e200, 1e-100, 1e300)), "mass·gravity·length");
    let fine = Pendulum::new(2.0, 1e100, 1e-100).expect("finite products");
    assert!(fine.system().mass_inverse().iter().all(|m| m.is_finite() && *m > 0.0));
    // The system refuses a subnormal mass of its own.
    let tiny = nalgebra::SMatrix::<f64, 1, 1>::new(1e-320);
    assert!(veselov::mechanics::SeparableLagrangian::new(tiny, fine).is_err());
}

/// `L = q v − q²/2` is degenerate: `∂²L/∂v² = 0`.
struct Degenerate;
impl Lagrangian<1> for Degenerate {
    fn lagrangian<D: Scalar>(&self, _t: D, q: &SVector<D, 1>, v: &SVector<D, 1>) -> D {
        q[0] * v[0] - q[0] * q[0] * 0.5
    }
}

#[test]
fn singular_velocity_hessian_is_a_typed_error() {
    let (q, v) = (Vector1::new(0.5), Vector1::new(0.1));
    assert!(matches!(
        acceleration(&Degenerate, 0.0, &q, &v),
        Err(Error::SingularVelocityHessian { .. })
    ));
    assert!(matches!(
        velocity_from_momentum(&Degenerate, 0.0, &q, &v),
        Err(Error::SingularVelocityHessian { .. })
    ));
}

#[test]
fn newton_failure_carries_step_time_and_residual() {
    // Kepler through a near-collision with a huge step: the stage equations have no nearby solution.
    let kepler = Kepler::new(0.9).expect("valid");
    let options = NewtonOptions {
        max_iterations: 4,
        ..NewtonOptions::default()
    };
    let mut map = GalerkinIntegrator::new(
        kepler.system(),
        GalerkinScheme::new(Method::GalerkinGauss(3)).expect("valid"),
        1.0,
    )
    .expect("valid")
    .with_options(options);
    let x0 = PhaseState::new(0.0, Vector2::new(0.1, 0.0), Vector2::new(0.0, 4.3));
    let run = integrate(&mut map, x0, 50, 1);
    match run.failure {
        Some(Error::NewtonFailure {
            step,
            t,
            residual,
            iterations,
            ..
        }) => {
            assert_eq!(t, step as f64);
            assert!(residual > 0.0);
            assert_eq!(iterations, 4);
            // Everything computed before the failure is kept.
            assert_eq!(run.states.len(), step + 1);
        }
        other => panic!("expected a Newton failure, got {other:?}"),
    }
}

/// `L = ½v² + ¼q⁴` (q'' = q³) from q = 1, p = 1 blows up at
/// t* = ∫₁^∞ dq/√(½ + q⁴/2) ≈ 1.31. Past the point where the midpoint
/// equations' continuing root disappears, Newton may find another root far
/// away: the step is refused with a typed error instead, before t*, and
/// everything computed until then is finite.
#[test]
fn a_blow_up_stops_the_run_instead_of_jumping_to_another_root() {
    struct Quartic;
    impl Lagrangian<1> for Quartic {
        fn lagrangian<D: Scalar>(&self, _t: D, q: &SVector<D, 1>, v: &SVector<D, 1>) -> D {
            v[0] * v[0] * 0.5 + q[0] * q[0] * q[0] * q[0] * 0.25
        }
    }
    for method in [Method::Midpoint, Method::GalerkinGauss(2)] {
        let mut map =
            GalerkinIntegrator::new(Quartic, GalerkinScheme::new(method).expect("valid"), 0.01).expect("valid");
        let run = integrate(
            &mut map,
            PhaseState::new(0.0, Vector1::new(1.0), Vector1::new(1.0)),
            500,
            1,
        );
        let t_end = run.states.last().expect("states").t;
        assert!(
            matches!(run.failure, Some(Error::NewtonFailure { .. })),
            "{method:?}: {:?}",
            run.failure
        );
        assert!(t_end < 1.32, "{method:?}: ran to t = {t_end}");
        assert!(run.states.iter().all(|x| x.q[0].is_finite() && x.p[0].is_finite()));
    }
}
