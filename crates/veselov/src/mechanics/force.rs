//! Generalised forces `F(t, q, v)`, written once, generic over the AD scalar.
//!
//! Forces enter the discrete Lagrange–d'Alembert principle through the
//! virtual work of the quadrature, `h Σᵢ bᵢ F(t_k + cᵢh, Xᵢ, Yᵢ)·δXᵢ`
//! (seed 004, Prop. 7.4; Marsden & West 2001, §3.2): with the Galerkin
//! control points this gives the discrete forces
//! `f⁻ = h Σᵢ bᵢ M_{i0} Fᵢ` and `f⁺ = h Σᵢ bᵢ M_{im} Fᵢ` of the forced
//! discrete Legendre transforms `p_k = −D₁L_d − f⁻`, `p_{k+1} = D₂L_d + f⁺`.

use nalgebra::{SMatrix, SVector, U1};
use num_dual::DualSVec64;

use crate::ad::{Scalar, lift};

/// A generalised force `F(t, q, v)` (a covector: it pairs with `δq`).
pub trait Force<const N: usize> {
    /// `F(t, q, v)`.
    fn force<D: Scalar>(&self, t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> SVector<D, N>;
    /// `true` only for a force that is identically zero (integrators then skip it).
    fn is_zero(&self) -> bool {
        false
    }
}

/// The zero force: the unforced, symplectic case.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NoForce;

impl<const N: usize> Force<N> for NoForce {
    fn force<D: Scalar>(&self, _t: D, _q: &SVector<D, N>, _v: &SVector<D, N>) -> SVector<D, N> {
        SVector::from_element(D::from(0.0))
    }
    fn is_zero(&self) -> bool {
        true
    }
}

impl<const N: usize, F: Force<N>> Force<N> for &F {
    fn force<D: Scalar>(&self, t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> SVector<D, N> {
        (**self).force(t, q, v)
    }
    fn is_zero(&self) -> bool {
        (**self).is_zero()
    }
}

/// A force and its Jacobians at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceJet<const N: usize> {
    /// `F`.
    pub value: SVector<f64, N>,
    /// `dq[(a, b)] = ∂F_a/∂q_b`.
    pub dq: SMatrix<f64, N, N>,
    /// `dv[(a, b)] = ∂F_a/∂v_b`.
    pub dv: SMatrix<f64, N, N>,
}

impl<const N: usize> ForceJet<N> {
    /// The zero jet.
    pub fn zero() -> Self {
        Self {
            value: SVector::zeros(),
            dq: SMatrix::zeros(),
            dv: SMatrix::zeros(),
        }
    }
}

/// `F(t, q, v)` in `f64`.
#[inline]
pub fn force_value<const N: usize, F: Force<N>>(
    f: &F,
    t: f64,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
) -> SVector<f64, N> {
    f.force(t, q, v)
}

/// `F` and its exact Jacobians in `q` and `v` (two forward-mode passes).
pub fn force_jet<const N: usize, F: Force<N>>(f: &F, t: f64, q: &SVector<f64, N>, v: &SVector<f64, N>) -> ForceJet<N> {
    let td = DualSVec64::<N>::from(t);
    let qd = SVector::<DualSVec64<N>, N>::from_fn(|i, _| DualSVec64::<N>::from(q[i]).derivative(i));
    let vd = SVector::<DualSVec64<N>, N>::from_fn(|i, _| DualSVec64::<N>::from(v[i]).derivative(i));
    let a = f.force(td, &qd, &lift(v));
    let b = f.force(td, &lift(q), &vd);
    let rows = |x: &SVector<DualSVec64<N>, N>| {
        SMatrix::<f64, N, N>::from_fn(|r, c| x[r].eps.unwrap_generic(nalgebra::Const::<N>, U1)[c])
    };
    ForceJet {
        value: a.map(|x| x.re),
        dq: rows(&a),
        dv: rows(&b),
    }
}
