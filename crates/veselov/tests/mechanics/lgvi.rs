//! Lie-group variational integrators: agreement of the general and the fast
//! path, stationarity of the discrete action (finite differences), Noether
//! momenta, orthogonality, order against an independent reference, and
//! symplecticity in left-trivialised coordinates.

use nalgebra::{Matrix3, SVector, Vector3, Vector6};
use veselov::diagnostics::fit_order;
use veselov::lgvi::{
    GroupState, GroupStepMap, LieGroupIntegrator, SplitLieIntegrator, discrete_lagrangian, energy,
    integrate_group_observed, lie_symplecticity_defect, rk4_group_reference, spatial_momentum,
};
use veselov::lie::{CayleyMap, ExpMap, GroupFamily, LieGroup, Retraction, RigidMotions, Rotations, SE3, so3};
use veselov::models::{FreeRigidBody, FreeRigidBodySE3, HeavyTop};

fn inertia() -> Matrix3<f64> {
    // An asymmetric body with a non-diagonal tensor (principal axes not the
    // body axes), so nothing is accidentally integrable.
    Matrix3::new(2.0, 0.1, -0.05, 0.1, 3.0, 0.2, -0.05, 0.2, 4.5)
}

fn body() -> FreeRigidBody {
    FreeRigidBody::new(inertia()).expect("valid inertia")
}

fn top() -> HeavyTop {
    HeavyTop::new(inertia(), 1.5, Vector3::new(0.1, -0.05, 0.8), 9.81).expect("valid top")
}

fn body_se3() -> FreeRigidBodySE3 {
    FreeRigidBodySE3::new(inertia(), 2.5).expect("valid body")
}

fn so3_state() -> GroupState<Rotations, 3> {
    let r = so3::exp(&Vector3::new(0.3, -0.7, 0.4));
    GroupState::new(0.0, r, inertia() * Vector3::new(1.1, -0.4, 0.9))
}

fn se3_state() -> GroupState<RigidMotions, 6> {
    let g = SE3::new(so3::exp(&Vector3::new(0.3, -0.7, 0.4)), Vector3::new(1.0, -2.0, 0.5));
    GroupState::new(0.0, g, Vector6::new(2.0, -1.0, 3.0, 0.7, 1.2, -0.4))
}

fn max_diff<G: GroupFamily<N>, const N: usize>(a: &GroupState<G, N>, b: &GroupState<G, N>) -> f64 {
    let dr = (G::rotation(&a.g) - G::rotation(&b.g)).amax();
    let dx = (G::translation(&a.g) - G::translation(&b.g)).amax();
    dr.max(dx).max((a.mu - b.mu).amax() / a.mu.amax().max(1.0))
}

/// The split fast path is the same map as the general Newton path (they solve
/// algebraically equivalent equations; 1e-14 per step allows the different
/// rounding of the two residuals).
fn paths_agree<G, R, L, const N: usize>(l: L, x0: GroupState<G, N>, h: f64)
where
    G: GroupFamily<N>,
    R: Retraction<N, Family = G>,
    L: veselov::lgvi::SplitReducedLagrangian<G, N> + Clone,
{
    let mut general = LieGroupIntegrator::<G, R, L, N>::new(l.clone(), h).expect("valid");
    let mut split = SplitLieIntegrator::<G, R, L, N>::new(l, h).expect("valid");
    let mut x = x0;
    for k in 0..50 {
        let (a, _) = general.step(k, &x).expect("general step");
        let (b, _) = split.step(k, &x).expect("split step");
        assert!(max_diff(&a, &b) <= 1e-14, "step {k}: {}", max_diff(&a, &b));
        x = b;
    }
}

#[test]
fn split_path_equals_general_path() {
    paths_agree::<Rotations, CayleyMap, _, 3>(body(), so3_state(), 0.05);
    paths_agree::<Rotations, ExpMap, _, 3>(body(), so3_state(), 0.05);
    paths_agree::<Rotations, CayleyMap, _, 3>(top(), so3_state(), 0.02);
    paths_agree::<Rotations, ExpMap, _, 3>(top(), so3_state(), 0.02);
    paths_agree::<RigidMotions, CayleyMap, _, 6>(body_se3(), se3_state(), 0.05);
    paths_agree::<RigidMotions, ExpMap, _, 6>(body_se3(), se3_state(), 0.05);
}

/// Stationarity of the discrete action, checked without the momentum
/// formulas: for three consecutive configurations g₀, g₁, g₂ of a computed
/// trajectory, S(ε) = L_d(g₀, ξ₀(ε)) + L_d(g₁τ(εη), ξ₁(ε)) with
/// ξ₀(ε) = τ⁻¹(g₀⁻¹g₁τ(εη))/h and ξ₁(ε) = τ⁻¹(τ(−εη)g₁⁻¹g₂)/h has
/// dS/dε = 0 at ε = 0. Central differences with ε = 1e-5 have truncation
/// error ~ε²·|S'''| ≈ 1e-10 and rounding ~ ε_mach·|S|/ε ≈ 1e-11·|S|.
fn action_is_stationary<G, R, L, const N: usize>(l: L, x0: GroupState<G, N>, h: f64)
where
    G: GroupFamily<N>,
    R: Retraction<N, Family = G>,
    L: veselov::lgvi::SplitReducedLagrangian<G, N> + Clone,
{
    let mut map = SplitLieIntegrator::<G, R, L, N>::new(l.clone(), h).expect("valid");
    let x1 = map.step(0, &x0).expect("step").0;
    let x2 = map.step(1, &x1).expect("step").0;
    let action = |eta: &SVector<f64, N>| -> f64 {
        let g1 = x1.g.compose(&R::tau(eta));
        let xi0 = R::tau_inv(&x0.g.inverse().compose(&g1)).expect("small step") / h;
        let xi1 = R::tau_inv(&g1.inverse().compose(&x2.g)).expect("small step") / h;
        discrete_lagrangian::<G, R, L, f64, N>(&l, &x0.g, &xi0, h)
            + discrete_lagrangian::<G, R, L, f64, N>(&l, &g1, &xi1, h)
    };
    let scale = action(&SVector::zeros()).abs().max(1.0);
    let eps = 1e-5;
    for i in 0..N {
        let e = SVector::<f64, N>::from_fn(|r, _| if r == i { eps } else { 0.0 });
        let derivative = (action(&e) - action(&-e)) / (2.0 * eps);
        assert!(
            derivative.abs() <= 1e-8 * scale,
            "direction {i}: dS/dε = {derivative:e}"
        );
    }
}

#[test]
fn discrete_action_is_stationary_along_computed_trajectories() {
    action_is_stationary::<Rotations, CayleyMap, _, 3>(top(), so3_state(), 0.05);
    action_is_stationary::<Rotations, ExpMap, _, 3>(top(), so3_state(), 0.05);
    action_is_stationary::<RigidMotions, CayleyMap, _, 6>(body_se3(), se3_state(), 0.05);
    action_is_stationary::<RigidMotions, ExpMap, _, 6>(body_se3(), se3_state(), 0.05);
}

/// Free rigid body, 10⁶ steps: spatial angular momentum conserved to 1e-13
/// relative, ‖RᵀR − I‖ ≤ 1e-13 at every step, energy bounded without drift
/// (max error in the last tenth within 10% of the first tenth).
#[test]
fn free_rigid_body_long_run() {
    let l = body();
    let x0 = so3_state();
    let mut map = SplitLieIntegrator::<Rotations, CayleyMap, _, 3>::new(l, 0.01).expect("valid");
    let pi0 = spatial_momentum(&x0);
    let e0 = energy(&l, &x0).expect("energy");
    let steps = 1_000_000;
    let tenth = steps / 10;
    let (mut momentum, mut orth) = (0.0_f64, 0.0_f64);
    let (mut first, mut last) = (0.0_f64, 0.0_f64);
    let run = integrate_group_observed(&mut map, x0, steps, steps, |k, x| {
        momentum = momentum.max((spatial_momentum(x) - pi0).amax() / pi0.amax());
        orth = orth.max(Rotations::orthogonality_defect(&x.g));
        if k <= tenth || k > steps - tenth {
            let de = (0.5 * x.mu.dot(&(inertia().try_inverse().expect("SPD") * x.mu)) - e0).abs();
            if k <= tenth {
                first = first.max(de);
            } else {
                last = last.max(de);
            }
        }
    });
    assert!(run.failure.is_none(), "{:?}", run.failure);
    assert_eq!(run.steps, steps);
    println!("momentum {momentum:e}, orthogonality {orth:e}, energy first {first:e} last {last:e}");
    assert!(momentum <= 1e-13, "spatial momentum drift {momentum:e}");
    assert!(orth <= 1e-13, "orthogonality {orth:e}");
    assert!(
        first > 0.0 && last <= 1.1 * first,
        "energy error first tenth {first:e}, last tenth {last:e}"
    );
}

/// Heavy top: the vertical component of the spatial angular momentum is
/// conserved to round-off; the energy error stays bounded.
#[test]
fn heavy_top_vertical_momentum() {
    let l = top();
    let x0 = so3_state();
    for retraction in ["cayley", "exp"] {
        let steps = 100_000;
        let mut vertical = 0.0_f64;
        let mut energy_error = 0.0_f64;
        let pz0 = spatial_momentum(&x0)[2];
        let e0 = energy(&l, &x0).expect("energy");
        let observe = |_: usize, x: &GroupState<Rotations, 3>| {
            vertical = vertical.max((spatial_momentum(x)[2] - pz0).abs() / spatial_momentum(&x0).amax());
            energy_error = energy_error.max((energy(&l, x).expect("energy") - e0).abs() / e0.abs());
        };
        let run = if retraction == "cayley" {
            let mut map = SplitLieIntegrator::<Rotations, CayleyMap, _, 3>::new(l, 0.005).expect("valid");
            integrate_group_observed(&mut map, x0, steps, steps, observe)
        } else {
            let mut map = SplitLieIntegrator::<Rotations, ExpMap, _, 3>::new(l, 0.005).expect("valid");
            integrate_group_observed(&mut map, x0, steps, steps, observe)
        };
        assert!(run.failure.is_none(), "{:?}", run.failure);
        println!("{retraction}: vertical momentum {vertical:e}, energy {energy_error:e}");
        assert!(vertical <= 1e-13, "{retraction}: vertical momentum drift {vertical:e}");
        // Second order with h = 0.005 on a top whose energy is O(10):
        // a relative error of 1e-3 would signal a broken scheme.
        assert!(energy_error <= 1e-3, "{retraction}: energy error {energy_error:e}");
    }
}

/// SE(3) free flight: the six-component spatial momentum is conserved. The
/// integrator keeps π bit for bit; what is measured is the round trip
/// μ = Ad_gᵀπ, π = Ad*_{g⁻¹}μ, whose rounding grows like ε·|x|·|f| as the body
/// flies away (|x| ≈ 500 at t = 1000), hence 1e-13 rather than a few ε.
#[test]
fn se3_free_flight_spatial_momentum() {
    let l = body_se3();
    let x0 = se3_state();
    let mut map = SplitLieIntegrator::<RigidMotions, CayleyMap, _, 6>::new(l, 0.01).expect("valid");
    let p0 = spatial_momentum(&x0);
    let mut drift = 0.0_f64;
    let run = integrate_group_observed(&mut map, x0, 100_000, 100_000, |_, x| {
        drift = drift.max((spatial_momentum(x) - p0).amax() / p0.amax());
    });
    assert!(run.failure.is_none());
    println!("SE(3) spatial momentum drift {drift:e}");
    assert!(drift <= 1e-13, "{drift:e}");
}

/// Order 2 against the RK4 reference on the nonlinear heavy top and the free
/// body (T = 2; reference with 2·10⁴ steps, error ~1e-14).
#[test]
fn order_two_against_reference() {
    fn study<R: Retraction<3, Family = Rotations>, L>(l: L) -> f64
    where
        L: veselov::lgvi::SplitReducedLagrangian<Rotations, 3> + Clone,
    {
        let x0 = so3_state();
        let t_end = 2.0;
        let reference = rk4_group_reference::<Rotations, R, L, 3>(&l, &x0, t_end, 20_000).expect("reference");
        let (mut hs, mut errs) = (vec![], vec![]);
        for n in [40usize, 80, 160, 320, 640] {
            let h = t_end / n as f64;
            let mut map = SplitLieIntegrator::<Rotations, R, L, 3>::new(l.clone(), h).expect("valid");
            let run = veselov::lgvi::integrate_group(&mut map, x0, n, n);
            assert!(run.failure.is_none());
            hs.push(h);
            errs.push(max_diff(run.last(), &reference));
        }
        let fit = fit_order(&hs, &errs, 1e-12).expect("fit");
        println!("errors {errs:?} order {}", fit.order);
        fit.order
    }
    for order in [
        study::<CayleyMap, _>(top()),
        study::<ExpMap, _>(top()),
        study::<CayleyMap, _>(body()),
        study::<ExpMap, _>(body()),
    ] {
        assert!((order - 2.0).abs() <= 0.2, "order {order}");
    }
}

/// The step map preserves the canonical symplectic form of T*G in
/// left-trivialised coordinates; the exact Jacobian comes from the implicit
/// function theorem. Defect ≤ 1e-11 at several states.
#[test]
fn symplectic_in_trivialised_coordinates() {
    fn check<G, R, L, const N: usize>(l: L, x0: GroupState<G, N>, h: f64)
    where
        G: GroupFamily<N>,
        R: Retraction<N, Family = G>,
        L: veselov::lgvi::SplitReducedLagrangian<G, N> + Clone,
    {
        let mut map = LieGroupIntegrator::<G, R, L, N>::new(l, h).expect("valid");
        let mut x = x0;
        for k in 0..5 {
            let (next, jac) = map.flow_jacobian(&x).expect("jacobian");
            let defect = lie_symplecticity_defect::<G, N>(&jac, &x.mu, &next.mu);
            let scale = (jac.qq.amax() + jac.qp.amax() + jac.pq.amax() + jac.pp.amax()).powi(2);
            println!("defect {defect:e} (scale {scale:e})");
            assert!(defect <= 1e-11, "step {k}: defect {defect:e}");
            // Not vacuous: the Jacobian is far from the identity and the
            // naive flat form [[0, −I], [I, 0]] is not preserved.
            let flat = lie_symplecticity_defect::<G, N>(&jac, &SVector::zeros(), &SVector::zeros());
            assert!(flat > 1e-4, "flat form defect {flat:e} should be visible");
            x = map.step(k, &x).expect("step").0;
        }
    }
    check::<Rotations, CayleyMap, _, 3>(top(), so3_state(), 0.1);
    check::<Rotations, ExpMap, _, 3>(top(), so3_state(), 0.1);
    check::<Rotations, CayleyMap, _, 3>(body(), so3_state(), 0.1);
    check::<RigidMotions, CayleyMap, _, 6>(body_se3(), se3_state(), 0.1);
    check::<RigidMotions, ExpMap, _, 6>(body_se3(), se3_state(), 0.1);
}

#[test]
fn bad_input_is_a_typed_error() {
    let not_spd = Matrix3::new(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0);
    let msg = FreeRigidBody::new(not_spd).expect_err("not SPD").to_string();
    assert!(msg.contains("inertia") && msg.contains("positive definite"), "{msg}");
    let asym = Matrix3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    assert!(
        FreeRigidBody::new(asym)
            .expect_err("asymmetric")
            .to_string()
            .contains("symmetric")
    );
    assert!(
        HeavyTop::new(inertia(), -1.0, Vector3::zeros(), 9.81)
            .expect_err("mass")
            .to_string()
            .contains("mass")
    );
    assert!(
        HeavyTop::new(inertia(), 1.0, Vector3::zeros(), f64::NAN)
            .expect_err("gravity")
            .to_string()
            .contains("gravity")
    );
    let err = SplitLieIntegrator::<Rotations, CayleyMap, _, 3>::new(body(), -0.1)
        .err()
        .expect("bad step");
    assert!(err.to_string().contains("h = -0.1"), "{err}");
    // A non-orthogonal initial attitude is refused by the driver, which keeps
    // the initial state.
    let bad = GroupState::<Rotations, 3>::new(
        0.0,
        veselov::lie::SO3::from_matrix_unchecked(Matrix3::identity() * 1.01),
        Vector3::new(1.0, 0.0, 0.0),
    );
    let mut map = SplitLieIntegrator::<Rotations, CayleyMap, _, 3>::new(body(), 0.1).expect("valid");
    let run = veselov::lgvi::integrate_group(&mut map, bad, 10, 1);
    assert_eq!(run.states.len(), 1);
    assert!(run.failure.expect("refused").to_string().contains("`g`"));
}

/// The implicit-function-theorem flow Jacobian agrees with central finite
/// differences of the step map (ε = 1e-6: truncation ~ε² and rounding
/// ~1e-16/ε, so agreement to 1e-8 is expected and 1e-7 asserted).
#[test]
fn flow_jacobian_matches_finite_differences() {
    let l = top();
    let x0 = so3_state();
    let h = 0.1;
    let mut map = LieGroupIntegrator::<Rotations, CayleyMap, _, 3>::new(l, h).expect("valid");
    let (next, jac) = map.flow_jacobian(&x0).expect("jacobian");
    let eps = 1e-6;
    for c in 0..6 {
        let mut d = SVector::<f64, 3>::zeros();
        d[c % 3] = eps;
        let shifted = |s: f64| {
            let (g, mu) = if c < 3 {
                (x0.g.compose(&CayleyMap::tau(&(d * s))), x0.mu)
            } else {
                (x0.g, x0.mu + d * s)
            };
            let mut fresh = LieGroupIntegrator::<Rotations, CayleyMap, _, 3>::new(l, h).expect("valid");
            fresh.step(0, &GroupState::new(0.0, g, mu)).expect("step").0
        };
        let (p, m) = (shifted(1.0), shifted(-1.0));
        let eta = |x: &GroupState<Rotations, 3>| CayleyMap::tau_inv(&next.g.inverse().compose(&x.g)).expect("near");
        let deta: SVector<f64, 3> = (eta(&p) - eta(&m)) / (2.0 * eps);
        let dmu: SVector<f64, 3> = (p.mu - m.mu) / (2.0 * eps);
        let (ja, jb) = if c < 3 {
            (jac.qq.column(c).into_owned(), jac.pq.column(c).into_owned())
        } else {
            (jac.qp.column(c - 3).into_owned(), jac.pp.column(c - 3).into_owned())
        };
        assert!((deta - ja).amax() <= 1e-7, "column {c}: {deta:?} vs {ja:?}");
        assert!((dmu - jb).amax() <= 1e-7, "column {c}: {dmu:?} vs {jb:?}");
    }
}

/// With a large step the fixed-point iteration of the split path does not
/// contract (factor ≈ h‖𝕀⁻¹‖|μ|/2 > 1/2); it falls back to Newton, flags the
/// step, and still takes the same step as the general path.
#[test]
fn split_path_falls_back_to_newton_for_large_steps() {
    let l = body();
    let x0 = GroupState::<Rotations, 3>::new(
        0.0,
        so3::exp(&Vector3::new(0.3, -0.7, 0.4)),
        Vector3::new(8.0, -9.0, 7.0),
    );
    let h = 0.5;
    let mut split = SplitLieIntegrator::<Rotations, CayleyMap, _, 3>::new(l, h).expect("valid");
    let mut general = LieGroupIntegrator::<Rotations, CayleyMap, _, 3>::new(l, h).expect("valid");
    let (a, stats) = split.step(0, &x0).expect("split step");
    let (b, _) = general.step(0, &x0).expect("general step");
    assert!(stats.fallback, "expected a Newton fallback");
    assert!(max_diff(&a, &b) <= 1e-13, "{}", max_diff(&a, &b));
}

/// The free rigid body against the exact Euler-top solution (Jacobi elliptic
/// functions) for the body angular velocity: the exact formula agrees with
/// the independent RK4 reference to 1e-10, and the integrator's body momentum
/// converges to it at order 2 (nonlinear: the parameter is m = k² ≈ 0.52).
#[test]
fn free_rigid_body_against_the_exact_euler_top() {
    let inertia = Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0));
    let body = FreeRigidBody::new(inertia).expect("valid");
    let omega0 = Vector3::new(1.0, 0.0, 0.8);
    let x0 = GroupState::<Rotations, 3>::new(0.0, so3::exp(&Vector3::new(0.2, 0.1, -0.3)), inertia * omega0);
    let t_end = 3.0;
    let exact = inertia * body.exact_body_angular_velocity(&omega0, t_end).expect("exact");
    let rk4 = rk4_group_reference::<Rotations, CayleyMap, _, 3>(&body, &x0, t_end, 30_000).expect("reference");
    assert!(
        (rk4.mu - exact).amax() <= 1e-10,
        "exact vs RK4: {:e}",
        (rk4.mu - exact).amax()
    );
    let (mut hs, mut errs) = (vec![], vec![]);
    for n in [60usize, 120, 240, 480] {
        let h = t_end / n as f64;
        let mut map = SplitLieIntegrator::<Rotations, CayleyMap, _, 3>::new(body, h).expect("valid");
        let run = veselov::lgvi::integrate_group(&mut map, x0, n, n);
        hs.push(h);
        errs.push((run.last().mu - exact).amax());
    }
    let fit = fit_order(&hs, &errs, 1e-12).expect("fit");
    println!("Euler top: errors {errs:?}, order {}", fit.order);
    assert!((fit.order - 2.0).abs() <= 0.2, "order {}", fit.order);
    // Bad input is a typed error.
    assert!(
        body.exact_body_angular_velocity(&Vector3::new(1.0, 0.5, 0.8), 1.0)
            .is_err()
    );
}
