//! The lanes of the midpoint rule's metric solve: the star of vertex
//! equations solved side by side, their cells' weights, geometry, frames and
//! batched potentials (the data of [`super::metric_star`]).

use nalgebra::{SMatrix, SVector};

use super::affine_frame::{AffineFrame, PartialFrame};
use super::metric_terms::{
    metric_completed, metric_gradient_from, metric_known_part, metric_table_row, potential_weight,
};
use crate::field::cell::SolvedVertex;

/// Vertex equations [`MidpointRule`]'s metric solve treats together: their
/// cells' potentials are differentiated in one batch per Newton round, and
/// the sums over the cells run over the lanes side by side. Eight took
/// 4.7 % fewer instructions per 2+1 sine-Gordon vertex update than four
/// (the rounds' fixed costs shared by more vertices), sixteen another
/// 0.7 % with twice the stack.
pub(super) const METRIC_LANES: usize = 8;

/// Vertices of a star cell of the metric lanes (N + 1 for N ≤ 4).
pub(super) const METRIC_CELL_VERTICES: usize = 5;

/// One vertex equation of [`MidpointRule::solve_metric_stars`]: μ_v, the
/// size of μ_v's terms and the first guess.
#[derive(Clone, Copy)]
pub(super) struct MetricStar<const M: usize> {
    pub(super) mu: SVector<f64, M>,
    pub(super) mu_scale: f64,
    pub(super) start: SVector<f64, M>,
}

/// A star cell's geometry (vol_β, x̄) and its weights: the rows of its
/// metric table and vol_β/(N + 1).
#[derive(Clone, Copy)]
pub(super) struct CellWeights<const N: usize> {
    pub(super) volume: f64,
    pub(super) centre: SVector<f64, N>,
    /// Rows l = 0 … N of the table K_{lj} ([`metric_table_row`]): row 0
    /// weighs the unknown's equation, rows 1 … N the solved cell's later
    /// gradients.
    pub(super) table: [SVector<f64, N>; METRIC_CELL_VERTICES],
    /// vol_β/(N + 1), the weight of ∇V ([`potential_weight`]).
    pub(super) potential: f64,
}

impl<const N: usize> CellWeights<N> {
    pub(super) fn new(
        inverse: SMatrix<f64, N, N>,
        volume: f64,
        centre: SVector<f64, N>,
        eta: &SVector<f64, N>,
    ) -> Self {
        Self {
            volume,
            centre,
            table: std::array::from_fn(|l| {
                if l <= N {
                    metric_table_row(&inverse, eta, volume, l)
                } else {
                    SVector::zeros()
                }
            }),
            potential: potential_weight::<N>(volume),
        }
    }

    /// vol_β Σ_a η_a c_{0a} c_{Na} = K_{0N}: the jet part of ∂Leg/∂z.
    #[inline]
    pub(super) fn slope(&self) -> f64 {
        self.table[0][N - 1]
    }
}

/// The cells' geometry of a group of stars: one per cell position when
/// every lane's cell there has its shape's cached geometry (a translation
/// invariant lattice), else one per cell and lane.
#[derive(Clone, Copy)]
pub(super) enum StarGeometry<'a, const N: usize, const C: usize> {
    Shapes(&'a [CellWeights<N>; C]),
    Cells(&'a [[CellWeights<N>; METRIC_LANES]; C]),
}

impl<const N: usize, const C: usize> StarGeometry<'_, N, C> {
    /// The geometry of cell c of lane l.
    #[inline]
    pub(super) fn at(&self, c: usize, l: usize) -> &CellWeights<N> {
        match self {
            StarGeometry::Shapes(shapes) => &shapes[c],
            StarGeometry::Cells(cells) => &cells[c][l],
        }
    }
}

/// Where [`MidpointRule::solve_metric_stars`] writes: lane l's cells'
/// gradients at `gradients[l·stride..]`, its result at `solved[l]`.
pub(super) struct LaneOutput<'a, const M: usize> {
    pub(super) gradients: &'a mut [SVector<f64, M>],
    pub(super) stride: usize,
    pub(super) solved: &'a mut [SolvedVertex<SVector<f64, M>>],
}

/// Where the solved lanes' cell gradients go: lane l's at
/// `gradients[l·stride..]`.
pub(super) struct LaneGradients<'a, const M: usize> {
    pub(super) gradients: &'a mut [SVector<f64, M>],
    pub(super) stride: usize,
}

/// The known vertices' sums of the star cells of up to [`METRIC_LANES`]
/// vertices, cell by cell, then lane by lane (the lanes' numbers side by
/// side for the Newton rounds' sums).
pub(super) struct LaneFrames<const M: usize, const N: usize, const C: usize> {
    /// Whether cell c of lane l is in the action.
    pub(super) active: [[bool; METRIC_LANES]; C],
    /// Whether every cell of every lane is.
    pub(super) full: bool,
    /// y₀, the base vertex's value (each cell's first vertex).
    pub(super) first: [SVector<f64, M>; METRIC_LANES],
    /// y₀ + … + y_{N−1}.
    pub(super) sum: [[SVector<f64, M>; METRIC_LANES]; C],
    /// The known rises y_{a+1} − y₀ (a < N − 1).
    pub(super) rises: [[[SVector<f64, M>; METRIC_LANES]; N]; C],
}

impl<const M: usize, const N: usize, const C: usize> LaneFrames<M, N, C> {
    /// No lane in the action, every sum zero.
    pub(super) fn new() -> Self {
        Self {
            active: [[false; METRIC_LANES]; C],
            full: false,
            first: [SVector::zeros(); METRIC_LANES],
            sum: [[SVector::zeros(); METRIC_LANES]; C],
            rises: [[[SVector::zeros(); METRIC_LANES]; N]; C],
        }
    }

    /// Cell c's sum and known rises from its values `y[..N]` into lane l
    /// ([`PartialFrame::sum_and_rises`]).
    #[inline(always)]
    pub(super) fn set_cell(&mut self, c: usize, l: usize, y: &[SVector<f64, M>]) {
        let (sum, rises) = PartialFrame::<M, N>::sum_and_rises(y);
        self.sum[c][l] = sum;
        for a in 0..N {
            self.rises[c][a][l] = rises.column(a).into_owned();
        }
    }

    /// The known rises' part of every cell's term in the unknown's equation
    /// ([`metric_known_part`] with row 0 of the cells' tables), by cell then
    /// lane: formed once per group, completed at every evaluation.
    #[inline(always)]
    pub(super) fn known_parts<'g>(
        &self,
        weights: impl Fn(usize, usize) -> &'g CellWeights<N>,
    ) -> [[SVector<f64, M>; METRIC_LANES]; C] {
        std::array::from_fn(|c| {
            std::array::from_fn(|l| {
                let row = &weights(c, l).table[0];
                SVector::from_fn(|k, _| metric_known_part(row, |a| self.rises[c][a][l][k]))
            })
        })
    }

    /// Records whether all `lanes` lanes have all their cells in the action.
    pub(super) fn seal(&mut self, lanes: usize) {
        self.full = lanes == METRIC_LANES && self.active.iter().flatten().all(|&a| a);
    }

    /// The cells' gradients at positions 1 … N of every lane l with
    /// `written[l]`, at its solved z (∇V of the cells there in `dv`), into
    /// `out` (the marcher's layout: N + 1 per cell, zero at the base vertex
    /// and for cells outside the action): `metric_gradient` with the cells'
    /// weights `weights(c, l)` formed once. Out of line, as
    /// [`jacobians`](Self::jacobians): inlined into the Newton loop the two
    /// took 3.8 % more instructions per 2+1 vertex update.
    #[inline(never)]
    pub(super) fn write_gradients<'g>(
        &self,
        z: &[SVector<f64, M>; METRIC_LANES],
        dv: &[[SVector<f64, M>; METRIC_LANES]; C],
        written: &[bool; METRIC_LANES],
        out: LaneGradients<'_, M>,
        weights: impl Fn(usize, usize) -> &'g CellWeights<N>,
    ) {
        let width = N + 1;
        for l in (0..METRIC_LANES).filter(|&l| written[l]) {
            let lane = &mut out.gradients[l * out.stride..l * out.stride + C * width];
            lane.fill(SVector::zeros());
            let last = z[l] - self.first[l];
            for c in (0..C).filter(|&c| self.active[c][l]) {
                let t = weights(c, l);
                let rise = |a: usize, i: usize| if a + 1 < N { self.rises[c][a][l][i] } else { last[i] };
                for (k, g) in lane[c * width..(c + 1) * width].iter_mut().enumerate().skip(1) {
                    *g = metric_gradient_from::<M, N>(&t.table[k], rise, &dv[c][l], t.potential);
                }
            }
        }
    }

    /// Σ_cells (Σ_j K_{0j}(y_j − y₀) + vol_β∇V/(N + 1)) of every lane and
    /// its size: the known rises' parts `known` ([`known_parts`](Self::known_parts))
    /// completed by the last rise z − y₀ ([`metric_completed`], as
    /// `metric_gradient_from` completes them), lanes side by side, with the cells'
    /// geometry `weights(c, l)`.
    #[inline(always)]
    pub(super) fn residuals<'g>(
        &self,
        z: &[SVector<f64, M>; METRIC_LANES],
        known: &[[SVector<f64, M>; METRIC_LANES]; C],
        dv: &[[SVector<f64, M>; METRIC_LANES]; C],
        weights: impl Fn(usize, usize) -> &'g CellWeights<N>,
    ) -> ([SVector<f64, M>; METRIC_LANES], [f64; METRIC_LANES]) {
        let mut leg = [SVector::<f64, M>::zeros(); METRIC_LANES];
        let mut scale = [0.0; METRIC_LANES];
        let d: [SVector<f64, M>; METRIC_LANES] = std::array::from_fn(|l| z[l] - self.first[l]);
        for c in 0..C {
            // All the lanes' terms first, then their sums: straight-line
            // arithmetic over the lanes, which the compiler vectorises.
            let g: [SVector<f64, M>; METRIC_LANES] = std::array::from_fn(|l| {
                let t = weights(c, l);
                let last = t.table[0][N - 1];
                SVector::<f64, M>::from_fn(|k, _| {
                    metric_completed(known[c][l][k], last, d[l][k], dv[c][l][k] * t.potential)
                })
            });
            for l in 0..METRIC_LANES {
                if self.full || self.active[c][l] {
                    leg[l] += g[l];
                    scale[l] += g[l].amax();
                }
            }
        }
        (leg, scale)
    }

    /// Σ_cells vol_β(b_β I + ∇²V/(N + 1)²) of every lane l with
    /// `asked[l]` (zero for the others), from the cells' ∇²V, lanes side by
    /// side with the cells' geometry `weights(c, l)`. Out of line (see
    /// [`write_gradients`](Self::write_gradients)).
    #[inline(never)]
    pub(super) fn jacobians<'g>(
        &self,
        asked: &[bool; METRIC_LANES],
        hessians: &[[SMatrix<f64, M, M>; METRIC_LANES]; C],
        weights: impl Fn(usize, usize) -> &'g CellWeights<N>,
    ) -> [SMatrix<f64, M, M>; METRIC_LANES] {
        let w = AffineFrame::<M, N>::mean_weight();
        let mut jacobian = [SMatrix::<f64, M, M>::zeros(); METRIC_LANES];
        for c in 0..C {
            let terms: [SMatrix<f64, M, M>; METRIC_LANES] = std::array::from_fn(|l| {
                let t = weights(c, l);
                SMatrix::<f64, M, M>::identity() * t.slope() + hessians[c][l] * (w * w * t.volume)
            });
            for l in 0..METRIC_LANES {
                if asked[l] && (self.full || self.active[c][l]) {
                    jacobian[l] += terms[l];
                }
            }
        }
        jacobian
    }
}

/// ∇V (and ∇²V) at every active cell of the lanes, by cell then lane, and
/// the points they are taken at: the scratch of
/// [`MidpointRule::solve_metric_stars`], reused from one group of stars to
/// the next (every entry a group reads is written for it first, but the
/// centres of a shape's weights, which stay zero).
pub(super) struct Potentials<const M: usize, const N: usize, const C: usize> {
    pub(super) gradient: [[SVector<f64, M>; METRIC_LANES]; C],
    pub(super) hessian: [[SMatrix<f64, M, M>; METRIC_LANES]; C],
    pub(super) centres: [[SVector<f64, N>; METRIC_LANES]; C],
    pub(super) values: [[SVector<f64, M>; METRIC_LANES]; C],
    pub(super) packed_gradient: [[SVector<f64, M>; METRIC_LANES]; C],
    pub(super) packed_hessian: [[SMatrix<f64, M, M>; METRIC_LANES]; C],
}

impl<const M: usize, const N: usize, const C: usize> Potentials<M, N, C> {
    /// All zero.
    pub(super) fn new() -> Self {
        Self {
            gradient: [[SVector::zeros(); METRIC_LANES]; C],
            hessian: [[SMatrix::zeros(); METRIC_LANES]; C],
            centres: [[SVector::zeros(); METRIC_LANES]; C],
            values: [[SVector::zeros(); METRIC_LANES]; C],
            packed_gradient: [[SVector::zeros(); METRIC_LANES]; C],
            packed_hessian: [[SMatrix::zeros(); METRIC_LANES]; C],
        }
    }
}
