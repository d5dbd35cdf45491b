//! The classical fourth-order Runge–Kutta method with a fixed step, for the
//! continuum references of the tests (boundary-value problems solved by
//! shooting along the length of a beam or rod).

use nalgebra::SVector;

/// y at s = `length` from `y` at s = 0 under y′ = `rhs`(y), by `steps` RK4
/// steps, with `observe` called at every node (k = 0 … `steps`,
/// s = k·length/steps).
pub fn rk4<const D: usize>(
    mut y: SVector<f64, D>,
    length: f64,
    steps: usize,
    rhs: impl Fn(&SVector<f64, D>) -> SVector<f64, D>,
    mut observe: impl FnMut(usize, &SVector<f64, D>),
) -> SVector<f64, D> {
    let h = length / steps as f64;
    observe(0, &y);
    for k in 1..=steps {
        let k1 = rhs(&y);
        let k2 = rhs(&(y + k1 * (h / 2.0)));
        let k3 = rhs(&(y + k2 * (h / 2.0)));
        let k4 = rhs(&(y + k3 * h));
        y += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
        observe(k, &y);
    }
    y
}
