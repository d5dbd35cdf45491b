//! The diagonal quadratic energies of the wave equation and of the beam.

use nalgebra::{SMatrix, SVector};

use super::SplitDensity;
use crate::ad::Scalar;
use crate::field::fibre::Fibre;

/// K = ½ Σ mₖξₖ², Φ = ½ Σ cₖ(ηₖ − rₖ)² with diagonal weights and a reference
/// strain r: the wave equation on ℝ^M (r = 0) and the beam's quadratic
/// energies on SE(3) (r = E6), with no potential.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiagonalQuadratic<const M: usize> {
    /// Kinetic weights mₖ.
    pub inertia: [f64; M],
    /// Stiffness weights cₖ.
    pub stiffness: [f64; M],
    /// Reference strain rₖ.
    pub reference: [f64; M],
}

impl<const M: usize> DiagonalQuadratic<M> {
    /// Its gradient (wₖ(xₖ − rₖ))ₖ.
    pub fn quadratic_gradient<D: Scalar>(w: &[f64; M], x: &SVector<D, M>, r: &[f64; M]) -> SVector<D, M> {
        SVector::from_fn(|k, _| (x[k] - r[k]) * w[k])
    }

    /// ½ Σ wₖ(xₖ − rₖ)².
    pub fn quadratic<D: Scalar>(w: &[f64; M], x: &SVector<D, M>, r: &[f64; M]) -> D {
        let mut sum = D::zero();
        for k in 0..M {
            let d = x[k] - r[k];
            sum += d * d * (0.5 * w[k]);
        }
        sum
    }
}

impl<F: Fibre<M>, const M: usize> SplitDensity<F, M> for DiagonalQuadratic<M> {
    fn has_potential(&self) -> bool {
        false
    }
    fn kinetic<D: Scalar>(&self, xi: &SVector<D, M>) -> D {
        Self::quadratic(&self.inertia, xi, &[0.0; M])
    }
    fn stored<D: Scalar>(&self, eta: &SVector<D, M>) -> D {
        Self::quadratic(&self.stiffness, eta, &self.reference)
    }
    fn kinetic_gradient<D: Scalar>(&self, xi: &SVector<D, M>) -> SVector<D, M> {
        Self::quadratic_gradient(&self.inertia, xi, &[0.0; M])
    }
    fn stored_gradient<D: Scalar>(&self, eta: &SVector<D, M>) -> SVector<D, M> {
        Self::quadratic_gradient(&self.stiffness, eta, &self.reference)
    }
    fn kinetic_hessian(&self, _xi: &SVector<f64, M>) -> SMatrix<f64, M, M> {
        SMatrix::from_diagonal(&SVector::from(self.inertia))
    }
    fn stored_hessian(&self, _eta: &SVector<f64, M>) -> SMatrix<f64, M, M> {
        SMatrix::from_diagonal(&SVector::from(self.stiffness))
    }
}
