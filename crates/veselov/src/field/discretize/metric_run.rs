//! Where [`MidpointRule`]'s metric solve ([`super::metric_star`]) is
//! entered: a run of consecutive vertices of a Cauchy level
//! ([`VertexRun`], the marcher's fast path) or the star of a single vertex
//! (`solve_star`, for a march confined to a window or with prescribed
//! values).
//!
//! A run gathers each vertex's star straight from the level
//! ([`VertexRun::star_values`]) and weighs every cell with its shape's
//! weights, formed once per run (a translation-invariant lattice, where a
//! vertex's cell σ has the same shape at every vertex: the density does
//! not depend on position and every shape has its cached geometry); the
//! vertices are then solved eight at a time by
//! `solve_metric_stars`. The known sums and rises of each cell are those of
//! [`PartialFrame::sum_and_rises`](super::affine_frame::PartialFrame::sum_and_rises) and the first guess is the fibre's extrapolation,
//! as for a single star, so every vertex gets the bits it gets alone.

use nalgebra::{SMatrix, SVector};

use super::affine::MidpointRule;
use super::metric_lanes::{
    CellWeights, LaneFrames, LaneOutput, METRIC_CELL_VERTICES, METRIC_LANES, MetricStar, Potentials, StarGeometry,
};
use super::nodes::{NodeMap, factorial};
use super::smooth::SmoothDensity;
use crate::complex::TopCell;
use crate::field::cell::{VertexLane, VertexRun};
use crate::field::fibre::{Euclidean, Fibre};
use crate::field::legendre::CauchyOptions;

impl<L, X, const N: usize> MidpointRule<L, X, N>
where
    X: NodeMap<N>,
{
    /// The stars of up to [`METRIC_LANES`] vertices, lane l's cell σ from
    /// `star(l, σ, out)` and its momentum from `lanes[l]`, solved together
    /// by the metric solve, each with the bits of its own solve; `false`
    /// (nothing solved) without a diagonal jet metric, for N > 4, more
    /// lanes, too small outputs, a failed frame or a lane none of whose
    /// cells is in the action.
    pub(super) fn solve_metric_lanes<const M: usize, S>(
        &self,
        star: &S,
        lanes: &[VertexLane<SVector<f64, M>, M>],
        options: &CauchyOptions,
        out: LaneOutput<'_, M>,
    ) -> bool
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
        S: Fn(usize, usize, &mut [SVector<f64, M>]) -> Option<TopCell>,
    {
        let Some(eta) = self.density.diagonal_jet_metric() else {
            return false;
        };
        let per_vertex = factorial(N) * (N + 1);
        if lanes.len() > METRIC_LANES
            || out.solved.len() < lanes.len()
            || out.stride < per_vertex
            || out.gradients.len() < out.stride * lanes.len()
        {
            return false;
        }
        // N is a constant of the monomorphised rule: only its own arm (the
        // star size C = N!) is compiled in.
        match N {
            1 => self.metric_lanes_of::<M, 1, S>(&eta, star, lanes, options, out),
            2 => self.metric_lanes_of::<M, 2, S>(&eta, star, lanes, options, out),
            3 => self.metric_lanes_of::<M, 6, S>(&eta, star, lanes, options, out),
            4 => self.metric_lanes_of::<M, 24, S>(&eta, star, lanes, options, out),
            _ => false,
        }
    }

    /// Solves every vertex of `run` by the metric solve, up to
    /// [`VertexRun::lanes`] (at most [`METRIC_LANES`]) at a time, vertex k's
    /// cells' gradients into `out.gradients[k·stride..]` and its result
    /// into `out.solved[k]`; `false` (to be solved one at a time) without a
    /// diagonal jet metric, for N > 4, a run of another dimension, too small
    /// outputs, or a failed frame (a degenerate cell; the groups before it
    /// may have been written).
    pub(super) fn solve_metric_run<const M: usize, R>(
        &self,
        run: &R,
        options: &CauchyOptions,
        out: LaneOutput<'_, M>,
    ) -> bool
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
        R: VertexRun<SVector<f64, M>, M>,
    {
        let Some(eta) = self.density.diagonal_jet_metric() else {
            return false;
        };
        let per_vertex = factorial(N) * (N + 1);
        if run.dimension() != N
            || out.solved.len() < run.len()
            || out.stride < per_vertex
            || out.gradients.len() < out.stride * run.len()
        {
            return false;
        }
        match N {
            1 => self.metric_run_of::<M, 1, R>(&eta, run, options, out),
            2 => self.metric_run_of::<M, 2, R>(&eta, run, options, out),
            3 => self.metric_run_of::<M, 6, R>(&eta, run, options, out),
            4 => self.metric_run_of::<M, 24, R>(&eta, run, options, out),
            _ => false,
        }
    }

    /// [`solve_metric_run`](Self::solve_metric_run) for stars of C = N!
    /// cells: with the shapes' weights formed once where the lattice is
    /// translation invariant, else group by group through
    /// `metric_lanes_of` (each cell's own geometry).
    fn metric_run_of<const M: usize, const C: usize, R>(
        &self,
        eta: &SVector<f64, N>,
        run: &R,
        options: &CauchyOptions,
        out: LaneOutput<'_, M>,
    ) -> bool
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
        R: VertexRun<SVector<f64, M>, M>,
    {
        let width = N + 1;
        let LaneOutput {
            gradients,
            stride,
            solved,
        } = out;
        if run.is_empty() {
            return true;
        }
        let lanes = run.lanes().clamp(1, METRIC_LANES);
        let blank = CellWeights::new(SMatrix::zeros(), 0.0, SVector::zeros(), eta);
        let mut table = [blank; C];
        let mut uniform = !self.density.depends_on_position();
        for (sigma, weights) in table.iter_mut().enumerate() {
            if !uniform {
                break;
            }
            match self.shape_geometry(run.star_cell(0, sigma).shape) {
                Some((inv, volume)) => *weights = CellWeights::new(*inv, *volume, SVector::zeros(), eta),
                None => uniform = false,
            }
        }
        // The groups' scratch, filled anew for each group.
        let mut frames = LaneFrames::<M, N, C>::new();
        let mut stars = [MetricStar {
            mu: SVector::zeros(),
            mu_scale: 0.0,
            start: SVector::zeros(),
        }; METRIC_LANES];
        let mut potentials = Potentials::<M, N, C>::new();
        let mut first = 0;
        while first < run.len() {
            let count = lanes.min(run.len() - first);
            let out = LaneOutput {
                gradients: &mut gradients[first * stride..(first + count) * stride],
                stride,
                solved: &mut solved[first..first + count],
            };
            if uniform {
                Self::run_frames::<M, C, R>(run, first, count, &mut frames, &mut stars);
                let geometry = StarGeometry::Shapes(&table);
                self.solve_metric_stars(&frames, geometry, &stars[..count], options, out, &mut potentials);
            } else {
                let star = |l: usize, sigma: usize, out: &mut [SVector<f64, M>]| {
                    run.star_values(first + l, sigma, &mut out[..width]);
                    Some(run.star_cell(first + l, sigma))
                };
                let placeholder = VertexLane {
                    mu: SVector::zeros(),
                    mu_scale: 0.0,
                    previous: SVector::zeros(),
                };
                let mut vertex_lanes = [placeholder; METRIC_LANES];
                for (l, lane) in vertex_lanes.iter_mut().enumerate().take(count) {
                    *lane = run.lane(first + l);
                }
                if !self.metric_lanes_of::<M, C, _>(eta, &star, &vertex_lanes[..count], options, out) {
                    return false;
                }
            }
            first += count;
        }
        true
    }

    /// The known sums and rises of the star cells of the `count` vertices
    /// `first …` of `run` ([`LaneFrames::set_cell`]) into
    /// lanes 0 … count − 1 of `frames` (the other lanes outside the action)
    /// and their equations into `stars` (μ_v, its size, the fibre's
    /// extrapolation from y_{v−Δ} through y_v as the first guess).
    #[inline(always)]
    fn run_frames<const M: usize, const C: usize, R>(
        run: &R,
        first: usize,
        count: usize,
        frames: &mut LaneFrames<M, N, C>,
        stars: &mut [MetricStar<M>; METRIC_LANES],
    ) where
        R: VertexRun<SVector<f64, M>, M>,
    {
        let width = N + 1;
        let mut y = [SVector::<f64, M>::zeros(); METRIC_CELL_VERTICES];
        for l in 0..METRIC_LANES {
            for sigma in 0..C {
                frames.active[sigma][l] = l < count;
            }
        }
        for (l, star) in stars.iter_mut().enumerate().take(count) {
            let k = first + l;
            for sigma in 0..C {
                run.star_values(k, sigma, &mut y[..width]);
                frames.set_cell(sigma, l, &y[..width]);
            }
            frames.first[l] = y[0];
            let lane = run.lane(k);
            *star = MetricStar {
                mu: lane.mu,
                mu_scale: lane.mu_scale,
                start: Euclidean::<M>::extrapolate(&lane.previous, &y[0]),
            };
        }
        frames.seal(count);
    }
}
