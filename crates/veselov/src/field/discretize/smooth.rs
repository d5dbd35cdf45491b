//! Smooth Lagrangian densities 𝓛: J¹Y → ℝ over a fibre (note 003 §2.5):
//! 𝓛(x, y, φ) with x ∈ X = ℝ^N, y a fibre point and φ ∈ ℝ^{M×N} the jet in
//! the fibre's chart at y (column a = ∂/∂x^a; for SO(3) the left-trivialised
//! body vector, e.g. Ω = (Rᵀ∂_sR)^∨ for the rod).

use nalgebra::{SMatrix, SVector};

use crate::ad::Scalar;
use crate::field::density::Density;
use crate::field::fibre::{Euclidean, Fibre};
use crate::field::potential::{NonlinearWave, Potential};
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
    /// vector lanes, [`Potential::batch_derivatives`]).
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

/// A seed 002 density 𝓛(φ, φ_t, φ_x) on ℝ^DIM seen as a [`SmoothDensity`]
/// on 1+1 space–time with coordinates x = (x, t) (space first, time last, as
/// in [`super::CfkNodes::space_time`]): jet column 0 is φ_x, column 1 is φ_t.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpaceTime<L>(pub L);

impl<L: Density<DIM> + Send + Sync, const DIM: usize> SmoothDensity<Euclidean<DIM>, DIM, 2> for SpaceTime<L> {
    fn density<D: Scalar>(&self, _x: &SVector<f64, 2>, y: &SVector<D, DIM>, jet: &SMatrix<D, DIM, 2>) -> D {
        let phi_x: SVector<D, DIM> = jet.column(0).into_owned();
        let phi_t: SVector<D, DIM> = jet.column(1).into_owned();
        self.0.density(y, &phi_t, &phi_x)
    }
}

/// Any potential gives the nonlinear-wave density on N − 1 space dimensions
/// and time (the last coordinate): 𝓛 = ½(|φ_t|² − Σ_a |φ_{x_a}|²) + N(φ)
/// (seed 002 (4.32) in more space dimensions).
impl<P: Potential<DIM> + Send + Sync, const DIM: usize, const N: usize> SmoothDensity<Euclidean<DIM>, DIM, N>
    for NonlinearWave<P>
{
    fn depends_on_position(&self) -> bool {
        false
    }
    /// η = (−1, …, −1, +1): time is the last base coordinate.
    fn diagonal_jet_metric(&self) -> Option<SVector<f64, N>> {
        Some(SVector::from_fn(|a, _| if a + 1 == N { 1.0 } else { -1.0 }))
    }
    /// The potential N(y).
    fn jet_free_part<D: Scalar>(&self, _x: &SVector<f64, N>, y: &SVector<D, DIM>) -> D {
        self.0.potential(y)
    }
    /// The potential's batched derivatives ([`Potential::batch_derivatives`]).
    fn jet_free_derivatives(
        &self,
        _x: &[SVector<f64, N>],
        y: &[SVector<f64, DIM>],
        gradients: &mut [SVector<f64, DIM>],
        hessians: Option<&mut [SMatrix<f64, DIM, DIM>]>,
    ) -> bool {
        self.0.batch_derivatives(y, gradients, hessians)
    }
    fn density<D: Scalar>(&self, _x: &SVector<f64, N>, y: &SVector<D, DIM>, jet: &SMatrix<D, DIM, N>) -> D {
        let mut kin = D::zero();
        for k in 0..DIM {
            kin += jet[(k, N - 1)] * jet[(k, N - 1)];
            for a in 0..N - 1 {
                kin -= jet[(k, a)] * jet[(k, a)];
            }
        }
        kin * 0.5 + self.0.potential(y)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::potential::{ComplexKleinGordon, SineGordon};

    /// Twenty reproducible arguments (x, y, φ) of a density.
    #[allow(clippy::type_complexity)]
    fn samples<const M: usize, const N: usize>() -> Vec<(SVector<f64, N>, SVector<f64, M>, SMatrix<f64, M, N>)> {
        (0..20)
            .map(|trial| {
                let t = trial as f64;
                (
                    SVector::from_fn(|a, _| (0.3 * t + a as f64).sin()),
                    SVector::from_fn(|k, _| 2.0 * (0.7 * t - k as f64).cos()),
                    SMatrix::from_fn(|k, a| (1.3 * t + 0.4 * k as f64 - 0.9 * a as f64).sin() * 1.7),
                )
            })
            .collect()
    }

    fn check<S: SmoothDensity<Euclidean<M>, M, N>, const M: usize, const N: usize>(density: &S) -> f64 {
        let mut worst: f64 = 0.0;
        for (x, y, jet) in samples::<M, N>() {
            let mut momenta = [0.0; N];
            let e = energy_momentum_density(density, &x, &y, &jet, &mut momenta[..N - 1]);
            let e1 = energy_density(density, &x, &y, &jet);
            worst = worst.max((e - e1).abs() / e1.abs().max(1.0));
            for (a, p) in momenta.iter().enumerate().take(N - 1) {
                let p1 = momentum_density(density, &x, &y, &jet, a);
                worst = worst.max((p - p1).abs() / p1.abs().max(1.0));
            }
        }
        worst
    }

    /// A density that does not declare its jet metric (the dual pass).
    struct Undeclared<S>(S);

    impl<S: SmoothDensity<Euclidean<M>, M, N>, const M: usize, const N: usize> SmoothDensity<Euclidean<M>, M, N>
        for Undeclared<S>
    {
        fn density<D: Scalar>(&self, x: &SVector<f64, N>, y: &SVector<D, M>, jet: &SMatrix<D, M, N>) -> D {
            self.0.density(x, y, jet)
        }
    }

    /// The one-pass energy and momenta (the dual pass, and the closed form
    /// of a declared jet metric) equal the one-flux-per-pass definitions
    /// (the same derivatives; the energy takes 𝓛 from the dual pass's real
    /// part or from the closed form's sum, which may round differently from
    /// the `f64` evaluation in the last bits).
    #[test]
    fn one_pass_energy_and_momenta_equal_the_flux_definitions() {
        let worst = [
            check::<_, 1, 3>(&NonlinearWave(SineGordon)),
            check::<_, 2, 3>(&NonlinearWave(ComplexKleinGordon { m2: 1.2, lambda: 0.7 })),
            check::<_, 2, 2>(&NonlinearWave(ComplexKleinGordon { m2: 0.4, lambda: 1.5 })),
            check::<_, 1, 3>(&Undeclared(NonlinearWave(SineGordon))),
            check::<_, 2, 3>(&Undeclared(NonlinearWave(ComplexKleinGordon { m2: 1.2, lambda: 0.7 }))),
        ];
        assert!(worst.iter().all(|w| *w <= 4.0 * f64::EPSILON), "{worst:?}");
    }

    /// The nonlinear wave's declared form holds: 𝓛(x, y, φ) equals
    /// ½ Σ η_a φ_{ka}² plus its jet-free part, and the jet-free part is the
    /// density at a zero jet (the default), on random arguments.
    fn metric_form<S: SmoothDensity<Euclidean<M>, M, N>, const M: usize, const N: usize>(density: &S) -> f64 {
        let eta = density.diagonal_jet_metric().expect("a declared metric");
        let mut worst: f64 = 0.0;
        for (x, y, jet) in samples::<M, N>() {
            let quadratic: f64 = (0..M)
                .map(|k| (0..N).map(|a| 0.5 * eta[a] * jet[(k, a)] * jet[(k, a)]).sum::<f64>())
                .sum();
            let whole = density.density(&x, &y, &jet);
            let free = density.jet_free_part(&x, &y);
            let at_zero = density.density(&x, &y, &SMatrix::zeros());
            worst = worst.max((whole - quadratic - free).abs() / whole.abs().max(1.0));
            worst = worst.max((free - at_zero).abs() / free.abs().max(1.0));
        }
        worst
    }

    #[test]
    fn nonlinear_waves_have_the_diagonal_jet_metric_they_declare() {
        let worst = [
            metric_form::<_, 1, 3>(&NonlinearWave(SineGordon)),
            metric_form::<_, 1, 2>(&NonlinearWave(SineGordon)),
            metric_form::<_, 2, 3>(&NonlinearWave(ComplexKleinGordon { m2: 1.2, lambda: 0.7 })),
            metric_form::<_, 2, 4>(&NonlinearWave(ComplexKleinGordon { m2: 0.4, lambda: 1.5 })),
        ];
        assert!(worst.iter().all(|w| *w <= 8.0 * f64::EPSILON), "{worst:?}");
        let eta = SmoothDensity::<Euclidean<1>, 1, 3>::diagonal_jet_metric(&NonlinearWave(SineGordon));
        assert_eq!(eta, Some(SVector::from([-1.0, -1.0, 1.0])));
    }
}
