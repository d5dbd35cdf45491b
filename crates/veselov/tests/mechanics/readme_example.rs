//! The README's library example, kept compiling and true.

use nalgebra::{SVector, Vector2};
use veselov::ad::Scalar;
use veselov::diagnostics::{momentum_series, symplecticity_defect};
use veselov::mechanics::{GalerkinIntegrator, GalerkinScheme, Lagrangian, Method, PhaseState, integrate};
use veselov::models::Kepler;

struct MyKepler; // L = ½|v|² + 1/|q|, written once for f64 and every dual number
impl Lagrangian<2> for MyKepler {
    fn lagrangian<D: Scalar>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        (v[0] * v[0] + v[1] * v[1]) * 0.5 + (q[0] * q[0] + q[1] * q[1]).sqrt().recip()
    }
}

#[test]
fn readme_example() -> veselov::Result<()> {
    let scheme = GalerkinScheme::new(Method::GalerkinGauss(2))?; // order 4
    let mut map = GalerkinIntegrator::new(MyKepler, scheme, 0.01)?;
    let x0 = PhaseState::new(0.0, Vector2::new(0.5, 0.0), Vector2::new(0.0, 3f64.sqrt()));
    let run = integrate(&mut map, x0, 10_000, 10).into_result()?;
    let drift = momentum_series(&Kepler::angular_symmetry(), &run.states).max_rel_error(); // ~1e-15
    let (_, jacobian) = map.flow_jacobian(&x0)?; // exact, by the implicit function theorem
    assert!(symplecticity_defect(&jacobian) < 1e-12 && drift < 1e-12);
    Ok(())
}
