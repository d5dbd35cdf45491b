//! Exact derivatives of the midpoint rule Q_mid (5.6) through the chain rule
//! of its affine interpolant, with dual numbers on the density alone.
//!
//! On a simplex with nodes x₀ … x_N and values y₀ … y_N (Euclidean fibre
//! ℝ^M) the rule evaluates L_β = vol_β·𝓛(x̄, ȳ, φ) at
//!
//! * ȳ = (1/(N + 1)) Σ_l y_l, and
//! * φ_{ka} = Σ_c (y_{c+1} − y₀)_k (T^X)⁻¹_{ca}, i.e. φ_{ka} = Σ_l (y_l)_k c_{la}
//!   with c_{la} = (T^X)⁻¹_{l−1,a} for l ≥ 1 and c_{0a} = −Σ_c (T^X)⁻¹_{ca}.
//!
//! Both are linear in the vertex values, so moving y_l along e_k moves
//! (ȳ, φ) along the fixed direction D_{lk} = (e_k/(N + 1), e_k c_lᵀ), and
//!
//! ∂L_β/∂(y_l)_k = vol_β·d𝓛[D_{lk}],
//! ∂²L_β/∂(y_a)_i∂(y_b)_j = vol_β·d²𝓛[D_{ai}, D_{bj}].
//!
//! The jet is formed once in `f64` and only the density is evaluated over
//! dual numbers seeded with these directions, instead of lifting every
//! vertex value and forming the jet in dual arithmetic (the reference path,
//! [`vertex_gradient`](crate::field::cell::vertex_gradient) and
//! [`mixed_block_dual`](crate::field::cell::mixed_block_dual), which the
//! tests hold these against). The value parts are the bits of
//! [`MidpointRule::try_cell_lagrangian`]'s evaluation, and every direction's
//! derivative is computed by the same operations whatever else is seeded,
//! so one vertex's gradient equals its entry in the all-vertex pass bit for
//! bit.
//!
//! A density with a diagonal quadratic jet part needs no dual directions
//! for the jet at all (`metric_terms`).

use nalgebra::{Const, SMatrix, SVector, U1};
use num_dual::{Derivative, Dual2_64, Dual2SVec64, Dual64, DualSVec64, HyperDual64, HyperDualSVec64};

use super::affine::MidpointRule;
use super::affine_frame::{AffineFrame, MAX_STAR, PartialFrame};
use super::metric_lanes::LaneOutput;
use super::metric_terms::{metric_coefficients, metric_gradient, metric_product};
use super::nodes::{NodeMap, factorial};
use super::rules::{cell_nodes, invert_nodes};
use super::smooth::SmoothDensity;
use crate::ad::Scalar;
use crate::complex::TopCell;
use crate::field::cell::{MAX_CELL_VERTICES, SolvedVertex, VertexLane, VertexStar};
use crate::field::fibre::{Euclidean, Fibre};
use crate::field::legendre::{CauchyOptions, solve_legendre};

impl<L, X, const N: usize> MidpointRule<L, X, N>
where
    X: NodeMap<N>,
{
    /// The cell's interpolant, from the cached shape geometry where the
    /// density does not read the position, else from the cell's nodes (the
    /// expressions of [`MidpointRule::try_cell_lagrangian`]); `None` where
    /// that evaluation fails (the callers then take the reference path,
    /// which reports the cell as unsuitable).
    fn affine_frame<const M: usize>(&self, cell: &TopCell, y: &[SVector<f64, M>]) -> Option<AffineFrame<M, N>>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        if y.len() != N + 1 {
            return None;
        }
        Some(self.partial_frame(cell, y)?.complete(&y[N]))
    }

    /// The interpolant's sums over the values `y[..N]` of all but the last
    /// vertex.
    #[inline]
    pub(super) fn partial_frame<const M: usize>(
        &self,
        cell: &TopCell,
        y: &[SVector<f64, M>],
    ) -> Option<PartialFrame<M, N>>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        if N == 0 || y.len() < N {
            return None;
        }
        let (inverse, volume, centre) = self.cell_geometry(cell)?;
        Some(PartialFrame::new(inverse, volume, centre, y))
    }

    /// (T^X)⁻¹, vol_β and x̄ of a cell: its shape's cached geometry (x̄ = 0,
    /// not read) unless the density depends on position, else from its
    /// nodes.
    #[inline]
    pub(super) fn cell_geometry<const M: usize>(
        &self,
        cell: &TopCell,
    ) -> Option<(SMatrix<f64, N, N>, f64, SVector<f64, N>)>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        match self.cached_geometry(cell) {
            Some((inv, volume)) if !self.density.depends_on_position() => Some((inv, volume, SVector::zeros())),
            _ => self.node_geometry(cell),
        }
    }

    /// (T^X)⁻¹, vol_β and x̄ of a cell from its nodes (kept out of line: the
    /// cached shapes' path, inlined into the vertex solve, stays small).
    #[inline(never)]
    pub(super) fn node_geometry(&self, cell: &TopCell) -> Option<(SMatrix<f64, N, N>, f64, SVector<f64, N>)> {
        let mut x = [SVector::<f64, N>::zeros(); MAX_CELL_VERTICES];
        if cell_nodes(&self.nodes, cell, &mut x) != N + 1 {
            return None;
        }
        let tx = SMatrix::<f64, N, N>::from_fn(|r, c| x[c + 1][r] - x[0][r]);
        let (inv, jac) = invert_nodes(cell.index, &tx).ok()?;
        let w = 1.0 / (N + 1) as f64;
        let centre = x[..=N].iter().fold(SVector::<f64, N>::zeros(), |a, b| a + b) * w;
        Some((inv, jac / factorial(N) as f64, centre))
    }

    /// vol_β·𝓛 at the frame's (ȳ, φ) as dual numbers: `value(k, ȳ_k)` and
    /// `jet(k, a, φ_{ka})` build the seeded entries from their real parts.
    #[inline]
    fn seeded<D: Scalar, const M: usize>(
        &self,
        frame: &AffineFrame<M, N>,
        value: impl Fn(usize, f64) -> D,
        jet: impl Fn(usize, usize, f64) -> D,
    ) -> D
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        let y = SVector::<D, M>::from_fn(|k, _| value(k, frame.value[k]));
        let phi = SMatrix::<D, M, N>::from_fn(|k, a| jet(k, a, frame.jet[(k, a)]));
        self.density.density(&frame.centre, &y, &phi) * frame.volume
    }

    /// ∂L_β/∂y_l for the `count` vertices l = first … first + count − 1 by
    /// one pass over the density with their M·count directions D_{lk}
    /// (direction (l − first)M + k, padded to `W`), into `out[..count]`.
    /// Every direction is seeded alike whatever else is seeded, so a
    /// vertex's gradient has the same bits in any pass that holds it.
    fn vertex_pass<const W: usize, const M: usize>(
        &self,
        frame: &AffineFrame<M, N>,
        first: usize,
        count: usize,
        out: &mut [SVector<f64, M>],
    ) -> bool
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        if first + count > N + 1 || out.len() < count {
            return false;
        }
        if let Some(eta) = self.density.diagonal_jet_metric() {
            let dv = self.jet_free_gradient(&frame.centre, &frame.value);
            for (i, g) in out.iter_mut().enumerate().take(count) {
                *g = metric_gradient(frame, &eta, &dv, first + i);
            }
            return true;
        }
        let directions = M * count;
        if directions > W {
            return false;
        }
        let w = AffineFrame::<M, N>::mean_weight();
        let seeded = |k: usize, re: f64, coefficient: &dyn Fn(usize) -> f64| {
            let eps = SVector::<f64, W>::from_fn(|d, _| {
                if d < directions && d % M == k {
                    coefficient(first + d / M)
                } else {
                    0.0
                }
            });
            DualSVec64::new(re, Derivative::some(eps))
        };
        let r = self.seeded::<DualSVec64<W>, M>(
            frame,
            |k, re| seeded(k, re, &|_| w),
            |k, a, re| seeded(k, re, &|l| frame.coefficient(l, a)),
        );
        let eps = r.eps.unwrap_generic(Const::<W>, U1);
        for (l, g) in out.iter_mut().enumerate().take(count) {
            *g = SVector::from_fn(|k, _| eps[l * M + k]);
        }
        true
    }

    /// ∇_yV at (x̄, ȳ), V(x, y) = 𝓛(x, y, 0)
    /// ([`SmoothDensity::jet_free_part`]), by one pass with M directions
    /// (a plain dual number for a scalar field).
    #[inline]
    pub(super) fn jet_free_gradient<const M: usize>(
        &self,
        centre: &SVector<f64, N>,
        value: &SVector<f64, M>,
    ) -> SVector<f64, M>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        if M == 1 {
            let y = SVector::<Dual64, M>::from_fn(|k, _| Dual64::new(value[k], 1.0));
            return SVector::from_element(self.density.jet_free_part(centre, &y).eps);
        }
        let y = SVector::<DualSVec64<M>, M>::from_fn(|k, _| {
            DualSVec64::new(
                value[k],
                Derivative::some(SVector::from_fn(|d, _| if d == k { 1.0 } else { 0.0 })),
            )
        });
        self.density
            .jet_free_part(centre, &y)
            .eps
            .unwrap_generic(Const::<M>, U1)
    }

    /// ∇_yV and ∇²_yV at (x̄, ȳ) by one second-order pass.
    #[inline]
    pub(super) fn jet_free_hessian<const M: usize>(
        &self,
        centre: &SVector<f64, N>,
        value: &SVector<f64, M>,
    ) -> (SVector<f64, M>, SMatrix<f64, M, M>)
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        if M == 1 {
            let y = SVector::<Dual2_64, M>::from_fn(|k, _| Dual2_64::new(value[k], 1.0, 0.0));
            let v = self.density.jet_free_part(centre, &y);
            return (SVector::from_element(v.v1), SMatrix::from_element(v.v2));
        }
        let y = SVector::<Dual2SVec64<M>, M>::from_fn(|k, _| Dual2SVec64::from_re(value[k]).derivative(k));
        let v = self.density.jet_free_part(centre, &y);
        (
            v.v1.unwrap_generic(U1, Const::<M>).transpose(),
            v.v2.unwrap_generic(Const::<M>, Const::<M>),
        )
    }

    /// ∇_yV (and ∇²_yV if `hessians` is given) at the points (x̄_i, ȳ_i):
    /// the density's batched derivatives
    /// ([`SmoothDensity::jet_free_derivatives`]) where it has them, else
    /// [`jet_free_gradient`](Self::jet_free_gradient) or
    /// [`jet_free_hessian`](Self::jet_free_hessian) point by point; the
    /// same bits either way.
    pub(super) fn jet_free_batch<const M: usize>(
        &self,
        centres: &[SVector<f64, N>],
        values: &[SVector<f64, M>],
        gradients: &mut [SVector<f64, M>],
        mut hessians: Option<&mut [SMatrix<f64, M, M>]>,
    ) where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        if self
            .density
            .jet_free_derivatives(centres, values, gradients, hessians.as_deref_mut())
        {
            return;
        }
        for (i, (centre, value)) in centres.iter().zip(values).enumerate() {
            match hessians.as_deref_mut() {
                Some(h) => (gradients[i], h[i]) = self.jet_free_hessian(centre, value),
                None => gradients[i] = self.jet_free_gradient(centre, value),
            }
        }
    }

    /// ∂L_β/∂y_l by one pass with the M directions D_{lk}.
    pub(super) fn chain_gradient<const M: usize>(
        &self,
        cell: &TopCell,
        y: &[SVector<f64, M>],
        l: usize,
    ) -> Option<SVector<f64, M>>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        let frame = self.affine_frame(cell, y)?;
        let mut g = [SVector::zeros()];
        self.vertex_pass::<M, M>(&frame, l, 1, &mut g).then_some(g[0])
    }

    /// Every vertex gradient in one pass (directions padded to 4, 8 or 16;
    /// `false` for more).
    pub(super) fn chain_gradients<const M: usize>(
        &self,
        cell: &TopCell,
        y: &[SVector<f64, M>],
        out: &mut [SVector<f64, M>],
    ) -> bool
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        self.affine_frame(cell, y)
            .is_some_and(|frame| self.frame_gradients(&frame, out))
    }

    /// [`chain_gradients`](Self::chain_gradients) at a formed frame.
    fn frame_gradients<const M: usize>(&self, frame: &AffineFrame<M, N>, out: &mut [SVector<f64, M>]) -> bool
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        match M * (N + 1) {
            // The closed form of a diagonal jet metric takes no directions.
            _ if self.density.diagonal_jet_metric().is_some() => self.vertex_pass::<0, M>(frame, 0, N + 1, out),
            0..=4 => self.vertex_pass::<4, M>(frame, 0, N + 1, out),
            5..=8 => self.vertex_pass::<8, M>(frame, 0, N + 1, out),
            9..=16 => self.vertex_pass::<16, M>(frame, 0, N + 1, out),
            _ => false,
        }
    }

    /// ∂L_β/∂y_a and its derivative in y_b (the block of
    /// [`mixed_block`](crate::field::cell::mixed_block)) by one hyper-dual
    /// pass: directions D_{ai} in ε₁, D_{bj} in ε₂, the block in ε₁ε₂ (the
    /// plain hyper-dual number for M = 1).
    pub(super) fn chain_block<const M: usize>(
        &self,
        cell: &TopCell,
        y: &[SVector<f64, M>],
        a: usize,
        b: usize,
    ) -> Option<(SVector<f64, M>, SMatrix<f64, M, M>)>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        if a > N || b > N {
            return None;
        }
        Some(self.frame_block(&self.affine_frame(cell, y)?, a, b))
    }

    /// [`chain_block`](Self::chain_block) at a formed frame.
    fn frame_block<const M: usize>(
        &self,
        frame: &AffineFrame<M, N>,
        a: usize,
        b: usize,
    ) -> (SVector<f64, M>, SMatrix<f64, M, M>)
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        let w = AffineFrame::<M, N>::mean_weight();
        if let Some(eta) = self.density.diagonal_jet_metric() {
            let (dv, hessian) = self.jet_free_hessian(&frame.centre, &frame.value);
            let metric = metric_product(&frame.inverse, &metric_coefficients(&frame.inverse, &eta, a), b);
            let block = SMatrix::<f64, M, M>::from_fn(|i, j| {
                let diagonal = if i == j { metric } else { 0.0 };
                (diagonal + hessian[(i, j)] * (w * w)) * frame.volume
            });
            return (metric_gradient(frame, &eta, &dv, a), block);
        }
        if M == 1 {
            // One direction each: the plain hyper-dual number.
            let r = self.seeded::<HyperDual64, M>(
                frame,
                |_, re| HyperDual64::new(re, w, w, 0.0),
                |_, c, re| HyperDual64::new(re, frame.coefficient(a, c), frame.coefficient(b, c), 0.0),
            );
            return (SVector::from_element(r.eps1), SMatrix::from_element(r.eps1eps2));
        }
        type Hyper<const M: usize> = HyperDualSVec64<M, M>;
        // ε₁ carries the directions D_{ak}, ε₂ the directions D_{bk}.
        let seed = |k: usize, re: f64, inner: f64, outer: f64| {
            let inner_eps = SVector::<f64, M>::from_fn(|d, _| if d == k { inner } else { 0.0 });
            let outer_eps = SMatrix::<f64, 1, M>::from_fn(|_, d| if d == k { outer } else { 0.0 });
            Hyper::<M>::new(
                re,
                Derivative::some(inner_eps),
                Derivative::some(outer_eps),
                Derivative::none(),
            )
        };
        let r = self.seeded::<Hyper<M>, M>(
            frame,
            |k, re| seed(k, re, w, w),
            |k, c, re| seed(k, re, frame.coefficient(a, c), frame.coefficient(b, c)),
        );
        let grad = r.eps1.unwrap_generic(Const::<M>, U1);
        let block = r.eps1eps2.unwrap_generic(Const::<M>, Const::<M>);
        (grad, block)
    }

    /// The rule's own solve of a vertex equation of the Cauchy integrator
    /// ([`crate::field::cell::DiscreteLagrangian::solve_last_vertex`]): the generic Newton
    /// ([`solve_legendre`]) on the same equations, with each star cell's
    /// interpolant summed once over its known vertices and completed with
    /// the iterate z at every evaluation, and every residual-only evaluation
    /// taking all the cell's vertex gradients in one pass: those of the
    /// accepted z are the solved cells' gradients the marcher stores, so it
    /// need not evaluate the cells again. The residual, Jacobian and stored
    /// gradients are the bits of the marcher's own evaluation (the frames
    /// complete to the same sums, and one vertex's gradient is its entry in
    /// the all-vertex pass). `None` (the marcher's generic path) for stars of
    /// more than [`MAX_STAR`] cells, more than 16 directions, a failed
    /// frame, or a vertex none of whose cells is in the action.
    pub(super) fn solve_star<const M: usize>(
        &self,
        star: &VertexStar<'_, SVector<f64, M>>,
        mu: &SVector<f64, M>,
        mu_scale: f64,
        previous: &SVector<f64, M>,
        options: &CauchyOptions,
        gradients: &mut [SVector<f64, M>],
    ) -> Option<SolvedVertex<SVector<f64, M>>>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        let cells = factorial(N);
        let width = N + 1;
        let metric = self.density.diagonal_jet_metric();
        if N == 0
            || width > MAX_CELL_VERTICES
            || cells > MAX_STAR
            || (M * width > 16 && metric.is_none())
            || gradients.len() != cells * width
        {
            return None;
        }
        if metric.is_some() {
            let lanes = [VertexLane {
                mu: *mu,
                mu_scale,
                previous: *previous,
            }];
            let mut solved = [SolvedVertex {
                value: *previous,
                outcome: Default::default(),
                gradients_written: false,
                forces_written: false,
            }];
            let out = LaneOutput {
                stride: gradients.len(),
                gradients,
                solved: &mut solved,
            };
            let star = |_: usize, sigma: usize, out: &mut [SVector<f64, M>]| star(sigma, out);
            return self
                .solve_metric_lanes(&star, &lanes, options, out)
                .then_some(solved[0]);
        }
        let mut frames: [Option<PartialFrame<M, N>>; MAX_STAR] = [None; MAX_STAR];
        let mut y = [SVector::<f64, M>::zeros(); MAX_CELL_VERTICES];
        let mut base = None;
        for (sigma, slot) in frames.iter_mut().enumerate().take(cells) {
            if let Some(cell) = star(sigma, &mut y[..width]) {
                base.get_or_insert(y[0]);
                *slot = Some(self.partial_frame(&cell, &y[..width])?);
            }
        }
        let start = Euclidean::<M>::extrapolate(previous, &base?);
        // The point whose cell gradients `gradients` holds.
        let mut written: Option<SVector<f64, M>> = None;
        let (z, outcome) = solve_legendre::<Euclidean<M>, M>(mu, mu_scale, start, options, |z, mut jacobian| {
            let mut leg = SVector::<f64, M>::zeros();
            let mut scale = 0.0;
            if let Some(j) = jacobian.as_deref_mut() {
                j.fill(0.0);
            }
            for (sigma, partial) in frames.iter().enumerate().take(cells) {
                let Some(partial) = partial else { continue };
                let frame = partial.complete(z);
                let g = match jacobian.as_deref_mut() {
                    Some(j) => {
                        let (g, block) = self.frame_block(&frame, 0, N);
                        *j += block;
                        g
                    }
                    None => {
                        let out = &mut gradients[sigma * width..(sigma + 1) * width];
                        self.frame_gradients(&frame, out);
                        out[0]
                    }
                };
                leg += g;
                scale += g.amax();
            }
            if jacobian.is_none() {
                written = Some(*z);
            }
            (leg, scale)
        });
        if outcome.failure.is_some() {
            return Some(SolvedVertex {
                value: z,
                outcome,
                gradients_written: false,
                forces_written: false,
            });
        }
        for (sigma, partial) in frames.iter().enumerate().take(cells) {
            let out = &mut gradients[sigma * width..(sigma + 1) * width];
            match partial {
                Some(partial) if written != Some(z) => {
                    self.frame_gradients(&partial.complete(&z), out);
                }
                Some(_) => {}
                None => out.fill(SVector::zeros()),
            }
            out[0] = SVector::zeros();
        }
        Some(SolvedVertex {
            value: z,
            outcome,
            gradients_written: true,
            forces_written: false,
        })
    }
}
