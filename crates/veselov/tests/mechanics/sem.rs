//! Variable time-step symplectic-energy-momentum integrators (seed 001).

use nalgebra::{SVector, Vector1, Vector2};
use veselov::Error;
use veselov::diagnostics::{fit_order, symplecticity_defect};
use veselov::mechanics::{PhaseState, momentum_map};
use veselov::models::{HarmonicOscillator, Kepler, Pendulum};
use veselov::sem::{SemAction, SemIntegrator, SemRule, SemState, run_sem, solve_lee_bvp};

fn rel_energy_spread<const N: usize>(states: &[SemState<N>]) -> f64 {
    let e = states[1].energy;
    states[1..].iter().fold(0.0_f64, |m, s| m.max((s.energy - e).abs())) / e.abs()
}

/// Pendulum, midpoint rule, 10⁴ steps: the discrete energy is conserved to
/// round-off, every step is positive, and the two-step equations (3.3)–(3.4)
/// hold along the trajectory.
#[test]
fn pendulum_midpoint_conserves_discrete_energy() {
    let pendulum = Pendulum::default();
    let action = SemAction::new(pendulum.system(), SemRule::Midpoint).expect("valid");
    let mut sem = SemIntegrator::new(action.clone());
    let run = run_sem(
        &mut sem,
        0.0,
        Vector1::new(1.0),
        Vector1::new(0.5),
        0.05,
        f64::INFINITY,
        10_000,
        false,
    );
    assert!(run.failure.is_none(), "{:?}", run.failure);
    assert_eq!(run.states.len(), 10_001);
    let spread = rel_energy_spread(&run.states);
    assert!(spread <= 1e-12, "relative discrete-energy spread {spread:e}");
    assert!(run.states.windows(2).all(|w| w[1].t > w[0].t));
    // Two-step form: D_{x1}S(x_{k−1}, x_k) + D_{x0}S(x_k, x_{k+1}) = 0.
    for w in run.states.windows(3).take(2000) {
        let a = action.derivatives(w[0].t, &w[0].q, &w[1].q, w[1].t - w[0].t);
        let b = action.derivatives(w[1].t, &w[1].q, &w[2].q, w[2].t - w[1].t);
        let r_q = a.q1 + b.q0;
        let r_t = a.h + b.t0 - b.h;
        // Round-off bound: the step Jacobian has entries ~1/h (note 001 §3.4), so
        // residuals of a converged solve are a few ε/h ≈ 4e-15/h.
        let bound = 100.0 * f64::EPSILON / (w[1].t - w[0].t);
        assert!(
            r_q.amax() < bound && r_t.abs() < bound,
            "two-step residuals {:e}, {r_t:e} > {bound:e}",
            r_q.amax()
        );
    }
}

/// Kepler e = 0.5 with the Gauss-2 averaged Lagrangian: discrete energy and
/// angular momentum conserved to round-off over 10⁴ steps.
#[test]
fn kepler_averaged_conserves_energy_and_angular_momentum() {
    let kepler = Kepler::new(0.5).expect("valid");
    let x0 = kepler.initial_state();
    let action = SemAction::new(kepler.system(), SemRule::Averaged(2)).expect("valid");
    let mut sem = SemIntegrator::new(action);
    let run = run_sem(&mut sem, 0.0, x0.q, x0.p, 0.01, f64::INFINITY, 10_000, false);
    assert!(run.failure.is_none(), "{:?}", run.failure);
    assert!(
        rel_energy_spread(&run.states) <= 1e-12,
        "{:e}",
        rel_energy_spread(&run.states)
    );
    let sym = Kepler::angular_symmetry();
    let j0 = momentum_map(&sym, &x0.q, &x0.p);
    let drift = run
        .states
        .iter()
        .fold(0.0_f64, |m, s| m.max((momentum_map(&sym, &s.q, &s.p) - j0).abs()))
        / j0;
    assert!(drift <= 1e-12, "angular momentum drift {drift:e}");
    assert!(run.states.iter().all(|s| s.h > 0.0));
}

/// Second order at the computed times against the exact pendulum, and the
/// normalised step profile `h_k/h₀` converges as `h₀ → 0`.
#[test]
fn midpoint_sem_is_second_order_and_step_profile_converges() {
    let pendulum = Pendulum::default();
    let x0 = PhaseState::new(0.0, Vector1::new(1.0), Vector1::new(0.5));
    let t_end = 5.0;
    let mut hs = Vec::new();
    let mut errs = Vec::new();
    let mut profiles: Vec<Vec<f64>> = Vec::new();
    for h0 in [0.1, 0.05, 0.025, 0.0125, 0.00625] {
        let mut sem = SemIntegrator::new(SemAction::new(pendulum.system(), SemRule::Midpoint).expect("valid"));
        let run = run_sem(&mut sem, 0.0, x0.q, x0.p, h0, t_end, 1_000_000, false);
        assert!(run.failure.is_none());
        let last = run.states[run.states.len() - 1];
        let exact = pendulum.exact(&x0, last.t).expect("exact");
        hs.push(h0);
        errs.push((last.q - exact.q).amax().max((last.p - exact.p).amax()));
        // h_k/h₀ attached to step midpoints, interpolated linearly at τ = 1, 2, 3, 4.
        let mids: Vec<(f64, f64)> = run
            .states
            .windows(2)
            .map(|w| (0.5 * (w[0].t + w[1].t), w[1].h / h0))
            .collect();
        profiles.push(
            [1.0, 2.0, 3.0, 4.0]
                .iter()
                .map(|&tau| {
                    let k = mids.iter().position(|m| m.0 >= tau).expect("reached");
                    let (a, b) = (mids[k - 1], mids[k]);
                    a.1 + (b.1 - a.1) * (tau - a.0) / (b.0 - a.0)
                })
                .collect(),
        );
    }
    let fit = fit_order(&hs, &errs, 1e-13).expect("fit");
    assert!((fit.order - 2.0).abs() <= 0.2, "order {:.3}: {errs:?}", fit.order);
    let diffs: Vec<f64> = profiles
        .windows(2)
        .map(|w| w[0].iter().zip(&w[1]).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs())))
        .collect();
    for d in diffs.windows(2) {
        assert!(d[1] < 0.6 * d[0], "profile differences do not shrink: {diffs:?}");
    }
}

/// The reduced map at fixed E is symplectic (exact Jacobian); recomputing E
/// from the perturbed initial state (negative control) breaks it.
#[test]
fn reduced_map_is_symplectic_and_energy_recomputation_is_not() {
    let kepler = Kepler::new(0.3).expect("valid");
    let x0 = kepler.initial_state();
    let mut sem = SemIntegrator::new(SemAction::new(kepler.system(), SemRule::Midpoint).expect("valid"));
    let (_, s1) = sem.start(0.0, x0.q, x0.p, 0.02).expect("start");
    let mut s = s1;
    for k in 0..50 {
        let (next, jac) = sem.reduced_jacobian(&s).expect("step");
        let d = symplecticity_defect(&jac);
        assert!(d <= 1e-10, "step {k}: defect {d:e}");
        s = next;
    }
    // Negative control (pendulum, 1-D): (q₀, p₀) ↦ (q₂, p₂) with E recomputed
    // from each initial state; det J differs from 1 by far more than the
    // finite-difference error (~1e-8).
    let pendulum = Pendulum::default();
    let sem = SemIntegrator::new(SemAction::new(pendulum.system(), SemRule::Midpoint).expect("valid"));
    let map = |q: f64, p: f64| {
        let mut sem = sem.clone();
        let (_, s1) = sem.start(0.0, Vector1::new(q), Vector1::new(p), 0.1).expect("start");
        let (s2, _) = sem.step(1, &s1).expect("step");
        (s2.q[0], s2.p[0])
    };
    let eps = 1e-6;
    let (a, b) = (map(1.0 + eps, 0.5), map(1.0 - eps, 0.5));
    let (c, d) = (map(1.0, 0.5 + eps), map(1.0, 0.5 - eps));
    let j = [
        [(a.0 - b.0) / (2.0 * eps), (c.0 - d.0) / (2.0 * eps)],
        [(a.1 - b.1) / (2.0 * eps), (c.1 - d.1) / (2.0 * eps)],
    ];
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    assert!((det - 1.0).abs() > 1e-4, "det {det}");
}

/// Where the left-point rule (3.18) must produce `NegativeStep`. For
/// `L = ½v² − V(q)` its step from `(q, p)` at the fixed energy `E` solves
/// `½(p − h g)² + V(q) − E = 0`, `g = V′(q)`: a quadratic in `h` with roots
/// `h± = [pg ± √(p²g² + 2g²δ)]/g²`, `δ = E − H(q, p) = V(q_prev) − V(q)`.
/// If the last step ended higher than it started (`δ < 0`) while the momentum
/// now points downhill (`pg < 0`), both roots are negative: there is no
/// forward step. A circulating pendulum does exactly that when a step
/// straddles the top θ = π and lands nearer to it than it left. (The note's
/// oscillator scenario cannot: on V = ½q² a step that ends higher points
/// uphill, so the rule fails there only at a turning point, with no root at
/// all; see `degenerate_cases_are_typed_errors`.)
#[test]
fn left_point_step_is_negative_past_the_top_of_a_circulating_pendulum() {
    let pendulum = Pendulum::new(1.0, 1.0, 1.0).expect("valid");
    let mut sem = SemIntegrator::new(SemAction::new(pendulum.system(), SemRule::LeftPoint).expect("valid"));
    let run = run_sem(
        &mut sem,
        0.0,
        Vector1::new(0.0),
        Vector1::new(3.0),
        0.003,
        50.0,
        1_000_000,
        false,
    );
    let Some(Error::NegativeStep { h, .. }) = run.failure else {
        panic!("expected NegativeStep, got {:?}", run.failure);
    };
    let n = run.states.len();
    let (before, at) = (&run.states[n - 2], &run.states[n - 1]);
    let v = |q: f64| -q.cos();
    let (q, p, g) = (at.q[0], at.p[0], at.q[0].sin());
    let delta = v(before.q[0]) - v(q);
    println!(
        "q {} → {q}, p = {p}, δ = {delta:e}, pg = {:e}, reported h = {h:e}",
        before.q[0],
        p * g
    );
    assert!(
        (before.q[0] - std::f64::consts::PI) * (q - std::f64::consts::PI) < 0.0,
        "the step straddles the top"
    );
    assert!(delta < 0.0 && p * g < 0.0, "δ = {delta:e}, pg = {:e}", p * g);
    // δ is also E − H(q, p), with E the energy every step has kept.
    assert!((at.energy - 0.5 * p * p - v(q) - delta).abs() < 1e-12);
    let spread = run.states[1..]
        .iter()
        .map(|s| (s.energy - at.energy).abs())
        .fold(0.0, f64::max);
    // Each step's energy equation is solved to ~1e-13; over these 5747
    // steps the energy moved by 8e-11.
    assert!(spread < 1e-9 * at.energy.abs(), "energy spread {spread:e}");
    let root = (p * p * g * g + 2.0 * g * g * delta).sqrt();
    let (near, far) = ((p * g + root) / (g * g), (p * g - root) / (g * g));
    assert!(near < 0.0 && far < near, "roots {near:e}, {far:e}");
    // The reported step is the bracketed sign change of the backward scan:
    // the near root, to within the scan's spacing.
    assert!(
        h < 0.0 && (h - near).abs() < 0.5 * near.abs(),
        "h = {h:e}, near root {near:e}"
    );
    // Every state before it was a forward step.
    assert!(run.states.windows(2).all(|w| w[1].t > w[0].t));
}

/// Degenerate cases give the typed errors, not garbage.
#[test]
fn degenerate_cases_are_typed_errors() {
    let osc = HarmonicOscillator::new(1.0, 1.0).expect("valid");
    let run_osc = |rule: SemRule, q: f64, p: f64| {
        let mut sem = SemIntegrator::new(SemAction::new(osc.system(), rule).expect("valid"));
        run_sem(
            &mut sem,
            0.0,
            Vector1::new(q),
            Vector1::new(p),
            0.01,
            20.0,
            100_000,
            false,
        )
    };
    // (3.18) at the first turning point of the oscillator.
    let run = run_osc(SemRule::LeftPoint, 1.0, 0.5);
    assert!(
        matches!(
            run.failure,
            Some(Error::NoStepRoot { .. } | Error::DegenerateStep { .. } | Error::NegativeStep { .. })
        ),
        "{:?}",
        run.failure
    );
    let t_fail = run.states[run.states.len() - 1].t;
    assert!(t_fail < 2.0 * std::f64::consts::PI, "left point ran until {t_fail}");
    // Trapezoid on the oscillator fails within one period.
    let run = run_osc(SemRule::Trapezoid, 1.0, 0.5);
    assert!(
        matches!(
            run.failure,
            Some(Error::NoStepRoot { .. } | Error::DegenerateStep { .. })
        ),
        "{:?}",
        run.failure
    );
    // Midpoint on Kepler with e = 0.9 (> e* = √(5/8)) fails within the first orbit; e = 0.5 completes.
    for (e, fails) in [(0.9, true), (0.5, false)] {
        let kepler = Kepler::new(e).expect("valid");
        let x0 = kepler.initial_state();
        let mut sem = SemIntegrator::new(SemAction::new(kepler.system(), SemRule::Midpoint).expect("valid"));
        let run = run_sem(
            &mut sem,
            0.0,
            x0.q,
            x0.p,
            0.002,
            2.0 * std::f64::consts::PI,
            1_000_000,
            false,
        );
        assert_eq!(run.failure.is_some(), fails, "e = {e}: {:?}", run.failure);
        assert!(run.states.iter().all(|s| s.h > 0.0));
    }
    // The opt-in fallback lets the trapezoid run continue, flagging the steps.
    let mut sem = veselov::sem::SemIntegrator::with_options(
        SemAction::new(osc.system(), SemRule::Trapezoid).expect("valid"),
        veselov::sem::SemOptions {
            fallback: true,
            ..Default::default()
        },
    );
    let run = run_sem(
        &mut sem,
        0.0,
        Vector1::new(1.0),
        Vector1::new(0.5),
        0.01,
        10.0,
        100_000,
        false,
    );
    assert!(run.failure.is_none(), "{:?}", run.failure);
    assert!(!run.flagged_steps.is_empty());
}

/// The pendulum's midpoint SEM action and the points `(t_k, q_k)` of a
/// `steps`-step initial-value run from `q = 1, p = 0.5` with `h₀ = 0.1`.
pub(super) fn pendulum_ivp(
    steps: usize,
) -> (
    SemAction<impl veselov::mechanics::Lagrangian<1> + Clone, 1>,
    Vec<(f64, SVector<f64, 1>)>,
) {
    let action = SemAction::new(Pendulum::default().system(), SemRule::Midpoint).expect("valid");
    let mut sem = SemIntegrator::new(action.clone());
    let run = run_sem(
        &mut sem,
        0.0,
        Vector1::new(1.0),
        Vector1::new(0.5),
        0.1,
        f64::INFINITY,
        steps,
        false,
    );
    assert!(run.failure.is_none());
    let points = run.states.iter().map(|s| (s.t, s.q)).collect();
    (action, points)
}

/// Lee's boundary-value form reproduces an initial-value run, with increasing times.
#[test]
fn lee_bvp_reproduces_an_initial_value_run() {
    let (action, ivp) = pendulum_ivp(20);
    // Guess: uniform times between the endpoints, IVP positions.
    let k = ivp.len() - 1;
    let (t0, t1) = (ivp[0].0, ivp[k].0);
    let guess: Vec<(f64, SVector<f64, 1>)> = ivp
        .iter()
        .enumerate()
        .map(|(i, (_, q))| (t0 + (t1 - t0) * i as f64 / k as f64, *q))
        .collect();
    let sol = solve_lee_bvp(&action, &guess, 50).expect("converges");
    for ((ts, qs), (ti, qi)) in sol.iter().zip(&ivp) {
        assert!(
            (ts - ti).abs() < 1e-10 && (qs - qi).amax() < 1e-10,
            "{ts} {qs:?} vs {ti} {qi:?}"
        );
    }
    assert!(sol.windows(2).all(|w| w[1].0 > w[0].0));
    let _ = Vector2::<f64>::zeros();
}

/// The left-point rule (3.18) is first order where it has no turning point:
/// the circular Kepler orbit, errors against the exact orbit at the time
/// each run ends (t ≥ 3), steps 0.02 … 0.0025.
#[test]
fn left_point_rule_is_first_order_on_the_circular_orbit() {
    let kepler = Kepler::new(0.0).expect("valid");
    let x0 = kepler.initial_state();
    let steps = [0.02, 0.01, 0.005, 0.0025];
    let errors: Vec<f64> = steps
        .iter()
        .map(|&dt| {
            let mut sem = SemIntegrator::new(SemAction::new(kepler.system(), SemRule::LeftPoint).expect("valid"));
            let run = run_sem(&mut sem, 0.0, x0.q, x0.p, dt, 3.0, 1_000_000, false);
            assert!(run.failure.is_none(), "dt = {dt}: {:?}", run.failure);
            let s = &run.states[run.states.len() - 1];
            let (q, _) = veselov::special::kepler_exact(0.0, s.t).expect("exact orbit");
            ((s.q[0] - q[0]).powi(2) + (s.q[1] - q[1]).powi(2)).sqrt()
        })
        .collect();
    let fit = fit_order(&steps, &errors, 1e-12).expect("fit");
    println!("left point, circular orbit: errors {errors:?}, order {:.3}", fit.order);
    assert!((fit.order - 1.0).abs() < 0.1, "order {:.3}", fit.order);
}

/// The midpoint rule's fixed-energy step has an admissible root along the
/// whole Kepler orbit only below e* = √(5/8) ≈ 0.7906 (note 001): probed on
/// both sides, at three steps each.
#[test]
fn midpoint_kepler_threshold_is_probed_on_both_sides() {
    for (e, fails) in [(0.78, false), (0.80, true)] {
        let kepler = Kepler::new(e).expect("valid");
        let x0 = kepler.initial_state();
        for dt in [0.004, 0.002, 0.001] {
            let mut sem = SemIntegrator::new(SemAction::new(kepler.system(), SemRule::Midpoint).expect("valid"));
            let run = run_sem(
                &mut sem,
                0.0,
                x0.q,
                x0.p,
                dt,
                2.0 * std::f64::consts::PI,
                10_000_000,
                false,
            );
            match (&run.failure, fails) {
                (None, false) => {}
                (Some(Error::NoStepRoot { .. } | Error::DegenerateStep { .. }), true) => {}
                (f, _) => panic!("e = {e}, dt = {dt}: {f:?}"),
            }
        }
    }
}
