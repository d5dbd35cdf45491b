//! Automatic differentiation: the scalar bound user code is written against,
//! and helpers that lift `f64` data into dual numbers.
//!
//! Users write a Lagrangian, potential, force or symmetry generator once, as a
//! function generic over [`Scalar`]. The library evaluates it with `f64` for
//! values and with `num-dual` numbers (`DualVec`, `Dual2Vec`, `HyperDualVec`)
//! for exact first and second derivatives; nothing is finite-differenced.

use nalgebra::{Matrix3, SVector, Vector3};
pub use num_dual::DualNum;

/// The scalar bound of every user-supplied function: `f64` or a `num-dual`
/// number over `f64` with a fixed number of directions.
///
/// ```
/// use veselov::ad::Scalar;
/// fn kinetic<D: Scalar>(v: D) -> D { v * v * 0.5 }
/// assert_eq!(kinetic(2.0_f64), 2.0);
/// ```
pub trait Scalar: DualNum<Primitive = f64> + Copy {}

impl<T: DualNum<Primitive = f64> + Copy> Scalar for T {}

/// Lift a vector of `f64` into constants of the scalar type `D`.
#[inline]
pub fn lift<D: Scalar, const N: usize>(x: &SVector<f64, N>) -> SVector<D, N> {
    x.map(D::from)
}

/// Lift a single `f64` into a constant of the scalar type `D`.
#[inline]
pub fn constant<D: Scalar>(x: f64) -> D {
    D::from(x)
}

/// `a b` for 3×3 matrices, written out entry by entry: over dual numbers
/// this avoids the generic product's zero-filled accumulator and copies.
#[inline]
pub fn mat3_mul<D: Scalar>(a: &Matrix3<D>, b: &Matrix3<D>) -> Matrix3<D> {
    Matrix3::from_fn(|i, j| a[(i, 0)] * b[(0, j)] + a[(i, 1)] * b[(1, j)] + a[(i, 2)] * b[(2, j)])
}

/// `aᵀ b` for 3×3 matrices, written out (no transposed copy of `a`).
#[inline]
pub fn mat3_tr_mul<D: Scalar>(a: &Matrix3<D>, b: &Matrix3<D>) -> Matrix3<D> {
    Matrix3::from_fn(|i, j| a[(0, i)] * b[(0, j)] + a[(1, i)] * b[(1, j)] + a[(2, i)] * b[(2, j)])
}

/// `aᵀ x` for a 3×3 matrix, written out as [`mat3_tr_mul`].
#[inline]
pub fn mat3_tr_vec<D: Scalar>(a: &Matrix3<D>, x: &Vector3<D>) -> Vector3<D> {
    Vector3::from_fn(|i, _| a[(0, i)] * x[0] + a[(1, i)] * x[1] + a[(2, i)] * x[2])
}

/// `a x` for a 3×3 matrix, written out as [`mat3_mul`].
#[inline]
pub fn mat3_vec<D: Scalar>(a: &Matrix3<D>, x: &Vector3<D>) -> Vector3<D> {
    Vector3::from_fn(|i, _| a[(i, 0)] * x[0] + a[(i, 1)] * x[1] + a[(i, 2)] * x[2])
}

/// `a b` for a constant (`f64`) 3×3 matrix `a`: its entries scale those of
/// `b`, without lifting `a` into dual numbers.
#[inline]
pub fn const_mat3_mul<D: Scalar>(a: &Matrix3<f64>, b: &Matrix3<D>) -> Matrix3<D> {
    Matrix3::from_fn(|i, j| b[(0, j)] * a[(i, 0)] + b[(1, j)] * a[(i, 1)] + b[(2, j)] * a[(i, 2)])
}

/// `a x` for a constant (`f64`) 3×3 matrix, as [`const_mat3_mul`].
#[inline]
pub fn const_mat3_vec<D: Scalar>(a: &Matrix3<f64>, x: &Vector3<D>) -> Vector3<D> {
    Vector3::from_fn(|i, _| x[0] * a[(i, 0)] + x[1] * a[(i, 1)] + x[2] * a[(i, 2)])
}
