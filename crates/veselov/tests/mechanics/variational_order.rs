//! Seed 004 §3 and §5.1: Lemma 3.4 for inverse retractions (property test,
//! with a non-flat retraction beside the flat one and a map that is not an
//! inverse retraction to show the check can fail), and the local variational
//! order of Def. 5.1 against the exact discrete Lagrangian of the harmonic
//! oscillator, L_d^e(q₀, q₁, h) = ω[(q₀² + q₁²) cos ωh − 2q₀q₁]/(2 sin ωh):
//! |L_d − L_d^e| = O(h^{r+1}) along solutions, r = 2s − 2 for Galerkin
//! Lobatto and r = 2s for Galerkin Gauss with s stages.

use nalgebra::{SMatrix, SVector, Vector1};
use num_dual::{Derivative, DualSVec64};
use proptest::prelude::*;
use veselov::ad::Scalar;
use veselov::diagnostics::fit_order_asymptotic;
use veselov::mechanics::{FlatRetraction, GalerkinIntegrator, GalerkinScheme, InverseRetraction, Method};
use veselov::models::HarmonicOscillator;

/// A non-flat inverse retraction of ℝ³: τ(q, Q) = sinh(Q − q) + ((Q − q)·q)(Q − q),
/// componentwise sinh (τ(q, q) = 0, and its derivatives at Q = q are ∓I).
struct Curved;

impl InverseRetraction<3> for Curved {
    fn tau<D: Scalar>(&self, q: &SVector<D, 3>, target: &SVector<D, 3>) -> SVector<D, 3> {
        let d = target - q;
        let k = d.dot(q);
        d.map(|x| x.sinh()) + d * k
    }
}

/// A map with τ(q, q) = 0 whose derivative in Q is 2I: not an inverse retraction.
struct Doubled;

impl InverseRetraction<3> for Doubled {
    fn tau<D: Scalar>(&self, q: &SVector<D, 3>, target: &SVector<D, 3>) -> SVector<D, 3> {
        (target - q) * D::from(2.0)
    }
}

/// (|τ(q, q)|, max|∂τ/∂q + I|, max|∂τ/∂Q − I|) at q, exact derivatives by
/// forward-mode dual numbers over the six inputs.
fn lemma_3_4_defect<R: InverseRetraction<3>>(r: &R, q: [f64; 3]) -> (f64, f64, f64) {
    type D6 = DualSVec64<6>;
    let var = |k: usize, x: f64| {
        let mut e = SVector::<f64, 6>::zeros();
        e[k] = 1.0;
        D6::new(x, Derivative::some(e))
    };
    let qd = SVector::<D6, 3>::from_fn(|i, _| var(i, q[i]));
    let td = SVector::<D6, 3>::from_fn(|i, _| var(3 + i, q[i]));
    let tau = r.tau(&qd, &td);
    let mut jac = SMatrix::<f64, 3, 6>::zeros();
    for i in 0..3 {
        let g = tau[i].eps.unwrap_generic(nalgebra::Const::<6>, nalgebra::Const::<1>);
        for k in 0..6 {
            jac[(i, k)] = g[k];
        }
    }
    let identity = SMatrix::<f64, 3, 3>::identity();
    let value = tau.map(|x| x.re).amax();
    let dq = (jac.fixed_view::<3, 3>(0, 0) + identity).amax();
    let dt = (jac.fixed_view::<3, 3>(0, 3) - identity).amax();
    (value, dq, dt)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn inverse_retractions_satisfy_lemma_3_4(q in prop::array::uniform3(-3.0f64..3.0)) {
        for (name, (v, dq, dt)) in [("flat", lemma_3_4_defect(&FlatRetraction, q)), ("curved", lemma_3_4_defect(&Curved, q))] {
            prop_assert!(v == 0.0 && dq < 1e-15 && dt < 1e-15, "{}: {:?}", name, (v, dq, dt));
        }
        let (_, _, dt) = lemma_3_4_defect(&Doubled, q);
        prop_assert!(dt > 0.5, "the doubled map must fail the lemma: {}", dt);
    }
}

#[test]
fn galerkin_discrete_lagrangians_have_their_variational_order() {
    let omega = 1.3;
    let osc = HarmonicOscillator::new(1.0, omega).expect("oscillator");
    // Along the solution q(t) = A cos(ωt + φ), on [−h/2, h/2]: with the
    // interval centred at a fixed time the error coefficient is a smooth
    // even function of h (with q(0), q(h) it also varies with the phase).
    let (a, phi) = (0.8, 0.4);
    let q = |t: f64| a * (omega * t + phi).cos();
    let exact = |h: f64| {
        let (q0, q1) = (q(-0.5 * h), q(0.5 * h));
        omega * ((q0 * q0 + q1 * q1) * (omega * h).cos() - 2.0 * q0 * q1) / (2.0 * (omega * h).sin())
    };
    let hs: Vec<f64> = (0..17).map(|k| 0.8 * 0.5f64.powf(0.5 * k as f64)).collect();
    for (method, r) in [
        (Method::GalerkinLobatto(2), 2),
        (Method::GalerkinLobatto(3), 4),
        (Method::GalerkinLobatto(4), 6),
        (Method::GalerkinGauss(1), 2),
        (Method::GalerkinGauss(2), 4),
        (Method::GalerkinGauss(3), 6),
    ] {
        let errors: Vec<f64> = hs
            .iter()
            .map(|&h| {
                let scheme = GalerkinScheme::new(method).expect("scheme");
                let mut map = GalerkinIntegrator::new(osc.system(), scheme, h).expect("integrator");
                let ld = map
                    .discrete_lagrangian(0.0, &Vector1::new(q(-0.5 * h)), &Vector1::new(q(0.5 * h)))
                    .expect("L_d")
                    .value;
                (ld - exact(h)).abs()
            })
            .collect();
        // Round-off floor: L_d ≈ h·L with |L| ≤ ω²A², solved to ~1e-15
        // relative, scatters at 1e-15..3e-14: fit the four smallest steps
        // with errors in (1e-12, 1e-4], steps a factor √2 apart.
        let fit = fit_order_asymptotic(&hs, &errors, 1e-12, 1e-4, 4).expect("enough points above the floor");
        println!(
            "{method:?}: |L_d − L_d^e| = {:?}, fitted order {:.3} on {:?} (expected r + 1 = {})",
            errors.iter().map(|e| format!("{e:.2e}")).collect::<Vec<_>>(),
            fit.order,
            fit.used,
            r + 1
        );
        assert!(
            (fit.order - (r + 1) as f64).abs() < 0.05,
            "{method:?}: order {:.3}, expected {}",
            fit.order,
            r + 1
        );
    }
}
