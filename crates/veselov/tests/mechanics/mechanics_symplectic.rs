//! Symplecticity of the one-step maps, measured as ‖JᵀΩJ − Ω‖ with the exact
//! Jacobian of the converged step (implicit function theorem).

use crate::common;

use common::{all_methods, scheme};
use nalgebra::Vector2;
use proptest::prelude::*;
use veselov::diagnostics::symplecticity_defect;
use veselov::mechanics::{GalerkinIntegrator, PhaseState};
use veselov::models::{DoublePendulum, HenonHeiles};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Hénon–Heiles at random bounded states, every method: defect ≤ 1e-12.
    #[test]
    fn henon_heiles_maps_are_symplectic(x in -0.4..0.4_f64, y in -0.4..0.4_f64, px in -0.4..0.4_f64, py in -0.4..0.4_f64) {
        let x0 = PhaseState::new(0.0, Vector2::new(x, y), Vector2::new(px, py));
        for method in all_methods() {
            let mut map = GalerkinIntegrator::new(HenonHeiles.system(), scheme(method), 0.1).expect("valid");
            let (_, jac) = map.flow_jacobian(&x0).expect("step");
            let d = symplecticity_defect(&jac);
            prop_assert!(d <= 1e-12, "{:?}: defect {:e}", method, d);
        }
    }

    /// The non-separable double pendulum too (position-dependent mass matrix).
    #[test]
    fn double_pendulum_maps_are_symplectic(a in -1.0..1.0_f64, b in -1.0..1.0_f64, pa in -0.5..0.5_f64, pb in -0.5..0.5_f64) {
        let x0 = PhaseState::new(0.0, Vector2::new(a, b), Vector2::new(pa, pb));
        for method in all_methods() {
            let mut map = GalerkinIntegrator::new(DoublePendulum::default(), scheme(method), 0.05).expect("valid");
            let (_, jac) = map.flow_jacobian(&x0).expect("step");
            let d = symplecticity_defect(&jac);
            prop_assert!(d <= 1e-12, "{:?}: defect {:e}", method, d);
        }
    }
}

/// The exact Jacobian agrees with central finite differences of the step map
/// (to the accuracy of the differences), so the defect above measures the map.
#[test]
fn flow_jacobian_matches_finite_differences() {
    let x0 = PhaseState::new(0.0, Vector2::new(0.3, -0.2), Vector2::new(0.1, 0.25));
    for method in all_methods() {
        let mut map = GalerkinIntegrator::new(DoublePendulum::default(), scheme(method), 0.05).expect("valid");
        let (_, jac) = map.flow_jacobian(&x0).expect("step");
        let eps = 1e-6;
        for j in 0..4 {
            let shift = |s: f64| {
                let mut x = x0;
                if j < 2 {
                    x.q[j] += s
                } else {
                    x.p[j - 2] += s
                }
                x
            };
            let plus = map.step_report(0, &shift(eps)).expect("step").0;
            let minus = map.step_report(0, &shift(-eps)).expect("step").0;
            let dq = (plus.q - minus.q) / (2.0 * eps);
            let dp = (plus.p - minus.p) / (2.0 * eps);
            let (cq, cp) = if j < 2 {
                (jac.qq.column(j), jac.pq.column(j))
            } else {
                (jac.qp.column(j - 2), jac.pp.column(j - 2))
            };
            assert!((dq - cq).amax() < 1e-8, "{method:?} column {j}: {dq:?} vs {cq:?}");
            assert!((dp - cp).amax() < 1e-8, "{method:?} column {j}: {dp:?} vs {cp:?}");
        }
    }
}
