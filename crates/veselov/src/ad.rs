//! Automatic differentiation: the scalar bound user code is written against,
//! and helpers that lift `f64` data into dual numbers.
//!
//! Users write a Lagrangian, potential, force or symmetry generator once, as a
//! function generic over [`Scalar`]. The library evaluates it with `f64` for
//! values and with `num-dual` numbers (`DualVec`, `Dual2Vec`, `HyperDualVec`)
//! for exact first and second derivatives; nothing is finite-differenced.

use nalgebra::SVector;
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
