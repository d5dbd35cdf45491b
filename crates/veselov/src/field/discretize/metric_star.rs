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
use super::affine_frame::completed_mean;
use super::metric_lanes::*;
use super::nodes::NodeMap;
use super::smooth::SmoothDensity;
use crate::complex::TopCell;
use crate::field::cell::{SolvedVertex, VertexLane};
use crate::field::fibre::{Euclidean, Fibre};
use crate::field::legendre::{CauchyOptions, LegendreNewton};

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
