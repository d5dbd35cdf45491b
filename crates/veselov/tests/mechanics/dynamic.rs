//! Lagrangians of run-time dimension: same steps as the fixed-size path, and
//! exact conservation for a larger system.

use crate::common;

use common::{all_methods, scheme};
use veselov::Error;
use veselov::ad::Scalar;
use veselov::mechanics::{DynGalerkinIntegrator, DynLagrangian, DynState, GalerkinIntegrator, OneStepMap};
use veselov::models::Kepler;

struct DynKepler;
impl DynLagrangian for DynKepler {
    fn dim(&self) -> usize {
        2
    }
    fn lagrangian<D: Scalar>(&self, _t: D, q: &[D], v: &[D]) -> D {
        (v[0] * v[0] + v[1] * v[1]) * 0.5 + (q[0] * q[0] + q[1] * q[1]).sqrt().recip()
    }
}

/// A free Fermi–Pasta–Ulam chain of `n` unit masses: translation invariant.
struct FpuChain(usize);
impl DynLagrangian for FpuChain {
    fn dim(&self) -> usize {
        self.0
    }
    fn lagrangian<D: Scalar>(&self, _t: D, q: &[D], v: &[D]) -> D {
        let kinetic = v.iter().fold(D::from(0.0), |s, vi| s + *vi * *vi) * 0.5;
        let potential = q.windows(2).fold(D::from(0.0), |s, w| {
            let d = w[1] - w[0];
            s + d * d * 0.5 + d * d * d * d * 0.25
        });
        kinetic - potential
    }
}

#[test]
fn dynamic_path_equals_the_fixed_size_path() {
    let kepler = Kepler::new(0.5).expect("valid");
    let h = 0.01;
    for method in all_methods() {
        let mut fixed = GalerkinIntegrator::new(kepler.system(), scheme(method), h).expect("valid");
        let mut dynamic = DynGalerkinIntegrator::new(DynKepler, scheme(method), h).expect("valid");
        let mut x = kepler.initial_state();
        let mut y = DynState {
            t: x.t,
            q: x.q.as_slice().to_vec(),
            p: x.p.as_slice().to_vec(),
        };
        for k in 0..100 {
            x = fixed.step(k, &x).expect("fixed").0;
            dynamic.step(k, &mut y).expect("dynamic");
            let d = (0..2).fold(0.0_f64, |m, a| {
                m.max((x.q[a] - y.q[a]).abs()).max((x.p[a] - y.p[a]).abs())
            });
            assert!(d < 1e-13, "{method:?} step {k}: {d:e}");
        }
    }
}

/// A 16-particle chain: total momentum (a Noether momentum of translations) is
/// conserved to round-off, the energy error stays small and bounded.
#[test]
fn larger_dynamic_system_conserves_total_momentum() {
    let n = 16;
    let mut map = DynGalerkinIntegrator::new(FpuChain(n), scheme(veselov::mechanics::Method::GalerkinGauss(2)), 0.05)
        .expect("valid");
    let mut x = DynState {
        t: 0.0,
        q: (0..n).map(|i| 0.1 * (i as f64).sin()).collect(),
        p: (0..n).map(|i| 0.2 * (0.7 * i as f64).cos()).collect(),
    };
    let total = |x: &DynState| x.p.iter().sum::<f64>();
    let energy = |x: &DynState| {
        x.p.iter().map(|p| 0.5 * p * p).sum::<f64>()
            + x.q
                .windows(2)
                .map(|w| {
                    let d = w[1] - w[0];
                    0.5 * d * d + 0.25 * d.powi(4)
                })
                .sum::<f64>()
    };
    let (p0, e0) = (total(&x), energy(&x));
    let mut worst_e = 0.0_f64;
    for k in 0..2000 {
        map.step(k, &mut x).expect("step");
        assert!(
            (total(&x) - p0).abs() <= 1e-13,
            "step {k}: momentum drift {:e}",
            total(&x) - p0
        );
        worst_e = worst_e.max((energy(&x) - e0).abs());
    }
    // Order-4 method, h = 0.05: energy error O(h⁴) ≈ 1e-5 relative, no drift.
    assert!(worst_e < 1e-4 * e0, "energy error {worst_e:e}");
    // The factored Jacobian is kept across steps while the iteration contracts.
    let jacobians = map.jacobians();
    assert!((1..200).contains(&jacobians), "{jacobians} Jacobians in 2000 steps");
    // Dimension mismatch is a typed error.
    let mut bad = DynState {
        t: 0.0,
        q: vec![0.0; n + 1],
        p: vec![0.0; n],
    };
    assert!(matches!(map.step(0, &mut bad), Err(Error::DimensionMismatch { .. })));
}
