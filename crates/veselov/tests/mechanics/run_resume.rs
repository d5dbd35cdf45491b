//! A run stopped at a checkpoint and continued in a fresh integrator, with
//! the state and the integrator's carry restored from checkpoint words,
//! reproduces the uninterrupted run bit for bit.

use nalgebra::{Matrix3, Vector2, Vector3};
use veselov::lgvi::GroupStepper;
use veselov::lgvi::{GroupState, SplitLieIntegrator};
use veselov::lie::{CayleyMap, Rotations, so3};
use veselov::mechanics::PhaseStepper;
use veselov::mechanics::{GalerkinIntegrator, GalerkinScheme, Method, OneStepMap, PhaseState, SeparableIntegrator};
use veselov::models::{DoublePendulum, FreeRigidBody, Kepler, VanDerPol};
use veselov::run::{Checkpoint, Stepper, StopWhen, Words, drive};

/// Run `total` steps in one go (`whole`), and `split` steps (`first`) then
/// the rest with a fresh stepper (`second`) restored from words; return both
/// final states' words.
fn both<S: Stepper + Checkpoint>(
    [mut whole, mut first, mut second]: [S; 3],
    x0: S::State,
    split: u64,
    total: u64,
) -> (Vec<f64>, Vec<f64>)
where
    S::State: Checkpoint + Clone,
{
    let mut x = x0.clone();
    let whole = drive(&mut whole, &mut x, 0, &StopWhen::steps(total), &mut []);
    assert!(whole.failure().is_none());
    let mut a = Vec::new();
    x.save(&mut a);

    let mut y = x0.clone();
    drive(&mut first, &mut y, 0, &StopWhen::steps(split), &mut []);
    let (mut state_words, mut carry_words) = (Vec::new(), Vec::new());
    y.save(&mut state_words);
    first.save(&mut carry_words);
    let mut z = x0;
    z.restore(&mut Words::new(&state_words)).expect("state");
    let mut w = Words::new(&carry_words);
    second.restore(&mut w).expect("carry");
    w.end().expect("all words read");
    drive(&mut second, &mut z, split, &StopWhen::steps(total), &mut []);
    let mut b = Vec::new();
    z.save(&mut b);
    (a, b)
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// The same map built three times.
fn three<M>(make: impl Fn() -> M) -> [M; 3] {
    [make(), make(), make()]
}

fn phase_case<M: OneStepMap<2>>(maps: &mut [M; 3], x0: PhaseState<2>, split: u64, total: u64) {
    let [a, b, c] = maps;
    let steppers = [
        PhaseStepper::new(a, x0.t),
        PhaseStepper::new(b, x0.t),
        PhaseStepper::new(c, x0.t),
    ];
    let (whole, resumed) = both(steppers, x0, split, total);
    assert_eq!(bits(&whole), bits(&resumed));
}

#[test]
fn separable_and_general_galerkin_resume_bit_for_bit() {
    let kepler = Kepler::new(0.5).expect("kepler");
    let gauss = GalerkinScheme::new(Method::GalerkinGauss(2)).expect("scheme");
    let mut maps = three(|| SeparableIntegrator::new(kepler.system(), gauss.clone(), 0.01).expect("map"));
    phase_case(&mut maps, kepler.initial_state(), 137, 400);

    let vdp = VanDerPol::new(1.0, 0.5, 0.3).expect("van der pol");
    let lobatto = GalerkinScheme::new(Method::GalerkinLobatto(3)).expect("scheme");
    let mut maps =
        three(|| SeparableIntegrator::with_force(vdp.system(), vdp.force(), lobatto.clone(), 0.02).expect("map"));
    phase_case(&mut maps, VanDerPol::initial_state(), 77, 300);

    let pendulum = DoublePendulum::new(1.0, 1.0, 1.0, 1.0, 9.81).expect("double pendulum");
    let mut maps = three(|| GalerkinIntegrator::new(pendulum, lobatto.clone(), 0.01).expect("map"));
    let x0 = PhaseState::new(0.0, Vector2::new(0.5, -0.5), Vector2::zeros());
    phase_case(&mut maps, x0, 51, 200);
}

#[test]
fn lie_group_integrator_resumes_bit_for_bit() {
    let body = FreeRigidBody::new(Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0))).expect("body");
    let x0 = GroupState::<Rotations, 3>::new(
        0.0,
        so3::exp(&Vector3::new(0.3, 0.1, 0.0)),
        Vector3::new(0.05, 2.0, 0.15),
    );
    let [mut a, mut b, mut c] =
        three(|| SplitLieIntegrator::<Rotations, CayleyMap, _, 3>::new(body, 0.01).expect("map"));
    let steppers = [
        GroupStepper::new(&mut a, 0.0),
        GroupStepper::new(&mut b, 0.0),
        GroupStepper::new(&mut c, 0.0),
    ];
    let (whole, resumed) = both(steppers, x0, 333, 1000);
    assert_eq!(bits(&whole), bits(&resumed));
}

/// The variable-step SEM integrator carries its step history and its kept
/// momentum block through a checkpoint: the resumed run takes the same
/// iterations and lands on the same bits; without the carry it would not.
#[test]
fn variable_step_integrator_resumes_bit_for_bit() {
    use veselov::sem::SemStepper;
    use veselov::sem::{SemAction, SemIntegrator, SemRule, SemState};
    let kepler = Kepler::new(0.5).expect("valid");
    let x0 = kepler.initial_state();
    let make = || SemIntegrator::new(SemAction::new(kepler.system(), SemRule::Midpoint).expect("valid"));
    let (_, s1): (SemState<2>, SemState<2>) = make().start(0.0, x0.q, x0.p, 0.01).expect("start");
    let [mut a, mut b, mut c] = three(make);
    let steppers = [
        SemStepper::new(&mut a, None),
        SemStepper::new(&mut b, None),
        SemStepper::new(&mut c, None),
    ];
    let (whole, resumed) = both(steppers, s1, 333, 1000);
    assert_eq!(bits(&whole), bits(&resumed));
    // Without the carry the resumed run restarts its predictor: it solves to
    // round-off all the same, but not to the same bits.
    let [mut a, mut b] = [make(), make()];
    let mut x = s1;
    drive(
        &mut SemStepper::new(&mut a, None),
        &mut x,
        0,
        &StopWhen::steps(1000),
        &mut [],
    );
    let mut y = s1;
    drive(
        &mut SemStepper::new(&mut b, None),
        &mut y,
        0,
        &StopWhen::steps(333),
        &mut [],
    );
    let mut fresh = make();
    drive(
        &mut SemStepper::new(&mut fresh, None),
        &mut y,
        333,
        &StopWhen::steps(1000),
        &mut [],
    );
    let (mut u, mut v) = (Vec::new(), Vec::new());
    x.save(&mut u);
    y.save(&mut v);
    assert_ne!(bits(&u), bits(&v), "the carry made no difference");
    assert!(u.iter().zip(&v).all(|(p, q)| (p - q).abs() < 1e-9), "{u:?} {v:?}");
}
