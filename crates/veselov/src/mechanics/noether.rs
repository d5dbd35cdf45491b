//! Symmetries and their discrete momentum maps (discrete Noether theorem).
//!
//! A symmetry is declared by its infinitesimal generator `ξ_Q(q)` on
//! configuration space, generic over the AD scalar. If `L` is invariant under
//! the flow of `ξ_Q` (lifted to velocities), the discrete Lagrangians built
//! from it are invariant under the diagonal action, and the discrete momentum
//! map `J(q_k, p_k) = ⟨p_k, ξ_Q(q_k)⟩` is conserved exactly by the
//! variational integrator (Marsden & West 2001, Thm 1.3.3; seed 002 (3.11)).

use nalgebra::SVector;

use crate::ad::Scalar;

/// An infinitesimal symmetry `ξ_Q(q)` of configuration space.
pub trait Symmetry<const N: usize> {
    /// Name used in outputs (column `J_<name>`).
    fn name(&self) -> &str;
    /// The generator `ξ_Q(q)`.
    fn generator<D: Scalar>(&self, q: &SVector<D, N>) -> SVector<D, N>;
}

/// Momentum map `J = ⟨p, ξ_Q(q)⟩`.
pub fn momentum_map<const N: usize, S: Symmetry<N> + ?Sized>(
    symmetry: &S,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> f64 {
    p.dot(&symmetry.generator(q))
}

/// A symmetry with an affine generator `ξ_Q(q) = A q + b`: rotations and translations.
#[derive(Debug, Clone, PartialEq)]
pub struct AffineSymmetry<const N: usize> {
    name: String,
    matrix: nalgebra::SMatrix<f64, N, N>,
    offset: SVector<f64, N>,
}

impl<const N: usize> AffineSymmetry<N> {
    /// `ξ_Q(q) = A q + b`.
    pub fn new(name: &str, matrix: nalgebra::SMatrix<f64, N, N>, offset: SVector<f64, N>) -> Self {
        Self {
            name: name.to_string(),
            matrix,
            offset,
        }
    }
    /// Rotation in the plane of coordinates `(i, j)`: `ξ = (…, −q_j, …, q_i, …)`.
    pub fn rotation(name: &str, i: usize, j: usize) -> Self {
        let mut a = nalgebra::SMatrix::<f64, N, N>::zeros();
        a[(i, j)] = -1.0;
        a[(j, i)] = 1.0;
        Self::new(name, a, SVector::zeros())
    }
    /// Translation along coordinate `i`.
    pub fn translation(name: &str, i: usize) -> Self {
        let mut b = SVector::<f64, N>::zeros();
        b[i] = 1.0;
        Self::new(name, nalgebra::SMatrix::zeros(), b)
    }
}

impl<const N: usize> Symmetry<N> for AffineSymmetry<N> {
    fn name(&self) -> &str {
        &self.name
    }
    fn generator<D: Scalar>(&self, q: &SVector<D, N>) -> SVector<D, N> {
        let a = self.matrix.map(D::from);
        a * q + self.offset.map(D::from)
    }
}
