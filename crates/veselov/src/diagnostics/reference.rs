//! Independent reference solutions for convergence studies: the classical
//! fourth-order Runge–Kutta method on the (forced) Euler–Lagrange equations in
//! `(q, v)`, with compensated summation so that tens of thousands of steps add
//! no visible round-off. It shares nothing with the variational integrators
//! except the exact derivatives of `L`.

use nalgebra::SVector;

use crate::error::{Result, check_step};
use crate::mechanics::{Force, Lagrangian, PhaseState, forced_acceleration, momentum, velocity_from_momentum};

/// Integrate from `x0` to `t_end` with `steps` RK4 steps; returns `(t_end, q, p)`.
pub fn rk4_reference<const N: usize, L: Lagrangian<N>, F: Force<N>>(
    l: &L,
    force: &F,
    x0: &PhaseState<N>,
    t_end: f64,
    steps: usize,
) -> Result<PhaseState<N>> {
    x0.check()?;
    let h = (t_end - x0.t) / steps as f64;
    check_step(h)?;
    let mut q = x0.q;
    let mut v = velocity_from_momentum(l, x0.t, &x0.q, &x0.p)?;
    let (mut cq, mut cv) = (SVector::<f64, N>::zeros(), SVector::<f64, N>::zeros());
    let acc = |t: f64, q: &SVector<f64, N>, v: &SVector<f64, N>| forced_acceleration(l, force, t, q, v);
    for k in 0..steps {
        let t = x0.t + k as f64 * h;
        let (k1q, k1v) = (v, acc(t, &q, &v)?);
        let (q2, v2) = (q + k1q * (0.5 * h), v + k1v * (0.5 * h));
        let (k2q, k2v) = (v2, acc(t + 0.5 * h, &q2, &v2)?);
        let (q3, v3) = (q + k2q * (0.5 * h), v + k2v * (0.5 * h));
        let (k3q, k3v) = (v3, acc(t + 0.5 * h, &q3, &v3)?);
        let (q4, v4) = (q + k3q * h, v + k3v * h);
        let (k4q, k4v) = (v4, acc(t + h, &q4, &v4)?);
        let dq = (k1q + (k2q + k3q) * 2.0 + k4q) * (h / 6.0);
        let dv = (k1v + (k2v + k3v) * 2.0 + k4v) * (h / 6.0);
        // Kahan-compensated q += dq, v += dv.
        let yq = dq - cq;
        let tq = q + yq;
        cq = (tq - q) - yq;
        q = tq;
        let yv = dv - cv;
        let tv = v + yv;
        cv = (tv - v) - yv;
        v = tv;
    }
    let p = momentum(l, t_end, &q, &v);
    Ok(PhaseState::new(t_end, q, p))
}
