//! The derivatives of the midpoint rule Q_mid (5.6) for a density with a
//! diagonal quadratic jet part
//! ([`SmoothDensity::diagonal_jet_metric`](super::smooth::SmoothDensity::diagonal_jet_metric):
//! 𝓛 = ½ Σ_{k,a} η_a φ_{ka}² + V(x, y) with V(x, y) = 𝓛(x, y, 0), as the
//! nonlinear waves of seed 002 (4.32)), with no dual directions for the jet
//! (the notation of [`super::affine_chain`]):
//!
//! ∂L_β/∂(y_l)_k = vol_β·(Σ_a η_a φ_{ka} c_{la} + ∂_kV(x̄, ȳ)/(N + 1))
//!              = Σ_{j=1…N} K_{lj} (y_j − y₀)_k + (vol_β/(N + 1)) ∂_kV(x̄, ȳ),
//! ∂²L_β/∂(y_a)_i∂(y_b)_j = vol_β·(δ_{ij} Σ_c η_c c_{ac} c_{bc} + ∂_i∂_jV(x̄, ȳ)/(N + 1)²),
//!
//! with the cell's table K_{lj} = vol_β Σ_a η_a c_{la} c_{ja} (φ_{ka} =
//! Σ_j (y_j − y₀)_k c_{ja}, as Σ_l c_{la} = 0), formed once per cell
//! geometry (`metric_table_row`): the gradient at a vertex is then N
//! products with the rises y_j − y₀, not the jet and its contraction. Only V
//! is evaluated over dual numbers (M directions, or second order for the
//! block): one evaluation of the potential per cell and evaluation.

use nalgebra::{SMatrix, SVector};

use super::affine_frame::{AffineFrame, vertex_coefficient};

/// η_a c_{la} for a = 0 … N − 1: the weights of vertex l's jet term.
#[inline]
pub(super) fn metric_coefficients<const N: usize>(
    inverse: &SMatrix<f64, N, N>,
    eta: &SVector<f64, N>,
    l: usize,
) -> SVector<f64, N> {
    SVector::from_fn(|a, _| eta[a] * vertex_coefficient(inverse, l, a))
}

/// Σ_c η_c c_{ac} c_{bc}: the jet term of ∂²L_β/∂y_a∂y_b over vol_β (a
/// multiple of the identity), formed from the weights η_c c_{ac}
/// ([`metric_coefficients`] of vertex a).
#[inline]
pub(super) fn metric_product<const N: usize>(
    inverse: &SMatrix<f64, N, N>,
    weights_a: &SVector<f64, N>,
    b: usize,
) -> f64 {
    (0..N).fold(0.0, |acc, c| acc + weights_a[c] * vertex_coefficient(inverse, b, c))
}

/// Row l of the cell's metric table: K_{lj} = vol_β Σ_a η_a c_{la} c_{ja}
/// for j = 1 … N at index j − 1, the weights of the rises y_j − y₀ in
/// ∂L_β/∂y_l ([`metric_gradient_from`]). K_{0N} = vol_β Σ_a η_a c_{0a} c_{Na}
/// is also the jet term of ∂²L_β/∂y₀∂y_N, as the metric solve's Jacobian
/// takes it.
#[inline]
pub(super) fn metric_table_row<const N: usize>(
    inverse: &SMatrix<f64, N, N>,
    eta: &SVector<f64, N>,
    volume: f64,
    l: usize,
) -> SVector<f64, N> {
    let weights = metric_coefficients(inverse, eta, l);
    SVector::from_fn(|j, _| metric_product(inverse, &weights, j + 1) * volume)
}

/// vol_β/(N + 1): the weight of ∇_yV in every vertex's gradient.
#[inline]
pub(super) fn potential_weight<const N: usize>(volume: f64) -> f64 {
    volume * AffineFrame::<1, N>::mean_weight()
}

/// ∂L_β/∂y_l = Σ_{j=1…N} K_{lj} (y_j − y₀) + (vol_β/(N + 1)) ∇_yV for a
/// density of diagonal jet metric η, from row l of the cell's table
/// ([`metric_table_row`]), the rises `rise(c, k)` = (y_{c+1} − y₀)_k, ∇_yV
/// at the frame and the potential's weight ([`potential_weight`]): the
/// known rises' part ([`metric_known_part`]) completed by the last rise
/// ([`metric_completed`]), the operations the metric solve's residual
/// performs with its known parts formed once, so every vertex's gradient
/// has the same bits whichever pass asks for it.
#[inline]
pub(super) fn metric_gradient_from<const M: usize, const N: usize>(
    row: &SVector<f64, N>,
    rise: impl Fn(usize, usize) -> f64,
    dv: &SVector<f64, M>,
    potential: f64,
) -> SVector<f64, M> {
    SVector::from_fn(|k, _| {
        let known = metric_known_part(row, |c| rise(c, k));
        metric_completed(known, row[N - 1], rise(N - 1, k), dv[k] * potential)
    })
}

/// Σ_{c < N−1} row_c·rise(c): the known rises' part of one component of
/// [`metric_gradient_from`].
#[inline]
pub(super) fn metric_known_part<const N: usize>(row: &SVector<f64, N>, rise: impl Fn(usize) -> f64) -> f64 {
    (0..N - 1).fold(0.0, |acc, c| acc + row[c] * rise(c))
}

/// A component of a cell's gradient from its known rises' part, the last
/// rise (z − y₀)_k with its weight K_{l,N}, and the potential's term
/// (vol_β/(N + 1))∂_kV: the one completion of [`metric_gradient_from`] and
/// the metric solve's residual.
#[inline(always)]
pub(super) fn metric_completed(known: f64, last_weight: f64, last_rise: f64, potential_term: f64) -> f64 {
    (known + last_weight * last_rise) + potential_term
}

/// [`metric_gradient_from`] at a formed frame.
#[inline]
pub(super) fn metric_gradient<const M: usize, const N: usize>(
    frame: &AffineFrame<M, N>,
    eta: &SVector<f64, N>,
    dv: &SVector<f64, M>,
    l: usize,
) -> SVector<f64, M> {
    let row = metric_table_row(&frame.inverse, eta, frame.volume, l);
    let potential = potential_weight::<N>(frame.volume);
    metric_gradient_from::<M, N>(&row, |c, k| frame.rises[(k, c)], dv, potential)
}
