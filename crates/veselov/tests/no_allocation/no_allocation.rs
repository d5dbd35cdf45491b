//! Fixed-size systems allocate nothing inside a step: a counting global
//! allocator watches the steps of every method on both paths.

use std::sync::atomic::Ordering;

use veselov::mechanics::{GalerkinIntegrator, GalerkinScheme, Method, OneStepMap, SeparableIntegrator};
use veselov::models::{DoublePendulum, Kepler};

use crate::counting_alloc;
use counting_alloc::{ALLOCATIONS, WATCHED};

fn allocations_in_steps<M: OneStepMap<2>>(map: &mut M, x0: veselov::mechanics::PhaseState<2>) -> usize {
    let mut x = map.step(0, &x0).expect("first step").0; // warm-up
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    WATCHED.with(|w| w.set(true));
    for k in 1..200 {
        x = map.step(k, &x).expect("step").0;
    }
    WATCHED.with(|w| w.set(false));
    ALLOCATIONS.load(Ordering::SeqCst) - before
}

#[test]
fn steps_do_not_allocate() {
    let kepler = Kepler::new(0.6).expect("valid");
    let h = 2.0 * std::f64::consts::PI / 1000.0;
    let methods = [
        Method::Midpoint,
        Method::Trapezoid,
        Method::GalerkinLobatto(3),
        Method::GalerkinGauss(2),
        Method::GalerkinGauss(4),
    ];
    for m in methods {
        let scheme = || GalerkinScheme::new(m).expect("valid");
        let mut general = GalerkinIntegrator::new(kepler.system(), scheme(), h).expect("valid");
        assert_eq!(
            allocations_in_steps(&mut general, kepler.initial_state()),
            0,
            "{m:?} general path"
        );
        let mut fast = SeparableIntegrator::new(kepler.system(), scheme(), h).expect("valid");
        assert_eq!(
            allocations_in_steps(&mut fast, kepler.initial_state()),
            0,
            "{m:?} separable path"
        );
        let mut dp = GalerkinIntegrator::new(DoublePendulum::default(), scheme(), 0.01).expect("valid");
        let x0 =
            veselov::mechanics::PhaseState::new(0.0, nalgebra::Vector2::new(0.5, -0.5), nalgebra::Vector2::zeros());
        assert_eq!(allocations_in_steps(&mut dp, x0), 0, "{m:?} double pendulum");
    }
}

struct DynOscillators;
impl veselov::mechanics::DynLagrangian for DynOscillators {
    fn dim(&self) -> usize {
        5
    }
    fn lagrangian<D: veselov::ad::Scalar>(&self, _t: D, q: &[D], v: &[D]) -> D {
        q.iter()
            .zip(v)
            .fold(D::from(0.0), |s, (q, v)| s + (*v * *v - q.sin() * *q) * 0.5)
    }
}

#[test]
fn run_time_dimension_steps_do_not_allocate_either() {
    let scheme = GalerkinScheme::new(Method::GalerkinLobatto(3)).expect("valid");
    let mut map = veselov::mechanics::DynGalerkinIntegrator::new(DynOscillators, scheme, 0.05).expect("valid");
    let mut x = veselov::mechanics::DynState {
        t: 0.0,
        q: vec![0.3; 5],
        p: vec![0.1; 5],
    };
    map.step(0, &mut x).expect("warm-up");
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    WATCHED.with(|w| w.set(true));
    for k in 1..50 {
        map.step(k, &mut x).expect("step");
    }
    WATCHED.with(|w| w.set(false));
    assert_eq!(ALLOCATIONS.load(Ordering::SeqCst) - before, 0);
}

#[test]
fn lie_group_steps_do_not_allocate() {
    use veselov::lgvi::{GroupState, GroupStepMap, LieGroupIntegrator, SplitLieIntegrator};
    use veselov::lie::{CayleyMap, ExpMap, RigidMotions, Rotations, SE3, so3};
    use veselov::models::{FreeRigidBodySE3, HeavyTop};
    fn count<G: veselov::lie::GroupFamily<N>, const N: usize>(
        map: &mut impl GroupStepMap<G, N>,
        x0: GroupState<G, N>,
    ) -> usize {
        let mut x = map.step(0, &x0).expect("warm-up").0;
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        WATCHED.with(|w| w.set(true));
        for k in 1..100 {
            x = map.step(k, &x).expect("step").0;
        }
        WATCHED.with(|w| w.set(false));
        ALLOCATIONS.load(Ordering::SeqCst) - before
    }
    let inertia = nalgebra::Matrix3::new(2.0, 0.1, 0.0, 0.1, 3.0, 0.0, 0.0, 0.0, 4.0);
    let top = HeavyTop::new(inertia, 1.0, nalgebra::Vector3::new(0.0, 0.0, 0.5), 9.81).expect("valid");
    let x0 = GroupState::<Rotations, 3>::new(
        0.0,
        so3::exp(&nalgebra::Vector3::new(0.2, 0.1, 0.0)),
        nalgebra::Vector3::new(1.0, 2.0, 3.0),
    );
    let mut fast = SplitLieIntegrator::<Rotations, CayleyMap, _, 3>::new(top, 0.01).expect("valid");
    assert_eq!(count(&mut fast, x0), 0, "heavy top, split path");
    let mut general = LieGroupIntegrator::<Rotations, ExpMap, _, 3>::new(top, 0.01).expect("valid");
    assert_eq!(count(&mut general, x0), 0, "heavy top, general path");
    let body = FreeRigidBodySE3::new(inertia, 2.0).expect("valid");
    let y0 = GroupState::<RigidMotions, 6>::new(
        0.0,
        SE3::identity(),
        nalgebra::Vector6::new(1.0, 2.0, 3.0, 0.5, 0.0, -0.5),
    );
    let mut se3 = SplitLieIntegrator::<RigidMotions, CayleyMap, _, 6>::new(body, 0.01).expect("valid");
    assert_eq!(count(&mut se3, y0), 0, "SE(3) free flight");
}

/// The variable-step SEM step allocates nothing either, on its continuing
/// path and on a restart (momentum-equation start), for both rules the
/// benchmarks time.
#[test]
fn variable_steps_do_not_allocate() {
    use veselov::sem::{SemAction, SemIntegrator, SemRule};
    let kepler = Kepler::new(0.5).expect("valid");
    let x0 = kepler.initial_state();
    for rule in [SemRule::Midpoint, SemRule::Averaged(2)] {
        let mut sem = SemIntegrator::new(SemAction::new(kepler.system(), rule).expect("valid"));
        let (_, s1) = sem.start(0.0, x0.q, x0.p, 0.01).expect("start");
        let mut s = sem.step(1, &s1).expect("warm-up").0;
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        WATCHED.with(|w| w.set(true));
        for k in 2..200 {
            s = sem.step(k, &s).expect("step").0;
        }
        let restarted = sem.step(1, &s1).expect("restart");
        WATCHED.with(|w| w.set(false));
        assert!(restarted.0.h > 0.0);
        assert_eq!(ALLOCATIONS.load(Ordering::SeqCst) - before, 0, "{rule:?}");
    }
}
