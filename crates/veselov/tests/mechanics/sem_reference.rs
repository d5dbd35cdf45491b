//! The variable-step SEM step held against stored reference trajectories
//! (`tests/data/sem_reference/`, computed by the earlier exact-Newton step):
//! from every stored state, one step must land on the next stored state to
//! 1e-13 (plus the round-off floor of the ill-conditioned step `h`, see
//! `step_floor`), whether the step starts a new trajectory or continues the
//! integrator's own last step.

use nalgebra::{DMatrix, SVector};
use veselov::ad::Scalar;
use veselov::mechanics::{Lagrangian, Potential, SeparableLagrangian};
use veselov::models::{DoublePendulum, Kepler, Pendulum};
use veselov::sem::{SemAction, SemIntegrator, SemRule, SemState};

/// `L = ½v² − ½(1 + 0.3 sin t)q²`: time-dependent, so `E⁻ ≠ −∂S/∂h`.
#[derive(Debug, Clone)]
struct DrivenOscillator;

impl Lagrangian<1> for DrivenOscillator {
    fn lagrangian<D: Scalar>(&self, t: D, q: &SVector<D, 1>, v: &SVector<D, 1>) -> D {
        let k = D::from(1.0) + t.sin() * D::from(0.3);
        v[0] * v[0] * D::from(0.5) - k * q[0] * q[0] * D::from(0.5)
    }
}

/// The same oscillator declared as `½v² − V(t, q)`: the step's closed forms in `V`.
#[derive(Debug, Clone, Copy)]
struct DrivenPotential;

impl Potential<1> for DrivenPotential {
    fn potential<D: Scalar>(&self, t: D, q: &SVector<D, 1>) -> D {
        (D::from(1.0) + t.sin() * D::from(0.3)) * q[0] * q[0] * D::from(0.5)
    }
}

fn reference<const N: usize>(name: &str) -> Vec<SemState<N>> {
    let path = format!("{}/tests/data/sem_reference/{name}.csv", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    text.lines()
        .map(|line| {
            let x: Vec<f64> = line.split(',').map(|w| w.parse().expect("number")).collect();
            assert_eq!(x.len(), 2 * N + 3, "{path}: row width");
            SemState {
                t: x[0],
                q: SVector::from_column_slice(&x[1..=N]),
                p: SVector::from_column_slice(&x[N + 1..=2 * N]),
                energy: x[2 * N + 1],
                h: x[2 * N + 2],
            }
        })
        .collect()
}

/// How far `h` may move within the round-off of the energy equation: an
/// error `8ε·max(|E|, |S/h|)` of its residual (the size of the energy terms)
/// carried into `h` by `(J⁻¹)_{hh}` of the step Jacobian at `(q₁, h)`. The
/// energy equation is ill-conditioned (`∂E_d/∂h ≈ 2c·h` along the momentum
/// equation, note 001 §3.4), so this floor can exceed 1e-13 where `c` is small.
fn step_floor<L: Lagrangian<N>, const N: usize>(action: &SemAction<L, N>, from: &SemState<N>, to: &SemState<N>) -> f64 {
    let h = to.t - from.t;
    // Rows R₁ = p + ∂S/∂q₀, R₂ = E⁻ − E; columns q₁, h.
    let d = action.derivatives(from.t, &from.q, &to.q, h);
    let mut m = DMatrix::<f64>::zeros(N + 1, N + 1);
    for a in 0..N {
        for b in 0..N {
            m[(a, b)] = d.q0q1[(a, b)];
        }
        m[(a, N)] = d.q0h[a];
        m[(N, a)] = d.q1t0[a] - d.q1h[a];
    }
    m[(N, N)] = d.t0h - d.hh;
    let inverse = m.try_inverse().expect("regular step Jacobian");
    8.0 * f64::EPSILON * to.energy.abs().max((d.value / h).abs()) * inverse[(N, N)].abs()
}

/// Whether `got` is within 1e-13 (relative to `max(1, |x|)`) of `want`, plus
/// the motion along the trajectory that an error `dh` of the step causes
/// (`dh` in `t` and `h`, `dh·(Δq/h, Δp/h)` in `q` and `p`; none in `E`).
/// Returns the worst excess ratio (≤ 1 passes).
fn deviation<const N: usize>(got: &SemState<N>, want: &SemState<N>, from: &SemState<N>, dh: f64) -> f64 {
    let h = want.t - from.t;
    let ratio = |x: f64, y: f64, rate: f64| (x - y).abs() / (1e-13 * y.abs().max(1.0) + rate.abs() * dh);
    let mut m = ratio(got.t, want.t, 1.0)
        .max(ratio(got.h, want.h, 1.0))
        .max(ratio(got.energy, want.energy, 0.0));
    for i in 0..N {
        m = m.max(ratio(got.q[i], want.q[i], (want.q[i] - from.q[i]) / h));
        m = m.max(ratio(got.p[i], want.p[i], (want.p[i] - from.p[i]) / h));
    }
    m
}

/// Largest difference over `t, q, p, E, h`, each relative to `max(1, |x|)`.
fn distance<const N: usize>(a: &SemState<N>, b: &SemState<N>) -> f64 {
    let d = |x: f64, y: f64| (x - y).abs() / y.abs().max(1.0);
    let mut m = d(a.t, b.t).max(d(a.energy, b.energy)).max(d(a.h, b.h));
    for i in 0..N {
        m = m.max(d(a.q[i], b.q[i])).max(d(a.p[i], b.p[i]));
    }
    m
}

/// One step from every stored state, by a fresh integrator (a new
/// trajectory) and by one integrator stepping from the state it just
/// produced when that state is the stored one to the bit (else as new).
fn check<L: Lagrangian<N> + Clone, const N: usize>(name: &str, lagrangian: L, rule: SemRule) {
    let states = reference::<N>(name);
    let action = SemAction::new(lagrangian, rule).expect("valid");
    let mut continued = SemIntegrator::new(action.clone());
    let (mut worst, mut excess, mut floored, mut iterations) = (0.0_f64, 0.0_f64, 0, 0);
    let (mut cont_iterations, mut cont_jacobians) = (0, 0);
    for k in 0..states.len() - 1 {
        let floor = step_floor(&action, &states[k], &states[k + 1]);
        floored += usize::from(floor > 1e-13);
        let mut fresh = SemIntegrator::new(action.clone());
        let (next, info) = fresh.step(k + 1, &states[k]).expect("step of a new trajectory");
        iterations += info.iterations;
        worst = worst.max(distance(&next, &states[k + 1]));
        excess = excess.max(deviation(&next, &states[k + 1], &states[k], floor));
        continued.seed_history(&states[k.saturating_sub(2)..=k]);
        let (next, info) = continued.step(k + 1, &states[k]).expect("continuing step");
        if k >= 2 {
            cont_iterations += info.iterations;
            cont_jacobians += info.jacobian_refreshes + info.jacobian_updates;
        }
        worst = worst.max(distance(&next, &states[k + 1]));
        excess = excess.max(deviation(&next, &states[k + 1], &states[k], floor));
    }
    eprintln!(
        "{name}: worst one-step deviation {worst:.1e}; h round-off floor above 1e-13 on {floored} of {} steps; \
         worst deviation / bound {excess:.2}; {:.2} iterations per new step, {:.2} iterations and {:.2} Jacobians \
         (whole or updated) per continued step",
        states.len() - 1,
        iterations as f64 / (states.len() - 1) as f64,
        cont_iterations as f64 / (states.len() - 3) as f64,
        cont_jacobians as f64 / (states.len() - 3) as f64
    );
    assert!(excess <= 1.0, "{name}: a step deviates by {excess:.2} times its bound");
}

#[test]
fn pendulum_midpoint_matches_reference() {
    check("pendulum_midpoint", Pendulum::default().system(), SemRule::Midpoint);
}

#[test]
fn kepler_midpoint_matches_reference() {
    check(
        "kepler_midpoint",
        Kepler::new(0.5).expect("valid").system(),
        SemRule::Midpoint,
    );
}

#[test]
fn kepler_averaged_matches_reference() {
    check(
        "kepler_averaged2",
        Kepler::new(0.5).expect("valid").system(),
        SemRule::Averaged(2),
    );
}

#[test]
fn kepler_trapezoid_matches_reference() {
    check(
        "kepler_circular_trapezoid",
        Kepler::new(0.0).expect("valid").system(),
        SemRule::Trapezoid,
    );
}

#[test]
fn kepler_left_point_matches_reference() {
    check(
        "kepler_circular_leftpoint",
        Kepler::new(0.0).expect("valid").system(),
        SemRule::LeftPoint,
    );
}

#[test]
fn double_pendulum_matches_reference() {
    check::<_, 2>("double_pendulum_midpoint", DoublePendulum::default(), SemRule::Midpoint);
}

#[test]
fn time_dependent_lagrangian_matches_reference() {
    check::<_, 1>("driven_oscillator_midpoint", DrivenOscillator, SemRule::Midpoint);
    let declared = SeparableLagrangian::unit_mass(DrivenPotential);
    assert!(declared.constant_mass().is_some());
    check::<_, 1>("driven_oscillator_midpoint", declared, SemRule::Midpoint);
}

/// A free run on the new path stays on the stored trajectory: deviations add
/// up over the steps without growing beyond 1e-13 per step.
#[test]
fn free_run_follows_reference() {
    let states = reference::<2>("kepler_midpoint");
    let kepler = Kepler::new(0.5).expect("valid");
    let mut sem = SemIntegrator::new(SemAction::new(kepler.system(), SemRule::Midpoint).expect("valid"));
    let mut s = states[0];
    for (k, want) in states.iter().enumerate().skip(1) {
        s = sem.step(k, &s).expect("step").0;
        let dev = distance(&s, want);
        assert!(dev <= 1e-13 * k as f64, "step {k}: {dev:e}");
    }
}
