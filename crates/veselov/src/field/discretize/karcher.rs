//! The simplicial geodesic interpolation of Casimiro–Rodrigo Def. 5.4 at
//! interior points — the weighted Riemannian (Karcher) mean
//!
//! Υ_{y_β}(λ) = argmin_{y ∈ Y} Σ_v λ_v dist²(y_v, y)    (Def. 5.4)
//!
//! — and the one-node rule Q_mid (5.2) on curved fibres built on it
//! (note 003 §2.5 items 4, 7; erratum 8: the paper gives the rule but no
//! way to evaluate Υ at an interior node).
//!
//! Evaluation: the critical point of the weighted energy is the zero of its
//! gradient −2 Σ_v λ_v Log_y(y_v), found by the fixed-point iteration
//!
//! y ← Exp_y(Σ_v λ_v Log_y(y_v) / Σ_v λ_v)
//!
//! (Karcher 1977; Buss–Fillmore 2001 on spheres), which converges
//! linearly, with a rate of order curvature × (diameter of the data)², for
//! data in a convex geodesic ball (Lemma 5.5). It runs over the AD scalar:
//! the derivative parts obey the same contraction, so once the value has
//! converged to round-off as many further sweeps converge them too.
//!
//! The fibres are those whose chart y·τ(ξ) is the Riemannian exponential
//! and whose logarithm is the Riemannian one ([`RiemannianFibre`]): ℝ^m,
//! SO(3) with the halved Frobenius (bi-invariant) metric, and the product
//! ℝ³ × SO(3) (by Lemma 5.6 the mean splits over the factors). SE(3) with
//! its group exponential is not one (no bi-invariant metric).
//!
//! The rule [`KarcherMidpointRule`]: L = 𝓛(x̄, Υ(λ̄), φ)·vol_β at the
//! barycentre λ̄ = (1/(n+1), …), with the jet φ = (∂Υ/∂λ)(∂Υ^X/∂λ)⁻¹ along
//! the simplex's edges (Def. 5.10: the interpolating section y = Υ∘(Υ^X)⁻¹
//! with Υ^X affine on an affine base), ∂Υ/∂λ by the dual numbers of one more
//! evaluation of the mean with λ = λ̄ + Σ_a t_a(e_a − e_0), in the chart at
//! Υ(λ̄); vol_β = |det T^X|/n!.

use std::marker::PhantomData;

use nalgebra::{Const, SMatrix, SVector, U1};
use num_dual::DualSVec;

use super::error::CellError;
use super::nodes::{NodeMap, factorial};
use super::rules::{cell_nodes, finite, invert_nodes};
use super::smooth::SmoothDensity;
use super::suitability::{CellCheck, GeodesicBall};
use crate::ad::Scalar;
use crate::complex::TopCell;
use crate::field::cell::{DiscreteLagrangian, MAX_CELL_VERTICES};
use crate::field::fibre::{Euclidean, PositionRotation, Rotations};
use crate::{Error, Result};

/// A fibre whose chart y·τ(ξ) is the Riemannian exponential at y and whose
/// [`Fibre::log`](crate::field::fibre::Fibre::log) is the Riemannian logarithm (in the same left-trivialised
/// coordinates), with a convex-ball criterion ([`GeodesicBall`]).
pub trait RiemannianFibre<const M: usize>: GeodesicBall<M> {}

impl<const M: usize> RiemannianFibre<M> for Euclidean<M> {}
/// Geodesics R·exp(tξ̂) of the bi-invariant metric ⟨â, b̂⟩ = ½tr(âᵀb̂) = a·b.
impl RiemannianFibre<3> for Rotations {}
/// The product metric (Euclidean × bi-invariant), chart (r + a, R·exp(b̂)).
impl RiemannianFibre<6> for PositionRotation {}

/// Sweeps allowed before the iteration is declared not to converge.
pub const KARCHER_MAX_SWEEPS: usize = 100;

/// The step size at which the value has converged: a few ulps of the
/// (dimensionless, rotation-angle or coordinate-scaled) step.
const KARCHER_TOLERANCE: f64 = 4.0 * f64::EPSILON;

/// Υ: the weighted Karcher mean of `points` with `weights` (Def. 5.4) over
/// any scalar, starting from the point of largest weight; `Err` with the
/// reason when the weights are not finite, non-negative with a positive
/// sum, a logarithm fails, or the iteration does not converge within
/// [`KARCHER_MAX_SWEEPS`] sweeps (the data are not checked to lie in a
/// convex ball here: see [`karcher_mean`]).
pub(crate) fn weighted_mean<F: RiemannianFibre<M>, D: Scalar, const M: usize>(
    points: &[F::Point<D>],
    weights: &[D],
) -> std::result::Result<F::Point<D>, String> {
    if points.is_empty() || points.len() != weights.len() {
        return Err(format!("{} points and {} weights", points.len(), weights.len()));
    }
    let total = weights.iter().fold(D::zero(), |a, &w| a + w);
    if !weights.iter().all(|w| w.re().is_finite() && w.re() >= 0.0) || total.re() <= 0.0 {
        return Err("the weights must be finite and non-negative with a positive sum".into());
    }
    let start = (0..weights.len())
        .max_by(|&a, &b| weights[a].re().total_cmp(&weights[b].re()))
        .unwrap_or(0);
    let mut y = points[start];
    let (mut converged_at, mut last, mut spread) = (None, f64::INFINITY, 0.0_f64);
    for sweep in 0..KARCHER_MAX_SWEEPS {
        let mut step = SVector::<D, M>::from_element(D::zero());
        for (p, &w) in points.iter().zip(weights) {
            let t = F::log(&y, p).map_err(|e| format!("no logarithm from the current mean: {e}"))?;
            step += t * (w / total);
        }
        let previous = last;
        last = step.iter().fold(0.0_f64, |m, s| m.max(s.re().abs()));
        if !last.is_finite() {
            return Err("non-finite step".into());
        }
        if sweep == 0 {
            spread = last;
        }
        y = F::retract(&y, &step);
        // Converged: a step of a few ulps of the data's spread, or a step
        // that no longer halves once below 1e-10 of it (the round-off
        // floor of coordinates larger than the spread, on ℝ^m).
        let small = last <= KARCHER_TOLERANCE * (1.0 + spread);
        let stalled = last <= 1e-10 * (1.0 + spread) && last >= 0.5 * previous;
        match converged_at {
            // The derivative parts contract at the value's rate: as many
            // sweeps again as the value needed converge them as well.
            Some(k) if sweep > 2 * k => return Ok(y),
            None if small || stalled => converged_at = Some(sweep),
            _ => {}
        }
    }
    Err(format!(
        "the fixed-point iteration did not converge in {KARCHER_MAX_SWEEPS} sweeps (last step {last:e})"
    ))
}

/// The weighted Karcher mean argmin_y Σ_v w_v dist²(y_v, y) of `points`
/// (Casimiro–Rodrigo Def. 5.4, Υ at barycentric coordinates λ = w/Σw), by
/// the fixed-point iteration of the module documentation, converged to
/// round-off.
///
/// # Errors
/// [`Error::InvalidParameter`] naming `points` when they do not lie in a
/// geodesic ball where the mean is unique and the iteration converges
/// (Lemma 5.5; for SO(3): some point within π/2 of all the others,
/// [`GeodesicBall::check_simplex`]) or the iteration does not converge,
/// and naming `weights` when they are not finite and non-negative with a
/// positive sum or their number differs from the points'.
pub fn karcher_mean<F: RiemannianFibre<M>, const M: usize>(
    points: &[F::Point<f64>],
    weights: &[f64],
) -> Result<F::Point<f64>> {
    let bad = |name: &str, reason: String| Error::InvalidParameter {
        name: name.into(),
        value: format!("{} values", points.len()),
        reason,
    };
    if points.is_empty() || points.len() != weights.len() {
        return Err(bad(
            "weights",
            format!(
                "one weight per point needed ({} points, {} weights)",
                points.len(),
                weights.len()
            ),
        ));
    }
    if !weights.iter().all(|w| w.is_finite() && *w >= 0.0) || weights.iter().sum::<f64>() <= 0.0 {
        return Err(bad(
            "weights",
            "the weights must be finite and non-negative with a positive sum".into(),
        ));
    }
    if !points.iter().all(F::is_finite) {
        return Err(bad("points", "a point is not finite".into()));
    }
    F::check_simplex(points).map_err(|r| bad("points", format!("not in a convex geodesic ball: {r}")))?;
    weighted_mean::<F, f64, M>(points, weights).map_err(|r| bad("points", r))
}

/// Q_mid (5.2) through the Karcher mean: L = 𝓛(x̄, Υ(λ̄), φ)·vol_β at the
/// barycentre of an N-simplex (module documentation), for any
/// [`RiemannianFibre`]. On ℝ^m it is [`MidpointRule`](super::MidpointRule)
/// (the mean is the arithmetic one and φ the affine interpolant's gradient).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KarcherMidpointRule<F, L, X, const M: usize, const N: usize> {
    /// The smooth density.
    pub density: L,
    /// The node map (simplices).
    pub nodes: X,
    fibre: PhantomData<fn() -> F>,
}

impl<F, L, X, const M: usize, const N: usize> KarcherMidpointRule<F, L, X, M, N> {
    /// Q_mid of `density` on the simplices of `nodes`.
    pub fn new(density: L, nodes: X) -> Self {
        Self {
            density,
            nodes,
            fibre: PhantomData,
        }
    }
}

impl<F, L, X, const M: usize, const N: usize> KarcherMidpointRule<F, L, X, M, N>
where
    F: RiemannianFibre<M>,
    L: SmoothDensity<F, M, N>,
    X: NodeMap<N>,
{
    /// The discrete Lagrangian with its failure named.
    ///
    /// # Errors
    /// [`CellError::Nodes`] for a cell the node map does not know or the
    /// wrong number of values, [`CellError::SingularNodes`],
    /// [`CellError::Unsuitable`] when the mean cannot be evaluated.
    pub fn try_cell_lagrangian<D: Scalar>(
        &self,
        cell: &TopCell,
        y: &[F::Point<D>],
    ) -> std::result::Result<D, CellError> {
        let mut x = [SVector::<f64, N>::zeros(); MAX_CELL_VERTICES];
        let k = cell_nodes(&self.nodes, cell, &mut x);
        if k != N + 1 || y.len() != N + 1 {
            return Err(CellError::Nodes {
                cell: cell.index,
                expected: N + 1,
                got: if k == N + 1 { y.len() } else { k },
            });
        }
        let tx = SMatrix::<f64, N, N>::from_fn(|r, c| x[c + 1][r] - x[0][r]);
        let (inv, jac) = invert_nodes(cell.index, &tx)?;
        let unsuitable = |reason: String| CellError::Unsuitable {
            cell: cell.index,
            reason: format!("Karcher mean: {reason}"),
        };
        // λ = λ̄ + Σ_a t_a (e_a − e_0), the t_a seeded as N dual directions.
        type T<D, const N: usize> = DualSVec<D, N>;
        let third = 1.0 / (N + 1) as f64;
        let weights: [T<D, N>; MAX_CELL_VERTICES] = std::array::from_fn(|v| {
            let mut w = T::<D, N>::from_re(D::from(third));
            if v == 0 {
                for a in 0..N {
                    w -= T::<D, N>::from_re(D::zero()).derivative(a);
                }
            } else if v <= N {
                w += T::<D, N>::from_re(D::zero()).derivative(v - 1);
            }
            w
        });
        let lifted: [F::Point<T<D, N>>; MAX_CELL_VERTICES] =
            std::array::from_fn(|v| F::map(&y[v.min(N)], T::<D, N>::from_re));
        let mean = weighted_mean::<F, T<D, N>, M>(&lifted[..=N], &weights[..=N]).map_err(&unsuitable)?;
        let centre = F::map(&mean, |d| d.re);
        // ∂Υ/∂t_a in the chart at Υ(λ̄): the dual parts of log(Υ(λ̄), Υ(λ)).
        let chart = F::log(&F::map(&centre, T::<D, N>::from_re), &mean)
            .map_err(|e| unsuitable(format!("no logarithm at the mean: {e}")))?;
        let dy = SMatrix::<D, M, N>::from_fn(|i, a| chart[i].eps.unwrap_generic(Const::<N>, U1)[a]);
        let jet = SMatrix::<D, M, N>::from_fn(|i, b| (0..N).fold(D::zero(), |s, a| s + dy[(i, a)] * inv[(a, b)]));
        let xbar = x[..=N].iter().fold(SVector::<f64, N>::zeros(), |s, p| s + p) * third;
        Ok(self.density.density(&xbar, &centre, &jet) * (jac / factorial(N) as f64))
    }
}

impl<F, L, X, const M: usize, const N: usize> DiscreteLagrangian<F, M> for KarcherMidpointRule<F, L, X, M, N>
where
    F: RiemannianFibre<M>,
    L: SmoothDensity<F, M, N>,
    X: NodeMap<N>,
{
    /// NaN on an unsuitable cell; see [`CellCheck::check_cell`].
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[F::Point<D>]) -> D {
        self.try_cell_lagrangian(cell, y).unwrap_or(D::from(f64::NAN))
    }
}

impl<F, L, X, const M: usize, const N: usize> CellCheck<F, M> for KarcherMidpointRule<F, L, X, M, N>
where
    F: RiemannianFibre<M>,
    L: SmoothDensity<F, M, N>,
    X: NodeMap<N>,
{
    /// The vertex values in a convex geodesic ball (Lemma 5.5), the mean
    /// converged, the Lagrangian finite.
    fn check_cell(&self, cell: &TopCell, y: &[F::Point<f64>]) -> std::result::Result<(), CellError> {
        if !y.iter().all(F::is_finite) {
            return Err(CellError::NonFinite {
                cell: cell.index,
                what: "vertex value",
            });
        }
        F::check_simplex(y).map_err(|reason| CellError::Unsuitable {
            cell: cell.index,
            reason,
        })?;
        finite(cell.index, self.try_cell_lagrangian(cell, y)?)
    }
}
