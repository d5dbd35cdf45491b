//! Forced and dissipative systems: discrete Lagrange–d'Alembert integrators,
//! Galley duplication, variational order (seed 004).

use crate::common;

use common::{LOWER, scheme};
use nalgebra::{Matrix2, SVector, Vector1, Vector2};
use veselov::diagnostics::{fit_order, rk4_reference, symplecticity_defect};
use veselov::mechanics::{
    DuplicatedLagrangian, Force, GalerkinIntegrator, Lagrangian, Method, NoForce, OneStepMap, PhaseState, integrate,
};
use veselov::models::damped_oscillator::LinearDamping;
use veselov::models::van_der_pol::VanDerPolForce;
use veselov::models::{DampedOscillator, LinearDrag, Pendulum, VanDerPol};

fn forced_methods() -> Vec<Method> {
    let mut m = vec![Method::Midpoint, Method::Alpha(0.3)];
    m.extend((2..=5).map(Method::GalerkinLobatto));
    m.extend((1..=4).map(Method::GalerkinGauss));
    m
}

/// Coupled van der Pol (ε, ρ, λ) = (0.5, 0.02, 0.8), q = (−½, −¼), v = (0, 4),
/// error at t = 1 against an RK4 reference with 40 000 compensated steps
/// (truncation ≈ h⁴·C ≲ 1e-15 here): fitted orders within ±0.2, for the
/// state (Diagram 7.1, left) and for the energy `E(q, p)` (Diagrams 7.1,
/// right, and 7.3: the same order 2s − 2 for Lobatto s = 2..5).
#[test]
fn van_der_pol_orders() {
    let vdp = VanDerPol::default();
    let x0 = VanDerPol::initial_state();
    let reference = rk4_reference(&vdp.system(), &vdp.force(), &x0, 1.0, 40_000).expect("reference");
    let energy_of = |x: &PhaseState<2>| {
        let v = veselov::mechanics::velocity_from_momentum(&vdp.system(), x.t, &x.q, &x.p).expect("regular");
        veselov::mechanics::energy(&vdp.system(), x.t, &x.q, &v)
    };
    let reference_energy = energy_of(&reference);
    for method in forced_methods() {
        let p = scheme(method).order() as f64;
        let mut table = Vec::new();
        let mut energy_table = Vec::new();
        for n in [4usize, 6, 8, 11, 16, 23, 32, 45, 64, 91, 128, 181, 256, 362, 512] {
            let mut map = GalerkinIntegrator::with_force(vdp.system(), vdp.force(), scheme(method), 1.0 / n as f64)
                .expect("valid");
            let run = integrate(&mut map, x0, n, n);
            let Some(x) = run.failure.is_none().then(|| *run.last()) else {
                continue;
            };
            let err = (x.q - reference.q).amax().max((x.p - reference.p).amax());
            table.push((1.0 / n as f64, err));
            energy_table.push((1.0 / n as f64, (energy_of(&x) - reference_energy).abs()));
            if err < common::floor(n) {
                break;
            }
        }
        let fit = common::fit_asymptotic(&table, 1.0, p as usize).unwrap_or_else(|| panic!("{method:?}: {table:?}"));
        assert!(fit.used.len() >= 3, "{method:?}: {table:?}");
        assert!(
            (fit.order - p).abs() <= 0.2,
            "{method:?}: fitted {:.3}, claimed {p}: {table:?}",
            fit.order
        );
        let fit = common::fit_asymptotic(&energy_table, 1.0, p as usize)
            .unwrap_or_else(|| panic!("{method:?} energy: {energy_table:?}"));
        assert!(fit.used.len() >= 3, "{method:?} energy: {energy_table:?}");
        assert!(
            (fit.order - p).abs() <= 0.2,
            "{method:?}: energy order {:.3}, claimed {p}: {energy_table:?}",
            fit.order
        );
    }
}

fn example_72() -> DampedOscillator<2> {
    DampedOscillator::new(
        Matrix2::new(2.0, 0.3, 0.3, 1.0),
        Matrix2::new(3.0, -1.0, -1.0, 2.0),
        Matrix2::new(0.4, 0.1, 0.1, 0.2),
    )
    .expect("valid")
}

/// Example 7.2: the forced midpoint scheme satisfies
/// `M(q_{k+2} − 2q_{k+1} + q_k)/h² + D(q_{k+2} − q_k)/(2h) + K(q_{k+2} + 2q_{k+1} + q_k)/4 = 0`
/// to round-off, and `Ê_k = ½|Δq/h|²_M + ½|q̄|²_K` decays by exactly
/// `(q_{k+2} − q_k)ᵀD(q_{k+2} − q_k)/(4h)` per step.
#[test]
fn example_7_2_recursion_and_exact_energy_decay() {
    let osc = example_72();
    let h = 0.1;
    let mut map =
        GalerkinIntegrator::with_force(osc.system(), osc.force(), scheme(Method::Midpoint), h).expect("valid");
    let x0 = PhaseState::new(0.0, Vector2::new(1.0, -0.5), Vector2::new(0.2, 0.7));
    let run = integrate(&mut map, x0, 200, 1);
    let q: Vec<Vector2<f64>> = run.states.iter().map(|x| x.q).collect();
    let (m, k, d) = (osc.mass, osc.stiffness, osc.damping);
    let e_hat = |a: &Vector2<f64>, b: &Vector2<f64>| {
        let dq = (b - a) / h;
        let mid = (a + b) / 2.0;
        0.5 * (m * dq).dot(&dq) + 0.5 * (k * mid).dot(&mid)
    };
    for w in q.windows(3) {
        let r = m * (w[2] - w[1] * 2.0 + w[0]) / (h * h)
            + d * (w[2] - w[0]) / (2.0 * h)
            + k * (w[2] + w[1] * 2.0 + w[0]) / 4.0;
        let scale = (m * w[2]).amax() / (h * h);
        assert!(r.amax() <= 1e-13 * scale.max(1.0), "recursion residual {:e}", r.amax());
        let decay = e_hat(&w[0], &w[1]) - e_hat(&w[1], &w[2]);
        let dd = w[2] - w[0];
        let expected = (d * dd).dot(&dd) / (4.0 * h);
        assert!(decay >= 0.0);
        assert!(
            (decay - expected).abs() <= 1e-13 * e_hat(&w[0], &w[1]).max(1e-3),
            "{decay:e} vs {expected:e}"
        );
    }
}

/// Damping dissipates for every method: with `F = −Dv`, `D ≻ 0`, the energy
/// falls overall and never rises by more than `10·hᵖ` (the order-p error of
/// the discrete energy); flipping the sign of `D` (a pumping force) makes the
/// same check fail, so it detects a sign error.
#[test]
fn damping_dissipates_energy() {
    let osc = example_72();
    let pump = LinearDamping(-osc.damping);
    let x0 = PhaseState::new(0.0, Vector2::new(1.0, -0.5), Vector2::new(0.2, 0.7));
    let h = 0.05;
    for method in forced_methods() {
        let p = scheme(method).order() as i32;
        let rise_and_drop = |f: &LinearDamping<2>| {
            let mut map = GalerkinIntegrator::with_force(osc.system(), *f, scheme(method), h).expect("valid");
            let run = integrate(&mut map, x0, 400, 1);
            let e: Vec<f64> = run.states.iter().map(|x| osc.energy(x)).collect();
            let mut low = e[0];
            let mut rise = 0.0_f64;
            for &x in &e {
                rise = rise.max(x - low);
                low = low.min(x);
            }
            (rise, e[0] - e[e.len() - 1])
        };
        let (rise, drop) = rise_and_drop(&osc.force());
        assert!(drop > 0.5 * osc.energy(&x0), "{method:?}: energy only fell by {drop}");
        assert!(rise <= 10.0 * h.powi(p), "{method:?}: energy rose by {rise:e}");
        let (rise, _) = rise_and_drop(&pump);
        assert!(rise > 10.0 * h.powi(p), "{method:?}: pumping force not detected");
    }
}

/// Discrete energy balance: `E_k − E_0 − W_k = O(hᵖ)` with `W` the discrete
/// work `Σ h Σᵢ bᵢ F(i)·Yᵢ`; measured on a pendulum with linear drag (a
/// non-quadratic potential) at t = 2. For the quadratic van der Pol potential
/// the midpoint balance even holds to round-off.
#[test]
fn discrete_energy_balance_converges_at_the_method_order() {
    let pendulum = Pendulum::default();
    let drag = LinearDrag::new(0.3).expect("valid");
    let x0 = PhaseState::new(0.0, Vector1::new(1.2), Vector1::new(0.0));
    for method in [
        Method::Midpoint,
        Method::Trapezoid,
        Method::GalerkinLobatto(3),
        Method::GalerkinGauss(2),
        Method::GalerkinLobatto(4),
    ] {
        let p = scheme(method).order() as f64;
        let mut h_list = Vec::new();
        let mut errs = Vec::new();
        let counts: &[usize] = if p >= 6.0 {
            &[4, 6, 8, 11, 16, 23]
        } else {
            &[16, 23, 32, 45, 64, 91, 128]
        };
        for &n in counts {
            let mut map =
                GalerkinIntegrator::with_force(pendulum.system(), drag, scheme(method), 2.0 / n as f64).expect("valid");
            let run = integrate(&mut map, x0, n, n);
            let balance = pendulum.energy(run.last()) - pendulum.energy(&x0) - run.work[run.work.len() - 1];
            h_list.push(2.0 / n as f64);
            errs.push(balance.abs());
        }
        let fit = fit_order(&h_list, &errs, LOWER).unwrap_or_else(|| panic!("{method:?}: {errs:?}"));
        assert!(
            fit.order >= p - 0.2,
            "{method:?}: balance error order {:.3} < {p}: {errs:?}",
            fit.order
        );
    }
    let vdp = VanDerPol::default();
    let x0 = VanDerPol::initial_state();
    let mut map =
        GalerkinIntegrator::with_force(vdp.system(), vdp.force(), scheme(Method::Midpoint), 0.05).expect("valid");
    let run = integrate(&mut map, x0, 20, 20);
    let balance = vdp.energy(run.last()) - vdp.energy(&x0) - run.work[run.work.len() - 1];
    assert!(balance.abs() < 1e-13, "{balance:e}");
}

type Dup = DuplicatedLagrangian<
    veselov::mechanics::SeparableLagrangian<VanDerPol, 2>,
    VanDerPolForce,
    veselov::mechanics::FlatRetraction,
    2,
    4,
>;

fn duplicated() -> Dup {
    let vdp = VanDerPol::default();
    DuplicatedLagrangian::new(vdp.system(), vdp.force()).expect("M = 2N")
}

/// Started on the diagonal, the free duplicated scheme stays there to ≤ 1e-13
/// and its physical copy equals the forced scheme; started off the diagonal it
/// leaves it (the diagonal is invariant, not attracting).
#[test]
fn duplicated_scheme_stays_on_the_diagonal_and_equals_the_forced_scheme() {
    let vdp = VanDerPol::default();
    let x0 = VanDerPol::initial_state();
    let h = 0.02;
    // Every Lobatto s of the paper's §7.1 (2..5), the midpoint and a Gauss rule.
    let methods = [Method::Midpoint, Method::GalerkinGauss(2)]
        .into_iter()
        .chain((2..=5).map(Method::GalerkinLobatto));
    for method in methods {
        let mut forced = GalerkinIntegrator::with_force(vdp.system(), vdp.force(), scheme(method), h).expect("valid");
        let mut dup = GalerkinIntegrator::new(duplicated(), scheme(method), h).expect("valid");
        let (mut x, mut y) = (x0, Dup::diagonal_state(&x0));
        for k in 0..100 {
            x = forced.step(k, &x).expect("forced").0;
            y = dup.step(k, &y).expect("duplicated").0;
            let (q, big_q) = Dup::split(&y.q);
            let (pq, pbig) = Dup::split(&y.p);
            let scale = x.q.amax().max(x.p.amax()).max(1.0);
            assert!(
                (q - big_q).amax() <= 1e-13 * scale,
                "{method:?} step {k}: off diagonal by {:e}",
                (q - big_q).amax()
            );
            assert!((pq + pbig).amax() <= 1e-13 * scale, "{method:?} step {k}: p_q ≠ −p_Q");
            assert!(
                (big_q - x.q).amax() <= 1e-13 * scale && (pbig - x.p).amax() <= 1e-13 * scale,
                "{method:?} step {k}: differs from forced"
            );
        }
        // Negative control: a 1e-6 offset grows (anti-damping) instead of decaying.
        let mut off = Dup::diagonal_state(&x0);
        off.q[0] += 1e-6;
        let run = integrate(&mut dup, off, 100, 100);
        let (q, big_q) = Dup::split(&run.last().q);
        assert!((q - big_q).amax() > 1e-6, "{method:?}: offset did not persist");
    }
}

/// The duplicated map is symplectic on R⁸; the forced map is not: its Jacobian
/// determinant is `exp(∫ div F) + O(h^{p+1})`, far from 1.
#[test]
fn duplicated_map_is_symplectic_and_forced_map_is_not() {
    let vdp = VanDerPol::default();
    let x0 = VanDerPol::initial_state();
    let h = 0.05;
    for method in [Method::Midpoint, Method::GalerkinLobatto(3), Method::GalerkinGauss(2)] {
        let mut dup = GalerkinIntegrator::new(duplicated(), scheme(method), h).expect("valid");
        let mut y0 = Dup::diagonal_state(&x0);
        y0.q[0] += 0.01; // a generic point, off the diagonal
        let (_, jac) = dup.flow_jacobian(&y0).expect("step");
        assert!(
            symplecticity_defect(&jac) <= 1e-12,
            "{method:?}: {:e}",
            symplecticity_defect(&jac)
        );

        let mut forced = GalerkinIntegrator::with_force(vdp.system(), vdp.force(), scheme(method), h).expect("valid");
        let (x1, j) = forced.flow_jacobian(&x0).expect("step");
        let mut full = nalgebra::Matrix4::<f64>::zeros();
        full.view_mut((0, 0), (2, 2)).copy_from(&j.qq);
        full.view_mut((0, 2), (2, 2)).copy_from(&j.qp);
        full.view_mut((2, 0), (2, 2)).copy_from(&j.pq);
        full.view_mut((2, 2), (2, 2)).copy_from(&j.pp);
        let det = full.determinant();
        // div F = Σ (ε − qᵢ²), trapezoid in time over the step.
        let div = |q: &Vector2<f64>| (vdp.epsilon - q[0] * q[0]) + (vdp.epsilon - q[1] * q[1]);
        let expected = (0.5 * h * (div(&x0.q) + div(&x1.q))).exp();
        assert!((det - 1.0).abs() > 1e-3, "{method:?}: det {det}");
        assert!(
            (det - expected).abs() <= 10.0 * h * h * h,
            "{method:?}: det {det} vs exp(h div F) {expected}"
        );
        if matches!(method, Method::Midpoint) {
            // F ≡ 0 restores symplecticity.
            let mut free = GalerkinIntegrator::with_force(vdp.system(), NoForce, scheme(method), h).expect("valid");
            let (_, j) = free.flow_jacobian(&x0).expect("step");
            assert!(symplecticity_defect(&j) < 1e-13);
        }
    }
}

/// `𝐋(ι̃x) = −𝐋(x)` for the duplicated Lagrangian and for its discretization.
#[test]
fn duplicated_lagrangian_and_discretization_are_antisymmetric() {
    let l = duplicated();
    let x = SVector::<f64, 4>::new(0.3, -0.2, 0.1, 0.4);
    let v = SVector::<f64, 4>::new(1.0, -0.5, 0.7, 0.2);
    let a = l.lagrangian(0.0, &x, &v);
    let b = l.lagrangian(0.0, &Dup::swap(&x), &Dup::swap(&v));
    assert!((a + b).abs() <= 1e-15 * a.abs().max(1.0), "{a} vs {b}");
    for method in [Method::Midpoint, Method::GalerkinLobatto(3), Method::GalerkinGauss(3)] {
        let mut map = GalerkinIntegrator::new(duplicated(), scheme(method), 0.1).expect("valid");
        let x1 = x + v * 0.1;
        let ld = map.discrete_lagrangian(0.0, &x, &x1).expect("ok").value;
        let ls = map
            .discrete_lagrangian(0.0, &Dup::swap(&x), &Dup::swap(&x1))
            .expect("ok")
            .value;
        assert!(
            (ld + ls).abs() <= 1e-14 * ld.abs().max(1e-3),
            "{method:?}: {ld} vs {ls}"
        );
    }
    // The van der Pol force vanishes at zero velocity (Lemma 3.4 itself is
    // checked for any inverse retraction in `tests/mechanics/variational_order.rs`).
    let f = VanDerPol::default().force();
    let q = Vector2::new(0.2, 0.3);
    assert_eq!(f.force(0.0, &q, &Vector2::zeros()), Vector2::zeros());
}

/// The fixed-point separable path with forces equals the general Newton path
/// step by step to round-off (van der Pol), including the discrete work.
#[test]
fn forced_separable_path_equals_general_path() {
    let vdp = VanDerPol::default();
    for method in forced_methods() {
        let h = 0.02;
        let mut general = GalerkinIntegrator::with_force(vdp.system(), vdp.force(), scheme(method), h).expect("valid");
        let mut fast =
            veselov::mechanics::SeparableIntegrator::with_force(vdp.system(), vdp.force(), scheme(method), h)
                .expect("valid");
        let mut x = VanDerPol::initial_state();
        for k in 0..200 {
            let (a, sa) = general.step(k, &x).expect("general");
            let (b, sb) = fast.step(k, &x).expect("fast");
            assert!(!sb.fallback, "{method:?} step {k}: fell back");
            let d = (a.q - b.q).amax().max((a.p - b.p).amax());
            assert!(d < 1e-13, "{method:?} step {k}: {d:e}");
            assert!(
                (sa.work - sb.work).abs() < 1e-13,
                "{method:?} step {k}: work {} vs {}",
                sa.work,
                sb.work
            );
            x = b;
        }
    }
}

/// Seed 004 §4 on the diagonal, for van der Pol (a velocity-dependent force)
/// at several states:
/// * Prop. 4.4: the energy of the duplicated Lagrangian is odd under the
///   swap, `E_𝐋 ∘ ι̃ = −E_𝐋` (anywhere, not only on the diagonal);
/// * Prop. 4.7: on the diagonal its velocity Hessian is `diag(−W, W)`, `W`
///   that of `L`, so it is regular there when `L` is;
/// * Thm. 4.8: on the diagonal its (free) Euler–Lagrange accelerations are
///   the forced accelerations of `(L, F)` in both copies; off the diagonal
///   they are not.
#[test]
fn duplicated_euler_lagrange_equations_on_the_diagonal_are_the_forced_ones() {
    use veselov::mechanics::{acceleration, energy, forced_acceleration, hessian};
    let vdp = VanDerPol::default();
    let (l, f) = (vdp.system(), vdp.force());
    let dup = duplicated();
    let states = [
        (Vector2::new(0.3, -0.2), Vector2::new(1.0, -0.5)),
        (Vector2::new(-1.1, 0.7), Vector2::new(0.2, 2.5)),
        (Vector2::new(0.05, 1.9), Vector2::new(-3.0, 0.4)),
    ];
    for (t, (q, v)) in states.iter().enumerate() {
        let t = 0.3 * t as f64;
        // Prop. 4.4, off the diagonal.
        let (x, xdot) = (Dup::join(q, &(q * 0.7)), Dup::join(v, &(v * -1.3)));
        let (e, e_swapped) = (
            energy(&dup, t, &x, &xdot),
            energy(&dup, t, &Dup::swap(&x), &Dup::swap(&xdot)),
        );
        assert!((e + e_swapped).abs() <= 1e-14 * e.abs().max(1.0), "{e} vs {e_swapped}");
        // Prop. 4.7.
        let (x, xdot) = (Dup::join(q, q), Dup::join(v, v));
        let w = hessian(&l, t, q, v).vv;
        let big = hessian(&dup, t, &x, &xdot).vv;
        for i in 0..4 {
            for j in 0..4 {
                let expected = match (i < 2, j < 2) {
                    (true, true) => -w[(i, j)],
                    (false, false) => w[(i - 2, j - 2)],
                    _ => 0.0,
                };
                assert!((big[(i, j)] - expected).abs() <= 1e-14, "W[{i}{j}] = {}", big[(i, j)]);
            }
        }
        // Thm. 4.8.
        let forced = forced_acceleration(&l, &f, t, q, v).expect("regular");
        let free = acceleration(&l, t, q, v).expect("regular");
        let a = acceleration(&dup, t, &x, &xdot).expect("regular on the diagonal");
        let (a_q, a_target) = Dup::split(&a);
        for copy in [a_q, a_target] {
            assert!(
                (copy - forced).amax() <= 1e-13 * forced.amax().max(1.0),
                "{copy} vs {forced}"
            );
        }
        assert!((forced - free).amax() > 1e-3, "the force must matter at this state");
        let off = acceleration(&dup, t, &Dup::join(q, &(q * 0.5)), &xdot).expect("regular");
        assert!(
            (Dup::split(&off).1 - forced).amax() > 1e-6,
            "off the diagonal the copies are not forced"
        );
    }
}
