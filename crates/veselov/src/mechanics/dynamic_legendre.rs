//! The continuous Legendre map, its inverse and the energy for a
//! [`DynLagrangian`] (run-time dimension): the counterparts of
//! [`momentum`](super::momentum), [`velocity_from_momentum`](super::velocity_from_momentum)
//! and [`energy`](super::energy) of the fixed-size interface.
//!
//! Derivatives are exact (forward mode): `∂L/∂v` by `n` dual passes and the
//! velocity Hessian `W = ∂²L/∂v²` by `n(n+1)/2` hyper-dual passes. These
//! functions allocate their buffers: they serve initial data and output
//! rows, not the time step.

use num_dual::{Dual64, HyperDual64};

use super::dynamic::DynLagrangian;
use super::lagrangian::inverse_legendre_iteration;
use crate::error::{Error, Result, check_finite};
use crate::solve::DenseLu;

fn check_lengths<L: DynLagrangian>(l: &L, parts: [(&str, &[f64]); 2]) -> Result<()> {
    for (what, x) in parts {
        if x.len() != l.dim() {
            return Err(Error::DimensionMismatch {
                what: what.into(),
                expected: l.dim(),
                got: x.len(),
            });
        }
        check_finite(what, x.iter())?;
    }
    Ok(())
}

/// `∂L/∂v(t, q, v)` into `out`.
fn velocity_gradient<L: DynLagrangian>(l: &L, t: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
    let qd: Vec<Dual64> = q.iter().map(|&x| Dual64::from(x)).collect();
    let mut vd: Vec<Dual64> = v.iter().map(|&x| Dual64::from(x)).collect();
    for (i, o) in out.iter_mut().enumerate() {
        vd[i].eps = 1.0;
        *o = l.lagrangian(Dual64::from(t), &qd, &vd).eps;
        vd[i].eps = 0.0;
    }
}

/// `∂L/∂v` into `grad` and `W = ∂²L/∂v²` (row-major) into `hess`.
fn velocity_hessian<L: DynLagrangian>(l: &L, t: f64, q: &[f64], v: &[f64], grad: &mut [f64], hess: &mut [f64]) {
    let n = v.len();
    let qd: Vec<HyperDual64> = q.iter().map(|&x| HyperDual64::from(x)).collect();
    let mut vd: Vec<HyperDual64> = v.iter().map(|&x| HyperDual64::from(x)).collect();
    for i in 0..n {
        for j in i..n {
            vd[i].eps1 = 1.0;
            vd[j].eps2 = 1.0;
            let r = l.lagrangian(HyperDual64::from(t), &qd, &vd);
            vd[i].eps1 = 0.0;
            vd[j].eps2 = 0.0;
            if i == j {
                grad[i] = r.eps1;
            }
            hess[i * n + j] = r.eps1eps2;
            hess[j * n + i] = r.eps1eps2;
        }
    }
}

/// The Legendre map `p = ∂L/∂v(t, q, v)`.
pub fn dyn_momentum<L: DynLagrangian>(l: &L, t: f64, q: &[f64], v: &[f64]) -> Result<Vec<f64>> {
    check_lengths(l, [("q", q), ("v", v)])?;
    let mut p = vec![0.0; l.dim()];
    velocity_gradient(l, t, q, v, &mut p);
    Ok(p)
}

/// The inverse Legendre map: `v` with `∂L/∂v(t, q, v) = p`, by Newton's method
/// on the exact velocity Hessian from `v = 0` (one step when `L` is quadratic
/// in `v`), with the iteration control of the fixed-size map. A singular
/// Hessian is [`Error::SingularVelocityHessian`]; no convergence in 60
/// iterations is [`Error::NewtonFailure`].
pub fn dyn_velocity_from_momentum<L: DynLagrangian>(l: &L, t: f64, q: &[f64], p: &[f64]) -> Result<Vec<f64>> {
    check_lengths(l, [("q", q), ("p", p)])?;
    let n = l.dim();
    let mut v = vec![0.0; n];
    let mut r = vec![0.0; n];
    let mut lu = DenseLu::new(n);
    inverse_legendre_iteration(t, || {
        velocity_hessian(l, t, q, &v, &mut r, &mut lu.matrix);
        for (ri, pi) in r.iter_mut().zip(p) {
            *ri -= pi;
        }
        let residual = r.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let pivot = lu.factor("inverse Legendre map").unwrap_or(0.0);
        if pivot <= 1e3 * f64::EPSILON {
            return Err(Error::SingularVelocityHessian { t, pivot });
        }
        lu.solve(&mut r);
        for (vi, d) in v.iter_mut().zip(&r) {
            *vi -= d;
        }
        let size = v.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        Ok((residual, r.iter().fold(0.0_f64, |m, x| m.max(x.abs())) / size))
    })?;
    Ok(v)
}

/// The energy `E = p·v − L(t, q, v)` at the phase-space point `(q, p)`, with
/// `v` from the inverse Legendre map.
pub fn dyn_energy<L: DynLagrangian>(l: &L, t: f64, q: &[f64], p: &[f64]) -> Result<f64> {
    let v = dyn_velocity_from_momentum(l, t, q, p)?;
    let pv: f64 = p.iter().zip(&v).map(|(a, b)| a * b).sum();
    Ok(pv - l.lagrangian(t, q, &v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ad::Scalar;

    /// `L = ½ vᵀ M(q) v + v·A(q) − V(q)` with a position-dependent mass,
    /// a magnetic term and a quartic potential in 3 dimensions.
    struct Magnetic;

    impl DynLagrangian for Magnetic {
        fn dim(&self) -> usize {
            3
        }
        fn lagrangian<D: Scalar>(&self, t: D, q: &[D], v: &[D]) -> D {
            let m = D::from(1.0) + q[0] * q[0] * 0.5;
            let kinetic = (v[0] * v[0] * m + v[1] * v[1] * 2.0 + v[2] * v[2] + v[0] * v[1] * 0.3) * 0.5;
            let magnetic = v[0] * q[1] * (-0.7) + v[1] * q[0] * 0.7 + v[2] * t.sin();
            let potential = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).powi(2) * 0.25;
            kinetic + magnetic - potential
        }
    }

    #[test]
    fn the_inverse_legendre_map_inverts_the_legendre_map() {
        let (t, q, v) = (0.4, [0.3, -0.8, 1.1], [1.5, -0.2, 0.7]);
        let p = dyn_momentum(&Magnetic, t, &q, &v).expect("p");
        // ∂L/∂v by hand.
        let m = 1.0 + 0.5 * q[0] * q[0];
        let expected = [
            m * v[0] + 0.15 * v[1] - 0.7 * q[1],
            2.0 * v[1] + 0.15 * v[0] + 0.7 * q[0],
            v[2] + t.sin(),
        ];
        for (a, b) in p.iter().zip(expected) {
            assert!((a - b).abs() < 1e-14, "{a} vs {b}");
        }
        let back = dyn_velocity_from_momentum(&Magnetic, t, &q, &p).expect("v");
        for (a, b) in back.iter().zip(v) {
            assert!((a - b).abs() < 1e-14, "{a} vs {b}");
        }
        let e = dyn_energy(&Magnetic, t, &q, &p).expect("E");
        let kinetic = 0.5 * (m * v[0] * v[0] + 2.0 * v[1] * v[1] + v[2] * v[2] + 0.3 * v[0] * v[1]);
        let potential = 0.25 * (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).powi(2);
        assert!((e - (kinetic + potential)).abs() < 1e-14, "{e}");
    }

    #[test]
    fn bad_inputs_are_typed_errors() {
        assert!(matches!(
            dyn_momentum(&Magnetic, 0.0, &[0.0; 2], &[0.0; 3]),
            Err(Error::DimensionMismatch { .. })
        ));
        assert!(dyn_energy(&Magnetic, 0.0, &[f64::NAN, 0.0, 0.0], &[0.0; 3]).is_err());
        struct Degenerate;
        impl DynLagrangian for Degenerate {
            fn dim(&self) -> usize {
                2
            }
            fn lagrangian<D: Scalar>(&self, _t: D, q: &[D], v: &[D]) -> D {
                v[0] * v[0] * 0.5 + v[1] * q[0]
            }
        }
        assert!(matches!(
            dyn_velocity_from_momentum(&Degenerate, 0.0, &[0.0; 2], &[1.0, 0.0]),
            Err(Error::SingularVelocityHessian { .. })
        ));
    }
}
