//! Tests of [`super`]: the group laws, exp/log and Cayley round trips,
//! derivatives against finite differences and dual numbers, the adjoint
//! identities, geodesics and the cut locus.

use super::*;
use crate::lie::so3::tests::{rotation, rotvec, rotvec_moderate, unit};
use num_dual::{Dual2_64, Dual64};
use proptest::prelude::*;
use std::f64::consts::PI;

const EPS: f64 = f64::EPSILON;

fn translation() -> impl Strategy<Value = Vector3<f64>> {
    (-2.0..2.0f64, -2.0..2.0f64, -2.0..2.0f64).prop_map(|(a, b, c)| Vector3::new(a, b, c))
}

fn twist() -> impl Strategy<Value = Vector6<f64>> {
    (rotvec(), translation()).prop_map(|(w, v)| join(&w, &v))
}

fn twist_moderate() -> impl Strategy<Value = Vector6<f64>> {
    (rotvec_moderate(), translation()).prop_map(|(w, v)| join(&w, &v))
}

fn element() -> impl Strategy<Value = SE3<f64>> {
    (rotation(), translation()).prop_map(|(r, x)| SE3::new(r, x))
}

fn dir6() -> impl Strategy<Value = Vector6<f64>> {
    (unit(), unit(), -1.0..1.0f64).prop_map(|(a, b, s)| join(&a, &(b * s)))
}

fn maxabs<const R: usize, const C: usize>(m: &nalgebra::SMatrix<f64, R, C>) -> f64 {
    m.abs().max()
}

/// Matrix exponential by scaling and squaring of a 20-term Taylor sum
/// (independent reference for `exp`).
fn expm(a: &Matrix4<f64>) -> Matrix4<f64> {
    let norm = a.abs().max() * 4.0;
    let s = if norm > 0.5 {
        (norm / 0.5).log2().ceil() as i32
    } else {
        0
    };
    let b = a / 2f64.powi(s);
    let (mut term, mut sum) = (Matrix4::identity(), Matrix4::identity());
    for k in 1..20 {
        term = term * b / k as f64;
        sum += term;
    }
    for _ in 0..s {
        sum = sum * sum;
    }
    sum
}

/// Cayley vector with the same rotation angle as the test angle |ω|
/// (so rotvec()'s near-π cases are near-π for the Cayley map too).
fn cayley_twist(xi: &Vector6<f64>) -> Vector6<f64> {
    let (w, v) = split(xi);
    let t = w.norm();
    let wc = if t > 0.0 { w * (2.0 * (t / 2.0).tan() / t) } else { w };
    join(&wc, &v)
}

proptest! {
    #![proptest_config(crate::lie::test_config())]

    /// g⁻¹h without the inverse: the rotation bit for bit as
    /// inverse-then-compose; the translation Rᵀ(y − x) against Rᵀy − Rᵀx,
    /// each within γ₃Σ_k|R_ki||·| ≤ 3√3ε|·|∞ per dot product (a unit column
    /// has Σ|R_ki| ≤ √3) plus one rounding of the difference: 16ε(|x|∞ + |y|∞).
    #[test]
    fn between_is_inverse_then_compose(g in element(), h in element()) {
        let (fused, reference) = (g.between(&h), g.inverse().compose(&h));
        prop_assert_eq!(fused.rotation().matrix(), reference.rotation().matrix());
        let bound = 16.0 * EPS * (g.translation().amax() + h.translation().amax());
        prop_assert!((fused.translation() - reference.translation()).amax() <= bound);
    }

    /// exp agrees with the 4×4 matrix exponential of hat(ξ); |ξ| ≤ ~4, the
    /// reference loses ~10 ε per squaring: tolerance 1e-13.
    #[test]
    fn exp_is_matrix_exponential(xi in twist()) {
        prop_assert!(maxabs(&(exp(&xi).to_matrix() - expm(&hat(&xi)))) <= 1e-13);
    }

    /// cay agrees with (I − ξ̂/2)⁻¹(I + ξ̂/2); cond(I − ξ̂/2) ≤ 1 + |ξ|²/4 ≤ 8.
    #[test]
    fn cay_is_matrix_cayley(xi in twist()) {
        let h = hat(&xi) * 0.5;
        let m = (Matrix4::identity() - h).try_inverse().expect("always invertible") * (Matrix4::identity() + h);
        prop_assert!(maxabs(&(cay(&xi).to_matrix() - m)) <= 64.0 * EPS);
    }

    /// Round trips τ⁻¹∘τ = id. The rotational part inherits the SO(3)
    /// bounds; the translation adds |J⁻¹| |x| ε-level error, and for the
    /// Cayley map near π the conditioning 1/sin θ of the rotation vector.
    #[test]
    fn round_trips(xi in twist()) {
        let back = log(&exp(&xi)).expect("below π");
        prop_assert!((back - xi).norm() <= 64.0 * EPS * (1.0 + xi.norm()), "exp err {}", (back - xi).norm());
        let xc = cayley_twist(&xi);
        let theta = split(&xi).0.norm();
        let cond = 1.0 + 1.0 / theta.sin().max(1e-300);
        let back = cay_inv(&cay(&xc)).expect("below π");
        prop_assert!((back - xc).norm() <= 64.0 * EPS * (1.0 + xc.norm()) * cond, "cay err {}", (back - xc).norm());
    }

    /// τ∘τ⁻¹ = id on random elements (uniform rotations and exp of the
    /// `twist` mix, angles 0 … π − 1e-5). exp: a few ε. Cayley: the
    /// translation is recovered through v = (I − ω̂/2)x and x = (I − ω̂/2)⁻¹v,
    /// whose condition number is √(1 + |ω|²/4) ≤ 1 + tan(θ/2) (|ω| = 2tan(θ/2)),
    /// so the bound is 16ε(1 + |x|)(1 + tan(θ/2)).
    #[test]
    fn inverse_then_forward(g in prop_oneof![element(), twist().prop_map(|x| exp(&x))]) {
        let theta = g.rotation().angle();
        prop_assume!(theta < PI - 2.0 * crate::lie::CUT_LOCUS_MARGIN);
        let scale = 1.0 + g.translation().norm();
        let e = exp(&log(&g).expect("ok"));
        prop_assert!(maxabs(&(e.to_matrix() - g.to_matrix())) <= 16.0 * EPS * scale);
        let c = cay(&cay_inv(&g).expect("ok"));
        let tol = 16.0 * EPS * scale * (1.0 + (theta / 2.0).tan());
        prop_assert!(maxabs(&(c.to_matrix() - g.to_matrix())) <= tol);
    }

    /// Right-trivialised derivative vs central differences:
    /// τ⁻¹(τ(ξ + εδ) τ(ξ)⁻¹) = ε dτ_ξ δ + O(ε²); ε = 1e-5, tolerance 1e-8.
    #[test]
    fn dtau_finite_differences(xi in twist_moderate(), d in dir6()) {
        let h = 1e-5;
        let fd = |tau: fn(&Vector6<f64>) -> SE3<f64>, inv: fn(&SE3<f64>) -> Result<Vector6<f64>, LieError>| {
            let g0 = tau(&xi).inverse();
            let p = inv(&tau(&(xi + d * h)).compose(&g0)).expect("small");
            let m = inv(&tau(&(xi - d * h)).compose(&g0)).expect("small");
            (p - m) / (2.0 * h)
        };
        let e = fd(exp, log) - dexp(&xi) * d;
        prop_assert!(e.norm() <= 1e-8, "dexp err {}", e.norm());
        let c = fd(cay, cay_inv) - dcay(&xi) * d;
        prop_assert!(c.norm() <= 1e-8, "dcay err {}", c.norm());
    }

    /// Exact version through Dual64: (d/dt τ(ξ + tδ)) τ(ξ)⁻¹ = hat(dτ_ξ δ)
    /// to round-off (‖dτ‖ ≲ (1 + |ξ|)²; tol 64ε(1 + |ξ|)³).
    #[test]
    fn dtau_exact_via_dual(xi in twist(), d in dir6()) {
        let xd = xi.map(Dual64::from) + d.map(|e| Dual64::new(0.0, e));
        let tol = 64.0 * EPS * (1.0 + xi.norm()).powi(3);
        for (gd, g, dt) in [(exp(&xd), exp(&xi), dexp(&xi)), (cay(&xd), cay(&xi), dcay(&xi))] {
            let deriv = gd.to_matrix().map(|e| e.eps) * g.inverse().to_matrix();
            prop_assert!(maxabs(&(deriv - hat(&(dt * d)))) <= tol, "err {}", maxabs(&(deriv - hat(&(dt * d)))));
        }
    }

    /// dτ⁻¹ = (dτ)⁻¹. Block entries are O(1 + |ω|²) on the diagonal and
    /// O((1 + |ω|²)|v|) off it, so the products carry a few ε times
    /// (1 + |ω|²)(1 + |v|)²; tolerance 16ε × that.
    #[test]
    fn dtau_inv_is_inverse(xi in twist()) {
        let i6 = Matrix6::identity();
        let (w, v) = split(&xi);
        let tol = 16.0 * EPS * (1.0 + w.norm_squared()) * (1.0 + v.norm()).powi(2);
        prop_assert!(maxabs(&(dexp_inv(&xi) * dexp(&xi) - i6)) <= tol);
        prop_assert!(maxabs(&(dexp(&xi) * dexp_inv(&xi) - i6)) <= tol);
        prop_assert!(maxabs(&(dcay_inv(&xi) * dcay(&xi) - i6)) <= tol);
        prop_assert!(maxabs(&(dcay(&xi) * dcay_inv(&xi) - i6)) <= tol);
    }

    /// dcay in 4×4 form: dcay_ξ(δ) = (I − ξ̂/2)⁻¹ δ̂ (I + ξ̂/2)⁻¹.
    #[test]
    fn dcay_matrix_form(xi in twist(), d in dir6()) {
        let h = hat(&xi) * 0.5;
        let a = (Matrix4::identity() - h).try_inverse().expect("invertible");
        let b = (Matrix4::identity() + h).try_inverse().expect("invertible");
        prop_assert!((vee(&(a * hat(&d) * b)) - dcay(&xi) * d).norm() <= 64.0 * EPS);
    }

    /// Left and right trivialisations are related by Ad: for both
    /// retractions Ad_{τ(ξ)} = dτ_ξ (dτ_{−ξ})⁻¹ (since τ(−ξ) = τ(ξ)⁻¹).
    #[test]
    fn adjoint_of_retraction(xi in twist_moderate()) {
        let tol = 1e-13 * (1.0 + xi.norm()).powi(3);
        prop_assert!(maxabs(&(adjoint(&exp(&xi)) - dexp(&xi) * dexp_inv(&(-xi)))) <= tol);
        prop_assert!(maxabs(&(adjoint(&cay(&xi)) - dcay(&xi) * dcay_inv(&(-xi)))) <= tol);
    }

    /// Ad homomorphism, Ad_g ξ̂ = g ξ̂ g⁻¹, ad = bracket, Ad* pairing,
    /// coadjoint homomorphism, and note 000 §12's Ad*_{(gτ)⁻¹}Ad*_τ = Ad*_{g⁻¹}.
    #[test]
    fn adjoint_identities(g in element(), h in element(), xi in dir6(), eta in dir6(), mu in dir6()) {
        let tol = 64.0 * EPS * 9.0;
        prop_assert!(maxabs(&(adjoint(&g.compose(&h)) - adjoint(&g) * adjoint(&h))) <= tol);
        let lhs = hat(&(adjoint(&g) * xi));
        let rhs = g.to_matrix() * hat(&xi) * g.inverse().to_matrix();
        prop_assert!(maxabs(&(lhs - rhs)) <= tol);
        let br = hat(&xi) * hat(&eta) - hat(&eta) * hat(&xi);
        prop_assert!((ad(&xi) * eta - vee(&br)).norm() <= 16.0 * EPS);
        prop_assert!(maxabs(&(hat(&(ad(&xi) * eta)) - br)) <= 16.0 * EPS);
        let pair = (ad_star_matrix(&g) * mu).dot(&xi) - mu.dot(&(adjoint(&g) * xi));
        prop_assert!(pair.abs() <= tol);
        prop_assert!(((ad_star(&xi) * mu).dot(&eta) - mu.dot(&(ad(&xi) * eta))).abs() <= 16.0 * EPS);
        prop_assert!(maxabs(&(coadjoint(&g.compose(&h)) - coadjoint(&g) * coadjoint(&h))) <= tol);
        prop_assert!(maxabs(&(coadjoint(&g) - adjoint(&g.inverse()).transpose())) <= tol);
        prop_assert!(maxabs(&(ad_star_matrix(&g.compose(&h)) - ad_star_matrix(&h) * ad_star_matrix(&g))) <= tol);
        let tau = cay(&(eta * 0.7));
        let lhs = ad_star_matrix(&g.compose(&tau).inverse()) * ad_star_matrix(&tau);
        prop_assert!(maxabs(&(lhs - ad_star_matrix(&g.inverse()))) <= tol);
        // Note 000 §13: Ad*_g(m; f) = (Rᵀ(m − x × f); Rᵀ f), coadjoint (m; f) = (Rm + x × Rf; Rf).
        let (m, f) = split(&mu);
        let (r, x) = (g.rotation().matrix(), g.translation());
        let expect = join(&(r.transpose() * (m - x.cross(&f))), &(r.transpose() * f));
        prop_assert!((ad_star_matrix(&g) * mu - expect).norm() <= tol);
        let expect = join(&(r * m + x.cross(&(r * f))), &(r * f));
        prop_assert!((coadjoint(&g) * mu - expect).norm() <= tol);
        // The trait defaults give the same matrices.
        prop_assert!(maxabs(&(LieGroup::coadjoint(&g) - coadjoint(&g))) <= tol);
    }

    /// Geodesic endpoints, constant speed along the screw, left invariance of
    /// the distance.
    #[test]
    fn geodesic_and_distance(g in element(), h in element(), k in element(), a in 0.0..1.0f64, b in 0.0..1.0f64) {
        prop_assume!(g.between(&h).rotation().angle() < PI - 1e-3);
        let g0 = geodesic(&g, &h, 0.0).expect("ok");
        let g1 = geodesic(&g, &h, 1.0).expect("ok");
        prop_assert!(maxabs(&(g0.to_matrix() - g.to_matrix())) <= 64.0 * EPS);
        prop_assert!(maxabs(&(g1.to_matrix() - h.to_matrix())) <= 1e-12);
        let d = distance(&g, &h).expect("ok");
        let (ga, gb) = (geodesic(&g, &h, a).expect("ok"), geodesic(&g, &h, b).expect("ok"));
        prop_assert!((distance(&ga, &gb).expect("ok") - (a - b).abs() * d).abs() <= 1e-11);
        let dk = distance(&k.compose(&g), &k.compose(&h)).expect("ok");
        prop_assert!((dk - d).abs() <= 1e-11);
    }
}

/// d/dt Ad_{exp(tξ)}|₀ = ad_ξ and d/dt coadjoint(exp(tξ))|₀ = −ad_ξᵀ, exactly
/// through Dual64; second derivative of exp at 0 is ξ̂² (Dual2).
#[test]
fn infinitesimal_adjoint_and_second_derivatives() {
    let xi = Vector6::new(0.3, -0.7, 0.2, 1.1, -0.4, 0.6);
    let xd = xi.map(|e| Dual64::new(0.0, e));
    let g = exp(&xd);
    assert!(maxabs(&(adjoint(&g).map(|e| e.eps) - ad(&xi))) <= 4.0 * EPS);
    assert!(maxabs(&(coadjoint(&g).map(|e| e.eps) + ad_star(&xi))) <= 4.0 * EPS);
    for &t in &[0.0, 1e-9] {
        let base = xi * t;
        let x2 = base.map(Dual2_64::from) + xi.map(|e| Dual2_64::new(0.0, e, 0.0));
        let h2 = hat(&xi) * hat(&xi);
        for (g2, g, dt) in [(exp(&x2), exp(&base), dexp(&base)), (cay(&x2), cay(&base), dcay(&base))] {
            let m = g2.to_matrix();
            let first = hat(&(dt * xi)) * g.to_matrix();
            assert!(maxabs(&(m.map(|e| e.v1) - first)) <= 4.0 * EPS);
            if t == 0.0 {
                assert!(maxabs(&(m.map(|e| e.v2) - h2)) <= 4.0 * EPS);
            }
        }
        // log∘exp and cay⁻¹∘cay are the identity: derivative ξ, second derivative 0.
        let back = log(&exp(&x2)).expect("ok");
        assert!((back.map(|e| e.v1) - xi).norm() <= 8.0 * EPS);
        assert!(back.map(|e| e.v2).norm() <= 1e-14);
        let back = cay_inv(&cay(&x2)).expect("ok");
        assert!((back.map(|e| e.v1) - xi).norm() <= 8.0 * EPS);
        assert!(back.map(|e| e.v2).norm() <= 1e-14);
    }
}

/// Dual derivative of log at a generic element against a central difference
/// of log along g ↦ exp(εδ) g (independent of dexp⁻¹), and against dexp⁻¹.
#[test]
fn log_dual_vs_finite_difference() {
    let xi = Vector6::new(0.9, -0.4, 1.3, 0.5, 2.0, -1.0);
    let d = Vector6::new(0.2, 0.7, -0.1, -0.3, 0.4, 0.9);
    let g = exp(&xi);
    let gd = SE3::new(
        SO3::from_matrix_unchecked(g.rotation().matrix().map(Dual64::from)),
        g.translation().map(Dual64::from),
    );
    let ad = log(&exp(&d.map(|e| Dual64::new(0.0, e))).compose(&gd))
        .expect("ok")
        .map(|e| e.eps);
    let h = 1e-5;
    let fd = (log(&exp(&(d * h)).compose(&g)).expect("ok") - log(&exp(&(-d * h)).compose(&g)).expect("ok")) / (2.0 * h);
    assert!((ad - fd).norm() <= 1e-8);
    assert!((ad - dexp_inv(&xi) * d).norm() <= 1e-13);
    let ad = cay_inv(&exp(&d.map(|e| Dual64::new(0.0, e))).compose(&gd))
        .expect("ok")
        .map(|e| e.eps);
    let w = cay_inv(&g).expect("ok");
    assert!((ad - dcay_inv(&w) * d).norm() <= 1e-12);
}

/// The published variant x = 2/(4+|ω|²)(2I + ω̂)v differs from the matrix
/// Cayley map whenever ω·v ≠ 0 (note 000 §13 pitfall).
#[test]
fn cayley_translation_pitfall() {
    let xi = Vector6::new(0.4, 0.3, -0.5, 1.0, 0.2, 0.3);
    let (w, v) = split(&xi);
    let variant: Vector3<f64> = (Matrix3::identity() * 2.0 + hat3(&w)) * v * (2.0 / (4.0 + w.norm_squared()));
    let h = hat(&xi) * 0.5;
    let m = (Matrix4::identity() - h).try_inverse().expect("invertible") * (Matrix4::identity() + h);
    let exact = m.fixed_view::<3, 1>(0, 3).into_owned();
    assert!((cay(&xi).translation() - exact).norm() <= 8.0 * EPS);
    assert!((variant - exact).norm() > 1e-2);
}

/// Note 000 §15.3 data: η₀⁰ = cay⁻¹(g₀⁰⁻¹g₁⁰)/Δs = E6 exactly, and the s = 0 end
/// g₀ʲ⁺¹ = g₀ʲ cay(Δt ξ₀) with ω ∥ v ∥ E2 translates by exactly Δt v per
/// step while rotating about E2 by 2 atan(0.85 Δt/2) per step.
#[test]
fn note_000_beam_data() {
    let (ds, dt) = (0.02, 0.04);
    let g1 = SE3::from_translation(Vector3::new(0.0, 0.0, ds));
    let eta = cay_inv(&SE3::<f64>::identity().between(&g1)).expect("ok") / ds;
    assert_eq!(eta, Vector6::new(0.0, 0.0, 0.0, 0.0, 0.0, 1.0));
    let xi0 = Vector6::new(0.0, -0.85, 0.0, 0.0, -0.1, 0.0);
    let mut g = SE3::identity();
    for _ in 0..3 {
        g = g.compose(&cay(&(xi0 * dt)));
    }
    assert!((g.translation() - Vector3::new(0.0, -3.0 * 0.1 * dt, 0.0)).norm() <= 8.0 * EPS);
    let angle = 3.0 * 2.0 * (0.85 * dt / 2.0).atan();
    let expect = so3::exp(&Vector3::new(0.0, -angle, 0.0));
    assert!(maxabs(&(g.rotation().matrix() - expect.matrix())) <= 8.0 * EPS);
}

#[test]
fn cut_locus_and_constructors() {
    let n = Vector3::new(0.0, 0.6, 0.8);
    let g = SE3::new(so3::exp(&(n * (PI - 1e-12))), Vector3::new(1.0, 2.0, 3.0));
    assert!(matches!(log(&g), Err(LieError::NearCutLocus { .. })));
    assert!(matches!(cay_inv(&g), Err(LieError::NearCutLocus { .. })));
    assert!(matches!(
        distance(&SE3::identity(), &g),
        Err(LieError::NearCutLocus { .. })
    ));
    let ok = SE3::new(so3::exp(&(n * (PI - 1e-3))), Vector3::new(1.0, 2.0, 3.0));
    assert!(log(&ok).is_ok() && cay_inv(&ok).is_ok());
    assert_eq!(SE3::from_matrix(&ok.to_matrix()), Ok(ok));
    let mut bad = ok.to_matrix();
    bad[(3, 0)] = 0.1;
    assert!(matches!(SE3::from_matrix(&bad), Err(LieError::NotARotation { .. })));
    let xi = Vector6::new(0.1, -0.2, 0.3, 0.4, 0.5, -0.6);
    assert_eq!(vee(&hat(&xi)), xi);
    let p = Vector3::new(0.3, 0.1, -0.2);
    let g = exp(&xi);
    let hp = g.to_matrix() * nalgebra::Vector4::new(p[0], p[1], p[2], 1.0);
    assert!((g.act(&p) - hp.xyz()).norm() <= 4.0 * EPS);
    assert!(maxabs(&((g * g.inverse()).to_matrix() - Matrix4::identity())) <= 4.0 * EPS);
}

/// Rotation blocks stay orthogonal to round-off through long products;
/// `renormalize` restores orthogonality to a few ε.
#[test]
fn orthogonality_after_compositions() {
    let steps = [
        Vector6::new(0.3, -0.2, 0.9, 1.0, 0.0, 0.5),
        Vector6::new(-1.1, 0.4, 0.05, 0.0, -2.0, 0.1),
    ];
    let mut g = SE3::identity();
    for i in 0..10 {
        g = g * exp(&steps[i % 2]) * cay(&steps[(i + 1) % 2]);
    }
    let r = g.rotation().matrix();
    assert!(maxabs(&(r.transpose() * r - Matrix3::identity())) <= 20.0 * EPS);
    for i in 0..10_000 {
        g = g * cay(&steps[i % 2]);
    }
    let g = g.renormalize();
    let r = g.rotation().matrix();
    assert!(maxabs(&(r.transpose() * r - Matrix3::identity())) <= 1e-15);
}
