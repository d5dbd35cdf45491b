//! The affine interpolant of one simplex (Prop. 5.20): its frame (T^X)⁻¹,
//! vol_β, barycentre and jet, a frame with the last vertex still unknown,
//! and the completed jet entries and means the midpoint rule's vertex solve
//! differentiates.

use nalgebra::SMatrix;
use nalgebra::SVector;

/// The affine interpolant of one simplex in `f64`: (T^X)⁻¹, vol_β, the
/// barycentre x̄ (zero where the density does not read it), ȳ and φ.
pub(super) struct AffineFrame<const M: usize, const N: usize> {
    pub(super) inverse: SMatrix<f64, N, N>,
    pub(super) volume: f64,
    pub(super) centre: SVector<f64, N>,
    pub(super) value: SVector<f64, M>,
    pub(super) jet: SMatrix<f64, M, N>,
    /// The rises y_{c+1} − y₀ (column c).
    pub(super) rises: SMatrix<f64, M, N>,
}

impl<const M: usize, const N: usize> AffineFrame<M, N> {
    /// c_{la} = ∂φ_{ka}/∂(y_l)_k.
    #[inline]
    pub(super) fn coefficient(&self, l: usize, a: usize) -> f64 {
        vertex_coefficient(&self.inverse, l, a)
    }

    /// The weight of every vertex in ȳ.
    #[inline]
    pub(super) fn mean_weight() -> f64 {
        1.0 / (N + 1) as f64
    }
}

/// c_{la} = ∂φ_{ka}/∂(y_l)_k from (T^X)⁻¹: its row l − 1 for l ≥ 1, minus
/// the sum of its rows for l = 0.
#[inline]
pub(super) fn vertex_coefficient<const N: usize>(inverse: &SMatrix<f64, N, N>, l: usize, a: usize) -> f64 {
    if l == 0 {
        -(0..N).fold(0.0, |acc, c| acc + inverse[(c, a)])
    } else {
        inverse[(l - 1, a)]
    }
}

/// The interpolant of a simplex whose last vertex value is not yet known:
/// the sums over the other vertices, in the order of the full evaluation, so
/// that [`complete`](Self::complete) gives the bits of the frame formed from
/// all N + 1 values at once (a fold's last term added last).
#[derive(Clone, Copy)]
pub(super) struct PartialFrame<const M: usize, const N: usize> {
    pub(super) inverse: SMatrix<f64, N, N>,
    pub(super) volume: f64,
    pub(super) centre: SVector<f64, N>,
    /// y₀ + … + y_{N−1}.
    pub(super) sum: SVector<f64, M>,
    /// Σ_{c < N−1} (y_{c+1} − y₀)_k (T^X)⁻¹_{ca}.
    pub(super) jet: SMatrix<f64, M, N>,
    /// The known rises y_{c+1} − y₀ (column c < N − 1; the last column 0).
    pub(super) rises: SMatrix<f64, M, N>,
    /// y₀.
    pub(super) first: SVector<f64, M>,
}

impl<const M: usize, const N: usize> PartialFrame<M, N> {
    /// The sums of the values `y[..N]` on a cell of geometry (`inverse`,
    /// `volume`, `centre`): [`sum_and_rises`](Self::sum_and_rises) and the
    /// known part Σ_{c < N−1} (y_{c+1} − y₀)_k (T^X)⁻¹_{ca} of φ.
    #[inline]
    pub(super) fn new(
        inverse: SMatrix<f64, N, N>,
        volume: f64,
        centre: SVector<f64, N>,
        y: &[SVector<f64, M>],
    ) -> Self {
        let (sum, rises) = Self::sum_and_rises(y);
        let jet =
            SMatrix::<f64, M, N>::from_fn(|k, a| (0..N - 1).fold(0.0, |acc, c| acc + rises[(k, c)] * inverse[(c, a)]));
        Self {
            inverse,
            volume,
            centre,
            sum,
            jet,
            rises,
            first: y[0],
        }
    }

    /// y₀ + … + y_{N−1} and the known rises y_{c+1} − y₀ (column c < N − 1,
    /// the last column zero) of the values `y[..N]`: all a diagonal jet
    /// metric's equation needs ([`metric_gradient_from`](super::metric_terms::metric_gradient_from)).
    #[inline]
    pub(super) fn sum_and_rises(y: &[SVector<f64, M>]) -> (SVector<f64, M>, SMatrix<f64, M, N>) {
        let rises = SMatrix::<f64, M, N>::from_fn(|k, c| if c + 1 < N { y[c + 1][k] - y[0][k] } else { 0.0 });
        let sum = y[..N].iter().fold(SVector::<f64, M>::zeros(), |acc, b| acc + b);
        (sum, rises)
    }

    /// The frame with the last vertex value `z`.
    #[inline]
    pub(super) fn complete(&self, z: &SVector<f64, M>) -> AffineFrame<M, N> {
        let jet = SMatrix::<f64, M, N>::from_fn(|k, a| self.jet_entry(z, k, a));
        let mut rises = self.rises;
        rises.set_column(N - 1, &(z - self.first));
        AffineFrame {
            inverse: self.inverse,
            volume: self.volume,
            centre: self.centre,
            value: self.value(z),
            jet,
            rises,
        }
    }

    /// ȳ with the last vertex value `z` (the bits of the completed frame's).
    #[inline]
    pub(super) fn value(&self, z: &SVector<f64, M>) -> SVector<f64, M> {
        completed_mean::<M, N>(&self.sum, z)
    }

    /// φ_{ka} with the last vertex value `z` (the completed frame's entry).
    #[inline]
    pub(super) fn jet_entry(&self, z: &SVector<f64, M>, k: usize, a: usize) -> f64 {
        completed_jet_entry(self.jet[(k, a)], z[k] - self.first[k], self.inverse[(N - 1, a)])
    }
}

/// φ_{ka} of a frame completed by its last vertex value z: the known
/// vertices' part φ̃_{ka} plus `rise` = (z − y₀)_k times c_{Na} =
/// (T^X)⁻¹_{N−1,a}: how [`PartialFrame`] completes a frame.
#[inline(always)]
pub(super) fn completed_jet_entry(known: f64, rise: f64, last_row: f64) -> f64 {
    known + rise * last_row
}

/// ȳ of a frame completed by its last vertex value z: (y₀ + … + y_{N−1} + z)/(N + 1)
/// from the known vertices' `sum`, the one formula of [`PartialFrame`] and
/// the metric star's lanes.
#[inline(always)]
pub(super) fn completed_mean<const M: usize, const N: usize>(
    sum: &SVector<f64, M>,
    z: &SVector<f64, M>,
) -> SVector<f64, M> {
    (sum + z) * AffineFrame::<M, N>::mean_weight()
}

/// Cells in the star of a vertex that [`MidpointRule`]'s own vertex solve
/// handles (N! ≤ 4!, as its shape cache).
pub(super) const MAX_STAR: usize = 24;
