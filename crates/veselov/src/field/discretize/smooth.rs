//! Smooth Lagrangian densities 𝓛: J¹Y → ℝ over a fibre (note 003 §2.5):
//! 𝓛(x, y, φ) with x ∈ X = ℝ^N, y a fibre point and φ ∈ ℝ^{M×N} the jet in
//! the fibre's chart at y (column a = ∂/∂x^a; for SO(3) the left-trivialised
//! body vector, e.g. Ω = (Rᵀ∂_sR)^∨ for the rod).

use nalgebra::{SMatrix, SVector};

use crate::ad::Scalar;
use crate::field::fibre::{Euclidean, Fibre};
use nalgebra::{Const, U1};
use num_dual::{Derivative, Dual64, DualSVec64};

/// A smooth first-order Lagrangian density 𝓛(x, y, φ) with respect to the
/// coordinate volume dx¹ ∧ … ∧ dx^N, written once over the AD scalar.
pub trait SmoothDensity<F: Fibre<M>, const M: usize, const N: usize>: Send + Sync {
    /// 𝓛(x, y, φ).
    fn density<D: Scalar>(&self, x: &SVector<f64, N>, y: &F::Point<D>, jet: &SMatrix<D, M, N>) -> D;

    /// Whether 𝓛 depends on the base point x (default true); rules skip
    /// computing x where it does not.
    fn depends_on_position(&self) -> bool {
        true
    }

    /// η ∈ ℝ^N if 𝓛 has a constant diagonal quadratic jet part:
    /// 𝓛(x, y, φ) = ½ Σ_{k,a} η_a φ_{ka}² + 𝓛(x, y, 0) for every x, y, φ
    /// (e.g. the nonlinear wave (4.32): η = (−1, …, −1, +1)). Rules then
    /// take the jet's derivatives in closed form and differentiate only
    /// 𝓛(x, y, 0). `None` (the default): no such form is claimed.
    fn diagonal_jet_metric(&self) -> Option<SVector<f64, N>> {
        None
    }

    /// 𝓛(x, y, 0), the part the closed form of a diagonal jet metric
    /// differentiates; the default evaluates the density at a zero jet,
    /// densities override it to skip the jet's terms.
    fn jet_free_part<D: Scalar>(&self, x: &SVector<f64, N>, y: &F::Point<D>) -> D {
        self.density(x, y, &SMatrix::from_element(D::zero()))
    }

    /// ∇_yV and, if asked, ∇²_yV of V(x, y) = 𝓛(x, y, 0) at the points
    /// (x_i, y_i) of `x` and `y` (equal lengths; x only read where 𝓛
    /// depends on it), into `gradients` and `hessians`, with the bits of
    /// [`jet_free_part`](Self::jet_free_part) over one first-order dual
    /// number per direction (gradients only) or a second-order one.
    /// `false` (the default): not provided, nothing written; rules then
    /// differentiate point by point. A density overrides it where its
    /// points share work (the sine-Gordon potential's trigonometry runs in
    /// vector lanes, [`Potential::batch_derivatives`](crate::spacetime::Potential::batch_derivatives)).
    fn jet_free_derivatives(
        &self,
        _x: &[SVector<f64, N>],
        _y: &[F::Point<f64>],
        _gradients: &mut [SVector<f64, M>],
        _hessians: Option<&mut [SMatrix<f64, M, M>]>,
    ) -> bool {
        false
    }
}

impl<T: SmoothDensity<F, M, N> + ?Sized, F: Fibre<M>, const M: usize, const N: usize> SmoothDensity<F, M, N> for &T {
    fn density<D: Scalar>(&self, x: &SVector<f64, N>, y: &F::Point<D>, jet: &SMatrix<D, M, N>) -> D {
        (**self).density(x, y, jet)
    }
    fn depends_on_position(&self) -> bool {
        (**self).depends_on_position()
    }
    fn diagonal_jet_metric(&self) -> Option<SVector<f64, N>> {
        (**self).diagonal_jet_metric()
    }
    fn jet_free_part<D: Scalar>(&self, x: &SVector<f64, N>, y: &F::Point<D>) -> D {
        (**self).jet_free_part(x, y)
    }
    fn jet_free_derivatives(
        &self,
        x: &[SVector<f64, N>],
        y: &[F::Point<f64>],
        gradients: &mut [SVector<f64, M>],
        hessians: Option<&mut [SMatrix<f64, M, M>]>,
    ) -> bool {
        (**self).jet_free_derivatives(x, y, gradients, hessians)
    }
}

/// Σ_k (∂𝓛/∂φ_t^k)·(∂φ^k/∂x^a): the directional derivative of 𝓛 with respect
/// to the time column of the jet (the last base coordinate) along column `a`
/// (exact, through a dual number).
pub fn time_flux<S, const M: usize, const N: usize>(
    density: &S,
    x: &SVector<f64, N>,
    y: &SVector<f64, M>,
    jet: &SMatrix<f64, M, N>,
    a: usize,
) -> f64
where
    S: SmoothDensity<Euclidean<M>, M, N>,
{
    let mut seeded = jet.map(Dual64::from);
    for k in 0..M {
        seeded[(k, N - 1)] = Dual64::new(jet[(k, N - 1)], jet[(k, a)]);
    }
    density.density(x, &y.map(Dual64::from), &seeded).eps
}

/// The energy density ℰ = Σ_k φ_t^k ∂𝓛/∂φ_t^k − 𝓛 of a density on ℝ^M with
/// time the last base coordinate.
pub fn energy_density<S, const M: usize, const N: usize>(
    density: &S,
    x: &SVector<f64, N>,
    y: &SVector<f64, M>,
    jet: &SMatrix<f64, M, N>,
) -> f64
where
    S: SmoothDensity<Euclidean<M>, M, N>,
{
    time_flux(density, x, y, jet, N - 1) - density.density(x, y, jet)
}

/// The momentum density along space axis a < N − 1:
/// 𝒫_a = −Σ_k (∂𝓛/∂φ_t^k)(∂φ^k/∂x^a) (for the wave equation −φ_t φ_{x_a},
/// positive for a wave moving towards +x^a).
pub fn momentum_density<S, const M: usize, const N: usize>(
    density: &S,
    x: &SVector<f64, N>,
    y: &SVector<f64, M>,
    jet: &SMatrix<f64, M, N>,
    a: usize,
) -> f64
where
    S: SmoothDensity<Euclidean<M>, M, N>,
{
    -time_flux(density, x, y, jet, a)
}

/// The energy density ℰ (the return value) and the momentum densities 𝒫_a
/// for a < N − 1 (into `momenta`, at most N − 1 of them) in one dual pass:
/// the time column of the jet carries, in direction a, the jet's column a,
/// so the pass gives every [`time_flux`] at once and the density itself as
/// its real part (one evaluation of 𝓛 and of its transcendental functions
/// instead of N + 1). A density with a diagonal jet metric η
/// ([`SmoothDensity::diagonal_jet_metric`]) takes the closed form
/// ℰ = η_t Σ_k φ_{kt}² − 𝓛 and 𝒫_a = −η_t Σ_k φ_{kt} φ_{ka} (t = N − 1), with
/// 𝓛 = ½ Σ_{k,a} η_a φ_{ka}² + 𝓛(x, y, 0) and no dual numbers.
pub fn energy_momentum_density<S, const M: usize, const N: usize>(
    density: &S,
    x: &SVector<f64, N>,
    y: &SVector<f64, M>,
    jet: &SMatrix<f64, M, N>,
    momenta: &mut [f64],
) -> f64
where
    S: SmoothDensity<Euclidean<M>, M, N>,
{
    if let Some(eta) = density.diagonal_jet_metric() {
        let t = N - 1;
        let (mut quadratic, mut time) = (0.0, 0.0);
        for k in 0..M {
            for a in 0..N {
                quadratic += eta[a] * jet[(k, a)] * jet[(k, a)];
            }
            time += jet[(k, t)] * jet[(k, t)];
        }
        for (a, p) in momenta.iter_mut().enumerate().take(t) {
            *p = -eta[t] * (0..M).fold(0.0, |acc, k| acc + jet[(k, t)] * jet[(k, a)]);
        }
        return eta[t] * time - (0.5 * quadratic + density.jet_free_part(x, y));
    }
    let mut seeded = jet.map(DualSVec64::<N>::from_re);
    for k in 0..M {
        let column = SVector::<f64, N>::from_fn(|a, _| jet[(k, a)]);
        seeded[(k, N - 1)] = DualSVec64::new(jet[(k, N - 1)], Derivative::some(column));
    }
    let value = density.density(x, &y.map(DualSVec64::<N>::from_re), &seeded);
    let flux = value.eps.unwrap_generic(Const::<N>, U1);
    for (a, p) in momenta.iter_mut().enumerate().take(N.saturating_sub(1)) {
        *p = -flux[a];
    }
    flux[N - 1] - value.re
}
