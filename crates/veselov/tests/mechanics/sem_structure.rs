//! The variable-step SEM step's structure (seed 001): its solve passes
//! against the full derivatives, the one-forms as the differential of the
//! action, the time-dependent energy balance, symplecticity in the extended
//! phase space (initial and boundary values), and the discrete equations'
//! continuum limits.

use nalgebra::{SVector, Vector1, Vector2};
use veselov::diagnostics::fit_order;
use veselov::models::{HarmonicOscillator, Kepler};
use veselov::sem::{SemAction, SemIntegrator, SemRule, run_sem, solve_lee_bvp};

use super::sem::pendulum_ivp;

/// `L = ½(1 + 0.2 sin t)|v|² − ½(1 + 0.3 cos t)|q|²`: time-dependent, so
/// every `t₀` derivative of the action is exercised.
#[derive(Debug, Clone)]
struct DrivenOscillator;

impl veselov::mechanics::Lagrangian<2> for DrivenOscillator {
    fn lagrangian<D: veselov::ad::Scalar>(&self, t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        let (m, k) = (D::from(1.0) + t.sin() * 0.2, D::from(1.0) + t.cos() * 0.3);
        (m * v.dot(v) - k * q.dot(q)) * 0.5
    }
}

/// The passes of the step solve agree with the pass that computes every
/// derivative (`derivatives`): the leaving momentum and energy, the arrival
/// momentum and energy, and the moving part of the step Jacobian; on the
/// averaged rule (Kepler), a non-separable Lagrangian (double pendulum) and a
/// time-dependent one.
#[test]
fn step_passes_agree_with_the_full_derivatives() {
    fn check<L: veselov::mechanics::Lagrangian<2>>(action: &SemAction<L, 2>, q0: Vector2<f64>, q1: Vector2<f64>) {
        let (t0, h) = (0.3, 0.07);
        let d = action.derivatives(t0, &q0, &q1, h);
        let scale = 1.0 + d.q0q1.amax() + d.q0h.amax() + d.hh.abs();
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * scale;
        let (value, s_q0, e_minus) = action.leaving(t0, &q0, &q1, h);
        assert!(close(value, d.value) && close(e_minus, d.t0 - d.h));
        assert!((s_q0 - d.q0).amax() <= 1e-13 * scale);
        assert!((action.leaving_momentum(t0, &q0, &q1, h) - d.q0).amax() <= 1e-13 * scale);
        let (p1, e_plus) = action.arrival(t0, &q0, &q1, h);
        assert!((p1 - d.q1).amax() <= 1e-13 * scale && close(e_plus, -d.h));
        let vbar = (q1 - q0) / h;
        let (momentum_w, energy_q1, energy_w) = action.step_jacobian_along(t0, &q0, &q1, h);
        assert!((momentum_w - (d.q0q1 * vbar + d.q0h)).amax() <= 1e-12 * scale);
        let e_q1 = d.q1t0 - d.q1h;
        assert!((energy_q1 - e_q1).amax() <= 1e-12 * scale);
        assert!(close(energy_w, e_q1.dot(&vbar) + d.t0h - d.hh));
    }
    let kepler = Kepler::new(0.5).expect("valid");
    let averaged = SemAction::new(kepler.system(), SemRule::Averaged(2)).expect("valid");
    check(&averaged, Vector2::new(0.6, 0.1), Vector2::new(0.58, 0.2));
    let dp = SemAction::new(veselov::models::DoublePendulum::default(), SemRule::Midpoint).expect("valid");
    check(&dp, Vector2::new(0.5, -0.3), Vector2::new(0.52, -0.25));
    let driven = SemAction::new(DrivenOscillator, SemRule::Trapezoid).expect("valid");
    check(&driven, Vector2::new(0.5, -0.3), Vector2::new(0.52, -0.25));
}

/// Seed 001 (3.8)/(3.15), θ⁻ + θ⁺ = dS on the extended space `x = (t, q)`:
/// the one-form components the integrator uses — `∂S/∂t₀|_{t₁} = E⁻`,
/// `∂S/∂q₀ = −p₀`, `∂S/∂t₁ = −E⁺`, `∂S/∂q₁ = p₁` — are the partial
/// derivatives of the action `S(t₀, q₀, t₁, q₁)`, checked against fourth-order
/// central differences of the action itself (step 1e-3·h; error ≲ 1e-9 of
/// the terms), on a time-dependent Lagrangian and two rules.
#[test]
fn one_forms_are_the_differential_of_the_action() {
    for rule in [SemRule::Midpoint, SemRule::Averaged(2)] {
        let action = SemAction::new(DrivenOscillator, rule).expect("valid");
        let (t0, t1) = (0.3, 0.37);
        let (q0, q1) = (Vector2::new(0.5, -0.3), Vector2::new(0.52, -0.25));
        let s = |t0: f64, q0: &Vector2<f64>, t1: f64, q1: &Vector2<f64>| action.action(t0, q0, q1, t1 - t0);
        let d = action.derivatives(t0, &q0, &q1, t1 - t0);
        let delta = 1e-3 * (t1 - t0);
        // f'(0) by the five-point stencil.
        let diff = |f: &dyn Fn(f64) -> f64| {
            (8.0 * (f(delta) - f(-delta)) - (f(2.0 * delta) - f(-2.0 * delta))) / (12.0 * delta)
        };
        let scale = 1.0 + d.q0.amax() + d.q1.amax() + d.h.abs();
        let close = |fd: f64, exact: f64, what: &str| {
            assert!((fd - exact).abs() <= 1e-9 * scale, "{rule:?} {what}: {fd} vs {exact}");
        };
        close(diff(&|e| s(t0 + e, &q0, t1, &q1)), d.t0 - d.h, "∂S/∂t₀ = E⁻");
        close(diff(&|e| s(t0, &q0, t1 + e, &q1)), d.h, "∂S/∂t₁ = −E⁺");
        for i in 0..2 {
            let unit = Vector2::from_fn(|j, _| if i == j { 1.0 } else { 0.0 });
            close(diff(&|e| s(t0, &(q0 + unit * e), t1, &q1)), d.q0[i], "∂S/∂q₀ = −p₀");
            close(diff(&|e| s(t0, &q0, t1, &(q1 + unit * e))), d.q1[i], "∂S/∂q₁ = p₁");
        }
    }
}

/// Seed 001 (3.4) with a time-dependent Lagrangian (note 001 §2.1): the step
/// makes the energies continuous at every node (`E⁻_k = E⁺_k`), and the
/// energy then changes over a step by the discrete analogue of
/// `dE/dt = −∂L/∂t`: `E_{k+1} − E_k = −∂S/∂t₀|_h` (both times shifted),
/// to round-off; the change is not small, so the test can fail.
#[test]
fn time_dependent_energy_balance_holds_step_by_step() {
    let action = SemAction::new(DrivenOscillator, SemRule::Midpoint).expect("valid");
    let mut sem = SemIntegrator::new(action.clone());
    let run = run_sem(
        &mut sem,
        0.0,
        Vector2::new(1.0, 0.0),
        Vector2::new(0.0, 0.5),
        0.05,
        f64::INFINITY,
        400,
        false,
    );
    assert!(run.failure.is_none(), "{:?}", run.failure);
    let (mut worst, mut moved) = (0.0_f64, 0.0_f64);
    for w in run.states.windows(2).skip(1) {
        let (a, b) = (&w[0], &w[1]);
        let d = action.derivatives(a.t, &a.q, &b.q, b.t - a.t);
        // E⁻ at the node equals the energy carried there (the step's equation).
        assert!((d.t0 - d.h - a.energy).abs() <= 1e-12 * (1.0 + a.energy.abs()));
        let balance = b.energy - a.energy + d.t0;
        worst = worst.max(balance.abs() / (1.0 + a.energy.abs() + d.t0.abs()));
        moved = moved.max((b.energy - run.states[1].energy).abs());
    }
    assert!(worst <= 1e-12, "energy balance off by {worst:e}");
    assert!(moved > 1e-2, "the driven energy should change: {moved:e}");
}

/// `L = ½(1 + 0.2 sin t) v² − ½(1 + 0.3 cos t) q²` in one dimension.
#[derive(Debug, Clone)]
struct DrivenOscillator1;

impl veselov::mechanics::Lagrangian<1> for DrivenOscillator1 {
    fn lagrangian<D: veselov::ad::Scalar>(&self, t: D, q: &SVector<D, 1>, v: &SVector<D, 1>) -> D {
        let (m, k) = (D::from(1.0) + t.sin() * 0.2, D::from(1.0) + t.cos() * 0.3);
        (m * v[0] * v[0] - k * q[0] * q[0]) * 0.5
    }
}

/// Seed 001 (3.16)–(3.17): the SEM step is symplectic on the extended phase
/// space `(t, q, p_t = −E, p)` — with a time-dependent Lagrangian, where the
/// energy is not conserved. The Jacobian of `(t₀, q₀, −E₀, p₀) ↦ (t₁, q₁,
/// −E₁, p₁)` comes from the implicit function theorem on the step equations
/// with the exact Hessian of `S(t₀, q₀, q₁, h)`; `JᵀΩJ = Ω` to round-off of
/// `|J|²`. Carrying the energy over unchanged instead (`E₁ = E₀`) is not
/// symplectic here, so the check can fail.
#[test]
fn step_is_symplectic_in_the_extended_phase_space() {
    use nalgebra::{Matrix2, Matrix2x4, Matrix4, Vector4};
    use num_dual::Dual2SVec64;
    let action = SemAction::new(DrivenOscillator1, SemRule::Midpoint).expect("valid");
    let mut sem = SemIntegrator::new(action.clone());
    let (_, mut s) = sem
        .start(0.2, Vector1::new(0.8), Vector1::new(0.3), 0.05)
        .expect("start");
    for _ in 0..25 {
        s = sem.step(1, &s).expect("step").0;
    }
    let (next, info) = sem.step(1, &s).expect("step");
    let (t0, q0, q1, h) = (s.t, s.q[0], next.q[0], info.h);
    let (_, _, hs) = num_dual::hessian(
        |x: SVector<Dual2SVec64<4>, 4>| action.action(x[0], &SVector::from([x[1]]), &SVector::from([x[2]]), x[3]),
        &Vector4::new(t0, q0, q1, h),
    );
    // Indices: 0 = t₀, 1 = q₀, 2 = q₁, 3 = h. Unknowns y = (q₁, h); data
    // x = (t₀, q₀, p_t = −E₀, p₀); R₁ = p₀ + S_q₀, R₂ = S_t₀ − S_h − E₀.
    let ry = Matrix2::new(hs[(1, 2)], hs[(1, 3)], hs[(0, 2)] - hs[(3, 2)], hs[(0, 3)] - hs[(3, 3)]);
    let rx = Matrix2x4::new(
        hs[(1, 0)],
        hs[(1, 1)],
        0.0,
        1.0,
        hs[(0, 0)] - hs[(3, 0)],
        hs[(0, 1)] - hs[(3, 1)],
        1.0, // R₂ = S_t₀ − S_h + p_t
        0.0,
    );
    let dy = -ry.try_inverse().expect("regular step") * rx;
    let jacobian = |conserve_energy: bool| {
        let e = |i: usize| Vector4::from_fn(|j, _| if i == j { 1.0 } else { 0.0 }).transpose();
        let (dq1, dh) = (dy.row(0).into_owned(), dy.row(1).into_owned());
        let dt1 = e(0) + dh;
        let dp1 = e(0) * hs[(2, 0)] + e(1) * hs[(2, 1)] + dq1 * hs[(2, 2)] + dh * hs[(2, 3)];
        // p_t₁ = −E₁ = S_h.
        let dpt1 = if conserve_energy {
            e(2)
        } else {
            e(0) * hs[(3, 0)] + e(1) * hs[(3, 1)] + dq1 * hs[(3, 2)] + dh * hs[(3, 3)]
        };
        Matrix4::from_rows(&[dt1, dq1, dpt1, dp1])
    };
    let omega = Matrix4::new(
        0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0,
    );
    let defect = |j: Matrix4<f64>| (j.transpose() * omega * j - omega).amax() / j.amax().powi(2);
    let exact = defect(jacobian(false));
    println!(
        "extended symplecticity defect {exact:e}, with E carried over {:e}",
        defect(jacobian(true))
    );
    assert!(exact < 1e-13, "extended symplecticity defect {exact:e}");
    let wrong = defect(jacobian(true));
    assert!(wrong > 1e-6, "carrying E over unchanged should break it: {wrong:e}");
}

/// Seed 001 §3 (Lee's discrete mechanics): the boundary-value solutions are
/// symplectic. With both ends `x₀ = (t₀, q₀)`, `x_K = (t_K, q_K)` fixed, the
/// end momenta `P₀ = −∂S/∂x₀` (first segment) and `P_K = ∂S/∂x_K` (last
/// segment) are the gradient of the total action 𝕊(x₀, x_K), so the map from
/// the ends to the end momenta has a symmetric Jacobian in the sense
/// `∂P_K/∂x₀ = −(∂P₀/∂x_K)ᵀ`, `∂P₀/∂x₀ = (∂P₀/∂x₀)ᵀ`, `∂P_K/∂x_K = (∂P_K/∂x_K)ᵀ`
/// (central differences of re-solved problems, step 1e-5: error ≲ 1e-8).
/// The cross block is far from zero, so a wrong sign would fail.
#[test]
fn lee_boundary_value_solutions_are_symplectic() {
    use nalgebra::{Matrix2, Vector2 as V2};
    let (action, base) = pendulum_ivp(10);
    let k = base.len() - 1;
    // End momenta (p_t = −E, p) of the solution with ends moved by `d0`, `dk`.
    let ends = |d0: V2<f64>, dk: V2<f64>| -> (V2<f64>, V2<f64>) {
        let mut guess = base.clone();
        guess[0] = (base[0].0 + d0[0], base[0].1 + Vector1::new(d0[1]));
        guess[k] = (base[k].0 + dk[0], base[k].1 + Vector1::new(dk[1]));
        let sol = solve_lee_bvp(&action, &guess, 50).expect("converges");
        let (a, b) = (&sol[0], &sol[1]);
        let first = action.derivatives(a.0, &a.1, &b.1, b.0 - a.0);
        let (y, z) = (&sol[k - 1], &sol[k]);
        let last = action.derivatives(y.0, &y.1, &z.1, z.0 - y.0);
        (-V2::new(first.t0 - first.h, first.q0[0]), V2::new(last.h, last.q1[0]))
    };
    let delta = 1e-5;
    let mut blocks = [Matrix2::<f64>::zeros(); 4]; // ∂P₀/∂x₀, ∂P₀/∂x_K, ∂P_K/∂x₀, ∂P_K/∂x_K
    for j in 0..2 {
        let e = V2::from_fn(|i, _| if i == j { delta } else { 0.0 });
        let z = V2::zeros();
        let (p0_plus, pk_plus) = ends(e, z);
        let (p0_minus, pk_minus) = ends(-e, z);
        blocks[0].set_column(j, &((p0_plus - p0_minus) / (2.0 * delta)));
        blocks[2].set_column(j, &((pk_plus - pk_minus) / (2.0 * delta)));
        let (p0_plus, pk_plus) = ends(z, e);
        let (p0_minus, pk_minus) = ends(z, -e);
        blocks[1].set_column(j, &((p0_plus - p0_minus) / (2.0 * delta)));
        blocks[3].set_column(j, &((pk_plus - pk_minus) / (2.0 * delta)));
    }
    let scale = blocks.iter().map(|b| b.amax()).fold(0.0, f64::max);
    let asym = |m: &Matrix2<f64>| (m - m.transpose()).amax() / scale;
    let cross = (blocks[2] + blocks[1].transpose()).amax() / scale;
    println!(
        "Lee BVP: |∂P₀/∂x₀ asym| {:.1e}, |∂P_K/∂x_K asym| {:.1e}, |∂P_K/∂x₀ + (∂P₀/∂x_K)ᵀ| {cross:.1e} (of {scale:.2})",
        asym(&blocks[0]),
        asym(&blocks[3])
    );
    assert!(asym(&blocks[0]) < 1e-7 && asym(&blocks[3]) < 1e-7 && cross < 1e-7);
    assert!(blocks[2].amax() > 1e-2 * scale, "the cross block must not vanish");
}

/// The discrete equations at node `k` of a grid `t`, sampled on the exact
/// harmonic-oscillator solution `q = cos t`, in the paper's normalisation:
/// the Euler–Lagrange residual (3.19) `(∂S_{k−1}/∂q₁ + ∂S_k/∂q₀)/h_k` and the
/// energy residual (3.21) `(E⁻_k − E⁺_{k−1})/h_k`.
fn continuum_residuals(rule: SemRule, t: [f64; 3]) -> (f64, f64) {
    let oscillator = HarmonicOscillator::new(1.0, 1.0).expect("valid");
    let action = SemAction::new(oscillator.system(), rule).expect("valid");
    let q = |t: f64| Vector1::new(t.cos());
    let (h0, h1) = (t[1] - t[0], t[2] - t[1]);
    let (p_arrive, e_arrive) = action.arrival(t[0], &q(t[0]), &q(t[1]), h0);
    let (_, p_leave, e_leave) = action.leaving(t[1], &q(t[1]), &q(t[2]), h1);
    (((p_arrive + p_leave)[0] / h1).abs(), ((e_leave - e_arrive) / h1).abs())
}

/// Seed 001 (3.19)→(3.20) and (3.21)→(3.22): the discrete equations tend to
/// the Euler–Lagrange equation and energy conservation. On a smoothly
/// varying grid `t = s + 0.2 sin s` (`s` uniform), the residuals of exact
/// solutions vanish at rate 1 for the left-point rule (3.18) and at rate 2
/// for the midpoint rule. On a grid whose steps alternate `h, 2h` the
/// left-point residuals do not vanish: with `r = h_{k−1}/h_k` they tend to
/// `|q̈ ((1 + r)/2 − 1)|` and `|(1 − r)/2 · q̇ · V'(q)|` (note 001 §2.7), the
/// paper's limits hold only for smoothly varying steps; the midpoint rule is
/// consistent on both grids (rate 1 on the alternating one).
#[test]
fn discrete_equations_tend_to_their_continuum_limits() {
    let node = 1.0;
    let steps = [0.04, 0.02, 0.01, 0.005, 0.0025];
    let smooth = |h: f64| {
        let s = |k: f64| node + k * h + 0.2 * (node + k * h).sin() - 0.2 * node.sin();
        [s(-1.0), s(0.0), s(1.0)]
    };
    let alternating = |h: f64| [node - h, node, node + 2.0 * h];
    // Rates: 1 for the left point; for the midpoint rule 2 where the steps
    // vary smoothly (the O(h²) errors of neighbouring steps cancel to first
    // order) and 1 where they alternate.
    for (rule, grid, expected, name) in [
        (
            SemRule::LeftPoint,
            &smooth as &dyn Fn(f64) -> [f64; 3],
            1.0,
            "left point, smooth grid",
        ),
        (SemRule::Midpoint, &smooth, 2.0, "midpoint, smooth grid"),
        (SemRule::Midpoint, &alternating, 1.0, "midpoint, alternating grid"),
    ] {
        let (del, energy): (Vec<f64>, Vec<f64>) = steps.iter().map(|&h| continuum_residuals(rule, grid(h))).unzip();
        for (what, r) in [("(3.19)", &del), ("(3.21)", &energy)] {
            let fit = fit_order(&steps, r, 1e-13).expect("fit");
            println!("{name} {what}: residuals {r:?}, rate {:.3}", fit.order);
            assert!(
                (fit.order - expected).abs() < 0.1,
                "{name} {what}: rate {:.3}",
                fit.order
            );
        }
    }
    // Left point, alternating steps (r = 1/2): O(1) residuals at the derived values.
    let r = 0.5;
    let (qdd, qd, v_prime) = (-node.cos(), -node.sin(), node.cos());
    for &h in &steps {
        let (del, energy) = continuum_residuals(SemRule::LeftPoint, alternating(h));
        let (del_limit, energy_limit) = (
            (qdd * ((1.0 + r) / 2.0 - 1.0)).abs(),
            ((1.0 - r) / 2.0 * qd * v_prime).abs(),
        );
        // The limits are approached at rate 1 in h.
        assert!(
            (del - del_limit).abs() < 2.0 * h,
            "h = {h}: (3.19) residual {del} vs {del_limit}"
        );
        assert!(
            (energy - energy_limit).abs() < 2.0 * h,
            "h = {h}: (3.21) residual {energy} vs {energy_limit}"
        );
    }
}
