//! Reduced Lagrangians ℓ(g, ξ) on a matrix group, written once for every
//! scalar type.

use nalgebra::{SMatrix, SVector};

use crate::ad::Scalar;
use crate::lie::GroupFamily;

/// A Lagrangian on TG in left trivialisation: ℓ(g, ξ) with body velocity
/// ξ = g⁻¹ġ ∈ Rᴺ (SE(3): ordered (ω; v)).
pub trait ReducedLagrangian<G: GroupFamily<N>, const N: usize> {
    /// ℓ(g, ξ).
    fn lagrangian<D: Scalar>(&self, g: &G::Element<D>, xi: &SVector<D, N>) -> D;
}

/// The common special form ℓ(g, ξ) = ½ ξᵀ𝕀ξ − V(g) with a constant symmetric
/// positive-definite inertia 𝕀. Every such type is a [`ReducedLagrangian`].
pub trait SplitReducedLagrangian<G: GroupFamily<N>, const N: usize> {
    /// The inertia 𝕀 (symmetric positive definite, body frame).
    fn inertia(&self) -> SMatrix<f64, N, N>;
    /// The potential V(g).
    fn potential<D: Scalar>(&self, g: &G::Element<D>) -> D;
}

impl<G: GroupFamily<N>, const N: usize, T: SplitReducedLagrangian<G, N>> ReducedLagrangian<G, N> for T {
    fn lagrangian<D: Scalar>(&self, g: &G::Element<D>, xi: &SVector<D, N>) -> D {
        let inertia = self.inertia();
        let mut kinetic = D::zero();
        for i in 0..N {
            let mut row = D::zero();
            for j in 0..N {
                row += xi[j] * inertia[(i, j)];
            }
            kinetic += xi[i] * row;
        }
        kinetic * 0.5 - self.potential(g)
    }
}
