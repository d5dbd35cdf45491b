//! [`MidpointRule`]'s vertex solve for a density with a diagonal jet metric
//! ([`SmoothDensity::diagonal_jet_metric`]: 𝓛 = ½ Σ_{k,a} η_a φ_{ka}² + V(x, y),
//! e.g. the nonlinear waves of seed 002 (4.32) in any dimension).
//!
//! The vertex equation Leg_v(z) = Σ_β ∂L_β/∂y₀ = μ_v (note 003 §2.4) sums,
//! over the cells β based at v whose last vertex z is unknown,
//!
//! ∂L_β/∂y₀ = vol_β·(Σ_a η_a φ_{·a}(z) c_{0a} + ∇V(x̄_β, ȳ_β(z))/(N + 1))
//!          = κ_β + K_{0N}(z − y₀) + (vol_β/(N + 1)) ∇V(x̄_β, ȳ_β(z)),
//!
//! with the cell's metric table K_{lj} = vol_β Σ_a η_a c_{la} c_{ja}
//! ([`metric_table_row`]), κ_β = Σ_{j<N} K_{0j}(y_j − y₀) the known rises'
//! part and ȳ_β(z) = (s_β + z)/(N + 1) (s_β the known vertices' sum,
//! `PartialFrame::sum_and_rises`), and
//!
//! ∂²L_β/∂y₀∂z = vol_β·(b_β I + ∇²V(ȳ_β(z))/(N + 1)²),  vol_β b_β = K_{0N}.
//!
//! An evaluation of the equation is one evaluation of V per cell (over
//! M-direction dual numbers; second order for the Jacobian; all the star's
//! cells at once where the density batches them,
//! [`SmoothDensity::jet_free_derivatives`], with the same bits) and the jet
//! term completed from κ_β, with the table formed once per cell geometry
//! and κ_β once per vertex (this table form took 9.8 % fewer instructions
//! per 2+1 sine-Gordon update than forming and contracting the jet φ at
//! every evaluation). Up to [`METRIC_LANES`] vertices of a level are
//! solved together, each by its own [`LegendreNewton`]: every Newton round
//! differentiates V at the star cells of all the lanes still iterating in
//! one batch, and the sums over the cells run with the lanes side by side;
//! a lane's evaluations and bits are those it has alone. The residual is computed by the operations of the
//! rule's own gradients ([`metric_gradient_from`]), so Newton zeroes the
//! equation the marcher's momenta are made of (a residual of another
//! rounding, affine in z, let the translation momenta of a free field drift
//! by 6e-12 relative over 1000 levels instead of 2e-14). The solved cells' gradients for the
//! marcher are formed once at the accepted z, from ∇V of the last
//! evaluation at that very point: the operations and bits of
//! [`DiscreteLagrangian::analytic_gradients`](crate::field::cell::DiscreteLagrangian::analytic_gradients),
//! which a restored march recomputes from the values.

use nalgebra::{SMatrix, SVector};

use super::affine::MidpointRule;
use super::affine_chain::{AffineFrame, PartialFrame, completed_mean};
use super::metric_terms::{
    metric_completed, metric_gradient_from, metric_known_part, metric_table_row, potential_weight,
};
use super::nodes::NodeMap;
use super::smooth::SmoothDensity;
use crate::field::cell::{SolvedVertex, VertexLane};
use crate::field::complex::TopCell;
use crate::field::fibre::{Euclidean, Fibre};
use crate::field::legendre::{CauchyOptions, LegendreNewton};

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
    volume: f64,
    centre: SVector<f64, N>,
    /// Rows l = 0 … N of the table K_{lj} ([`metric_table_row`]): row 0
    /// weighs the unknown's equation, rows 1 … N the solved cell's later
    /// gradients.
    table: [SVector<f64, N>; METRIC_CELL_VERTICES],
    /// vol_β/(N + 1), the weight of ∇V ([`potential_weight`]).
    potential: f64,
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
    fn slope(&self) -> f64 {
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
    fn at(&self, c: usize, l: usize) -> &CellWeights<N> {
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
    gradients: &'a mut [SVector<f64, M>],
    stride: usize,
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
    fn known_parts<'g>(
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
    fn write_gradients<'g>(
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
    fn residuals<'g>(
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
    fn jacobians<'g>(
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
    gradient: [[SVector<f64, M>; METRIC_LANES]; C],
    hessian: [[SMatrix<f64, M, M>; METRIC_LANES]; C],
    centres: [[SVector<f64, N>; METRIC_LANES]; C],
    values: [[SVector<f64, M>; METRIC_LANES]; C],
    packed_gradient: [[SVector<f64, M>; METRIC_LANES]; C],
    packed_hessian: [[SMatrix<f64, M, M>; METRIC_LANES]; C],
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

impl<L, X, const N: usize> MidpointRule<L, X, N>
where
    X: NodeMap<N>,
{
    /// Whether the rule's
    /// [`solve_vertex_run`](crate::field::cell::DiscreteLagrangian::solve_vertex_run)
    /// solves several vertices at once.
    pub(super) fn has_metric_lanes<const M: usize>(&self) -> bool
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        (1..=4).contains(&N) && self.density.diagonal_jet_metric().is_some()
    }

    /// The lanes' stars of C = N! cells from `star(l, σ, out)` (their
    /// cells' sums over the known vertices, their geometry and first
    /// guesses), solved by [`solve_metric_stars`](Self::solve_metric_stars);
    /// `false` (nothing solved) for a failed frame or a lane none of whose
    /// cells is in the action.
    pub(super) fn metric_lanes_of<const M: usize, const C: usize, S>(
        &self,
        eta: &SVector<f64, N>,
        star: &S,
        lanes: &[VertexLane<SVector<f64, M>, M>],
        options: &CauchyOptions,
        out: LaneOutput<'_, M>,
    ) -> bool
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
        S: Fn(usize, usize, &mut [SVector<f64, M>]) -> Option<TopCell>,
    {
        let width = N + 1;
        let blank = MetricStar {
            mu: SVector::zeros(),
            mu_scale: 0.0,
            start: SVector::zeros(),
        };
        let mut stars = [blank; METRIC_LANES];
        // The cells' values and their geometry: each position's shape once
        // while every lane's cell there has its shape's cached geometry,
        // else (a second pass) each cell's own. All the stars' values are
        // gathered before any is read (a value read back right after its
        // store would wait for it).
        let mut y = [[[SVector::<f64, M>::zeros(); METRIC_CELL_VERTICES]; C]; METRIC_LANES];
        let mut cells: [[Option<TopCell>; C]; METRIC_LANES] = [[None; C]; METRIC_LANES];
        for (l, (lane_cells, lane_values)) in cells.iter_mut().zip(y.iter_mut()).enumerate().take(lanes.len()) {
            for (c, (cell, values)) in lane_cells.iter_mut().zip(lane_values.iter_mut()).enumerate() {
                *cell = star(l, c, &mut values[..width]);
            }
        }
        let mut frames = LaneFrames::<M, N, C>::new();
        // Each position's shape and, once seen, its weights (`blank` for a
        // position no lane has a cell at).
        let blank = CellWeights::new(SMatrix::zeros(), 0.0, SVector::zeros(), eta);
        let mut shapes: [Option<usize>; C] = [None; C];
        let mut table = [blank; C];
        let position = self.density.depends_on_position();
        let mut uniform = !position;
        for (l, (lane, s)) in lanes.iter().zip(stars.iter_mut()).enumerate() {
            let mut base = None;
            for c in 0..C {
                let Some(cell) = &cells[l][c] else {
                    continue;
                };
                let y = &y[l][c];
                base.get_or_insert(y[0]);
                // The shape's cached geometry in place (its cell's own only
                // where the density depends on position or none is cached).
                let cached = if position {
                    None
                } else {
                    self.shape_geometry(cell.shape)
                };
                // (A degenerate cell fails in the geometry pass below.)
                match cached {
                    Some((inverse, volume)) if uniform => match shapes[c] {
                        None => {
                            shapes[c] = Some(cell.shape);
                            table[c] = CellWeights::new(*inverse, *volume, SVector::zeros(), eta);
                        }
                        Some(shape) if shape == cell.shape => {}
                        Some(_) => uniform = false,
                    },
                    Some(_) => {}
                    None => uniform = false,
                }
                frames.active[c][l] = true;
                frames.set_cell(c, l, &y[..width]);
            }
            let Some(base) = base else {
                return false;
            };
            frames.first[l] = base;
            s.mu = lane.mu;
            s.mu_scale = lane.mu_scale;
            s.start = Euclidean::<M>::extrapolate(&lane.previous, &base);
        }
        let count = lanes.len().min(METRIC_LANES);
        frames.seal(count);
        if uniform {
            let geometry = StarGeometry::Shapes(&table);
            self.solve_metric_stars(&frames, geometry, &stars[..count], options, out, &mut Potentials::new());
            return true;
        }
        let mut geometry = [[blank; METRIC_LANES]; C];
        for (l, lane_cells) in cells.iter().enumerate().take(count) {
            for (row, cell) in geometry.iter_mut().zip(lane_cells) {
                if let Some(cell) = cell {
                    let Some((inverse, volume, centre)) = self.cell_geometry::<M>(cell) else {
                        return false;
                    };
                    row[l] = CellWeights::new(inverse, volume, centre, eta);
                }
            }
        }
        self.solve_metric_stars(
            &frames,
            StarGeometry::Cells(&geometry),
            &stars[..count],
            options,
            out,
            &mut Potentials::new(),
        );
        true
    }

    /// ∇V, with ∇²V when `second`, at ȳ_β(z_l) of every active cell of the
    /// lanes l with `wanted[l] == Some(second)`, in one batch
    /// ([`jet_free_batch`](Self::jet_free_batch)): straight into `out` when
    /// every cell of every lane is wanted, else packed and unpacked.
    fn lane_potentials<const M: usize, const C: usize>(
        &self,
        frames: &LaneFrames<M, N, C>,
        geometry: StarGeometry<'_, N, C>,
        z: &[SVector<f64, M>; METRIC_LANES],
        wanted: &[Option<bool>; METRIC_LANES],
        second: bool,
        out: &mut Potentials<M, N, C>,
    ) where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        if !wanted.contains(&Some(second)) {
            return;
        }
        if frames.full && wanted.iter().all(|&x| x == Some(second)) {
            for c in 0..C {
                for l in 0..METRIC_LANES {
                    out.values[c][l] = completed_mean::<M, N>(&frames.sum[c][l], &z[l]);
                }
            }
            let hessians = second.then_some(out.hessian.as_flattened_mut());
            // A shape's weights have no centre: the centres stay zero.
            if let StarGeometry::Cells(cells) = geometry {
                for c in 0..C {
                    for l in 0..METRIC_LANES {
                        out.centres[c][l] = cells[c][l].centre;
                    }
                }
            }
            self.jet_free_batch(
                out.centres.as_flattened(),
                out.values.as_flattened(),
                out.gradient.as_flattened_mut(),
                hessians,
            );
            return;
        }
        let mut count = 0;
        {
            let (centres, values) = (out.centres.as_flattened_mut(), out.values.as_flattened_mut());
            for c in 0..C {
                for l in 0..METRIC_LANES {
                    if frames.active[c][l] && wanted[l] == Some(second) {
                        centres[count] = geometry.at(c, l).centre;
                        values[count] = completed_mean::<M, N>(&frames.sum[c][l], &z[l]);
                        count += 1;
                    }
                }
            }
        }
        let asked = second.then_some(&mut out.packed_hessian.as_flattened_mut()[..count]);
        self.jet_free_batch(
            &out.centres.as_flattened()[..count],
            &out.values.as_flattened()[..count],
            &mut out.packed_gradient.as_flattened_mut()[..count],
            asked,
        );
        let (gradients, hessians) = (out.packed_gradient.as_flattened(), out.packed_hessian.as_flattened());
        let mut k = 0;
        for c in 0..C {
            for l in 0..METRIC_LANES {
                if frames.active[c][l] && wanted[l] == Some(second) {
                    out.gradient[c][l] = gradients[k];
                    out.hessian[c][l] = hessians[k];
                    k += 1;
                }
            }
        }
    }

    /// Solves the vertex equations Leg_v(z) = μ_v of up to
    /// [`METRIC_LANES`] stars at once (`frames`, lane l the equation of
    /// `stars[l]`), each by the generic Newton ([`LegendreNewton`]) from
    /// its start, and writes each solved star's gradients at its z into
    /// `gradients[l·stride..]` (the marcher's layout, N + 1 per cell, zero
    /// at the base vertex and for absent cells). Each Newton round
    /// differentiates V at the cells of every lane still iterating in one
    /// batch; a lane's evaluations are the ones it would make alone, with
    /// the same bits. `potentials` is scratch, whatever it holds.
    pub(super) fn solve_metric_stars<const M: usize, const C: usize>(
        &self,
        frames: &LaneFrames<M, N, C>,
        geometry: StarGeometry<'_, N, C>,
        stars: &[MetricStar<M>],
        options: &CauchyOptions,
        out: LaneOutput<'_, M>,
        potentials: &mut Potentials<M, N, C>,
    ) where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        let LaneOutput {
            gradients,
            stride,
            solved,
        } = out;
        let lanes = stars.len().min(METRIC_LANES);
        let mut newton: [Option<LegendreNewton<Euclidean<M>, M>>; METRIC_LANES] = std::array::from_fn(|_| None);
        for (slot, star) in newton.iter_mut().zip(&stars[..lanes]) {
            *slot = Some(LegendreNewton::new(star.mu, star.mu_scale, star.start, *options, None));
        }
        // The point of each lane's last evaluation when it was a
        // residual-only one (∇V from a Jacobian evaluation's second-order
        // pass is not what the stored gradients use).
        let mut written: [Option<SVector<f64, M>>; METRIC_LANES] = [None; METRIC_LANES];
        let mut z = [SVector::<f64, M>::zeros(); METRIC_LANES];
        let known = match geometry {
            StarGeometry::Shapes(shapes) => frames.known_parts(|c, _| &shapes[c]),
            StarGeometry::Cells(cells) => frames.known_parts(|c, l| &cells[c][l]),
        };
        loop {
            let mut wanted = [None; METRIC_LANES];
            for l in 0..lanes {
                if let Some(n) = &newton[l] {
                    wanted[l] = n.wants_jacobian();
                    z[l] = *n.point();
                }
            }
            if wanted.iter().all(Option::is_none) {
                break;
            }
            self.lane_potentials(frames, geometry, &z, &wanted, true, potentials);
            self.lane_potentials(frames, geometry, &z, &wanted, false, potentials);
            let (leg, scale) = match geometry {
                StarGeometry::Shapes(shapes) => frames.residuals(&z, &known, &potentials.gradient, |c, _| &shapes[c]),
                StarGeometry::Cells(cells) => frames.residuals(&z, &known, &potentials.gradient, |c, l| &cells[c][l]),
            };
            let mut jacobian = [SMatrix::<f64, M, M>::zeros(); METRIC_LANES];
            if wanted.contains(&Some(true)) {
                let asked: [bool; METRIC_LANES] = std::array::from_fn(|l| wanted[l] == Some(true));
                jacobian = match geometry {
                    StarGeometry::Shapes(shapes) => frames.jacobians(&asked, &potentials.hessian, |c, _| &shapes[c]),
                    StarGeometry::Cells(cells) => frames.jacobians(&asked, &potentials.hessian, |c, l| &cells[c][l]),
                };
            }
            for l in 0..lanes {
                if let (Some(jac), Some(n)) = (wanted[l], newton[l].as_mut()) {
                    n.feed(&leg[l], scale[l], &jacobian[l]);
                    written[l] = (!jac).then_some(z[l]);
                }
            }
        }
        // The solved lanes whose last evaluation was not a residual-only
        // one at their z: ∇V there, in one batch.
        let mut again = [None; METRIC_LANES];
        for l in 0..lanes {
            let Some(n) = newton[l].take() else { continue };
            let (point, outcome, _) = n.finish();
            z[l] = point;
            solved[l] = SolvedVertex {
                value: point,
                outcome,
                gradients_written: outcome.failure.is_none(),
                forces_written: false,
            };
            if outcome.failure.is_none() && written[l] != Some(point) {
                again[l] = Some(false);
            }
        }
        self.lane_potentials(frames, geometry, &z, &again, false, potentials);
        let written: [bool; METRIC_LANES] = std::array::from_fn(|l| l < lanes && solved[l].gradients_written);
        let out = LaneGradients { gradients, stride };
        match geometry {
            StarGeometry::Shapes(shapes) => {
                frames.write_gradients(&z, &potentials.gradient, &written, out, |c, _| &shapes[c])
            }
            StarGeometry::Cells(cells) => {
                frames.write_gradients(&z, &potentials.gradient, &written, out, |c, l| &cells[c][l])
            }
        }
    }
}
