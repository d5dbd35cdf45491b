//! The 1+1 densities of Marsden–Patrick–Shkoller and the nonlinear-wave
//! family as smooth densities of the field core
//! ([`crate::field::discretize::SmoothDensity`], note 003 §2.5), so that
//! the core's quadrature rules and marchers take them on any lattice.

use nalgebra::{SMatrix, SVector};

use super::density::Density;
use super::potential::{NonlinearWave, Potential};
use crate::ad::Scalar;
use crate::field::discretize::SmoothDensity;
use crate::field::fibre::Euclidean;

/// A seed 002 density 𝓛(φ, φ_t, φ_x) on ℝ^DIM seen as a [`SmoothDensity`]
/// on 1+1 space–time with coordinates x = (x, t) (space first, time last, as
/// in [`crate::field::discretize::CfkNodes::space_time`]): jet column 0 is φ_x, column 1 is φ_t.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::discretize::{energy_density, energy_momentum_density, momentum_density};
    use crate::spacetime::potential::{ComplexKleinGordon, SineGordon};

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
