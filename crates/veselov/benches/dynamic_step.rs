//! Microseconds per step of the run-time-dimension Galerkin integrator
//! (`DynGalerkinIntegrator`, Newton with the exact Jacobian kept across
//! steps) on an FPU chain of `n` particles, Gauss s = 2, h = 0.05; the
//! residual evaluations and exact Jacobians per step are printed beside.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use veselov::ad::Scalar;
use veselov::mechanics::{DynGalerkinIntegrator, DynLagrangian, DynState, GalerkinScheme, Method};

/// `L = Σ ½ vᵢ² − Σ [½ (qᵢ₊₁ − qᵢ)² + ¼ (qᵢ₊₁ − qᵢ)⁴]`.
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

/// Steps between restarts from the initial state.
const RESTART: usize = 10_000;

fn dynamic(c: &mut Criterion) {
    let scheme = GalerkinScheme::new(Method::GalerkinGauss(2)).expect("valid");
    for n in [8, 16, 32] {
        let mut map = DynGalerkinIntegrator::new(FpuChain(n), scheme.clone(), 0.05).expect("valid");
        let x0 = DynState {
            t: 0.0,
            q: (0..n).map(|i| 0.1 * (i as f64).sin()).collect(),
            p: (0..n).map(|i| 0.2 * (0.7 * i as f64).cos()).collect(),
        };
        let mut x = x0.clone();
        let (mut iterations, steps) = (0, 2000);
        for k in 0..steps {
            iterations += map.step(k, &mut x).expect("step");
        }
        let name = format!("fpu-chain-n{n}/gauss-s2/dynamic");
        println!(
            "{name}: {:.2} residuals and {:.4} Jacobians per step",
            iterations as f64 / steps as f64,
            map.jacobians() as f64 / steps as f64
        );
        let mut k = 0usize;
        c.bench_function(&name, |b| {
            b.iter(|| {
                if k.is_multiple_of(RESTART) {
                    x.t = x0.t;
                    x.q.copy_from_slice(&x0.q);
                    x.p.copy_from_slice(&x0.p);
                }
                map.step(k, black_box(&mut x)).expect("step");
                k += 1;
            })
        });
    }
}

criterion_group!(benches, dynamic);
criterion_main!(benches);
