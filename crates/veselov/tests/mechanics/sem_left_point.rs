//! What the paper's left-point rule (seed 001 (3.18)) can and cannot do
//! (note 001 §3.3): started at a turning point its steps run away at a rate
//! fixed by the orbit, whatever the first step; started away from one it is
//! first order up to the next turning point; the degenerate start is
//! measurable before the run; and where two roots of the energy equation
//! lie near the last step, the run continues its step sequence.

use nalgebra::Vector2;
use veselov::diagnostics::fit_order;
use veselov::mechanics::{Lagrangian, PhaseState};
use veselov::models::Kepler;
use veselov::sem::{SemAction, SemIntegrator, SemRule, SemState, run_sem};
use veselov::special::kepler_exact;

/// The left-point integrator of the Kepler problem of eccentricity `e`.
fn left_point(e: f64) -> SemIntegrator<impl Lagrangian<2> + Clone, 2> {
    let kepler = Kepler::new(e).expect("valid");
    SemIntegrator::new(SemAction::new(kepler.system(), SemRule::LeftPoint).expect("valid"))
}

/// The pericentre start of the Kepler orbit of eccentricity `e` (t = 0).
fn pericentre(e: f64) -> PhaseState<2> {
    Kepler::new(e).expect("valid").initial_state()
}

/// The states of a left-point run on Kepler from pericentre (t = 0), up
/// to `steps` steps or to its failure.
fn from_pericentre(e: f64, h0: f64, steps: usize) -> Vec<SemState<2>> {
    let x0 = pericentre(e);
    let run = run_sem(&mut left_point(e), 0.0, x0.q, x0.p, h0, f64::INFINITY, steps, false);
    run.states
}

/// Started at pericentre, the steps follow `h_k ≈ κ(e)·t_k` (t from the
/// turning point), κ = 0.154, 0.479, 0.823 at e = 0.1, 0.3, 0.5, the same
/// for h₀ = 0.005 and 0.00125: each step is 1 + κ times the last, and the
/// error does not shrink with h₀. κ is measured as the least `h_k/t_k` over
/// the steps with `t_k ≤ 0.2`: the transient from h₀ decays from above
/// (h₀/t₀ = ∞) within about twenty steps, and beyond t ≈ 0.2 the orbit's
/// curvature moves it.
#[test]
fn from_a_turning_point_the_steps_grow_in_proportion_to_time_whatever_the_first() {
    for (e, kappa) in [(0.1, 0.154), (0.3, 0.479), (0.5, 0.823)] {
        for h0 in [0.005, 0.00125] {
            let states = from_pericentre(e, h0, 60);
            // h_k, the step leaving t_k, is the next state's `h`.
            let measured = states
                .windows(2)
                .skip(1)
                .filter(|w| w[0].t <= 0.2)
                .map(|w| w[1].h / w[0].t)
                .fold(f64::INFINITY, f64::min);
            assert!(
                (measured - kappa).abs() <= 0.005,
                "e = {e}, h0 = {h0}: h_k/t_k → {measured}, documented {kappa}"
            );
        }
    }
}

/// Started at t = 1 on the exact e = 0.1 orbit, away from turning points,
/// the rule converges at first order up to the next turning point (the
/// apocentre at t = π, which its consistent branch cannot pass): the error
/// of q at t = 2.5 (landed on by a final fixed step) halves with h₀.
#[test]
fn away_from_turning_points_the_rule_is_first_order_until_the_next() {
    let e = 0.1;
    let (q, p) = kepler_exact(e, 1.0).expect("exact");
    let (t_end, exact) = (2.5, kepler_exact(e, 2.5).expect("exact").0);
    let (mut hs, mut errors) = (Vec::new(), Vec::new());
    for h0 in [0.02, 0.01, 0.005, 0.0025] {
        let mut sem = left_point(e);
        let run = run_sem(
            &mut sem,
            1.0,
            Vector2::from(q),
            Vector2::from(p),
            h0,
            t_end,
            100_000,
            true,
        );
        assert!(run.failure.is_none(), "h0 = {h0}: {:?}", run.failure);
        let last = run.states.last().expect("states");
        assert!((last.t - t_end).abs() < 1e-12, "{}", last.t);
        hs.push(h0);
        errors.push((last.q - Vector2::from(exact)).norm());
    }
    let fit = fit_order(&hs, &errors, 1e-12).expect("a fit");
    println!("errors {errors:?}, order {}", fit.order);
    assert!((fit.order - 1.0).abs() < 0.15, "order {} from {errors:?}", fit.order);
    // The same start cannot pass the apocentre.
    let mut sem = left_point(e);
    let run = run_sem(
        &mut sem,
        1.0,
        Vector2::from(q),
        Vector2::from(p),
        0.005,
        4.0,
        100_000,
        false,
    );
    let failed_at = run.states.last().expect("states").t;
    assert!(run.failure.is_some(), "passed the apocentre: ended at t = {failed_at}");
    assert!(
        (failed_at - std::f64::consts::PI).abs() < 0.3,
        "failed at t = {failed_at}"
    );
}

/// The degenerate start is seen before the run: at pericentre the leading
/// term of the first step's energy is round-off against the next, and it
/// moves across zero within a step; away from the turning point it
/// dominates; on a circular orbit it stays zero (and the steps stay within
/// a bounded factor of h₀).
#[test]
fn the_start_expansion_tells_a_turning_point_from_a_circle_and_from_a_regular_start() {
    let at = |e: f64, q: [f64; 2], p: [f64; 2]| {
        left_point(e)
            .start_expansion(0.0, Vector2::from(q), Vector2::from(p), 0.005)
            .expect("expansion")
    };
    let x0 = pericentre(0.1);
    let turning = at(0.1, [x0.q[0], x0.q[1]], [x0.p[0], x0.p[1]]);
    assert!(turning.dominance() < 1e-6, "{turning:?}");
    assert!((turning.drift() - 0.2).abs() < 0.02, "{turning:?}");
    let (q, p) = kepler_exact(0.1, 1.0).expect("exact");
    let regular = at(0.1, q, p);
    println!("dominance at t = 1: {}, drift {}", regular.dominance(), regular.drift());
    assert!(regular.dominance() > 10.0, "{regular:?}: {}", regular.dominance());
    let circle = at(0.0, [1.0, 0.0], [0.0, 1.0]);
    assert!(circle.dominance() < 1e-6 && circle.drift() < 1e-3, "{circle:?}");
    // On the circle the steps stay within a factor of h₀ that does not
    // depend on h₀ (2.73), where from pericentre they grow to O(1).
    for h0 in [0.02, 0.005] {
        let steps = from_pericentre(0.0, h0, 4000);
        let growth = steps.iter().map(|s| s.h).fold(0.0, f64::max) / h0;
        assert!(growth < 3.0, "h0 = {h0}: a circular orbit's steps grow {growth}×");
    }
}

/// The root-selection policy: the run continues its step sequence (Newton
/// from the step extrapolated from the last ones). At e = 0.5, h₀ = 0.01,
/// from pericentre, the energy equation of the left-point rule,
/// ½|∇V|²h² − (p·∇V)h + (H_k − E) = 0 (explicit for L = ½|v|² − V), has
/// two positive roots around the fourth step's h₋₁ = 0.02170: 0.00735 and
/// 0.0381. The run takes 0.0381, the one its growing sequence leads to, not
/// 0.00735, the one nearest h₋₁; both being O(h₋₁) is the degenerate start,
/// which the command warns about.
#[test]
fn two_roots_near_the_last_step_the_run_continues_its_sequence() {
    let e = 0.5;
    let states = from_pericentre(e, 0.01, 4);
    let (s, next) = (&states[3], &states[4]);
    assert!((s.h - 0.02170).abs() < 5e-5, "h₋₁ = {}", s.h);
    let r = s.q.norm();
    let g = s.q / (r * r * r);
    let (a, b, c) = (
        0.5 * g.norm_squared(),
        s.p.dot(&g),
        0.5 * s.p.norm_squared() - 1.0 / r - s.energy,
    );
    let disc = (b * b - 4.0 * a * c).sqrt();
    let roots = [(b - disc) / (2.0 * a), (b + disc) / (2.0 * a)];
    assert!(
        (roots[0] - 0.00735).abs() < 5e-5 && (roots[1] - 0.0381).abs() < 5e-5,
        "{roots:?}"
    );
    assert!(
        (next.h - roots[1]).abs() < 1e-10 * roots[1],
        "took {} of {roots:?}",
        next.h
    );
    let nearest = if (roots[0] - s.h).abs() < (roots[1] - s.h).abs() {
        roots[0]
    } else {
        roots[1]
    };
    assert_ne!(next.h, nearest, "the policy is not nearest-root");
}
